#include "gi/record_emitter.h"

#include "gi/gather_stage.h"
#include "gi/gi_context.h"
#include "gi/irradiance_cache.h"
#include "kernels/random.h"
#include "kernels/sampling.h"

namespace rayproc {

RecordEmitter::RecordEmitter(const std::vector<IrradianceRecord>& records, std::size_t first,
                             std::size_t last, int rays, int correctionRays, bool stratify,
                             std::uint64_t key, IcRequest* const* slots)
    : m_records(records), m_first(first), m_last(last), m_stratify(stratify), m_key(key),
      m_slots(slots) {
    if (rays > 0) gatherStrata(rays, m_gather.theta, m_gather.phi);
    if (correctionRays > 0) gatherStrata(correctionRays, m_correction.theta, m_correction.phi);
}

bool RecordEmitter::emit(StageContext& ctx) {
    std::size_t begin = m_first + m_next.fetch_add(kRecordsPerUnit);
    if (begin >= m_last) return false;
    std::size_t end = std::min(m_last, begin + kRecordsPerUnit);
    for (std::size_t i = begin; i < end; ++i) {
        const IrradianceRecord& rec = m_records[i];
        const std::uint32_t local = std::uint32_t(i - m_first);
        Vec3 tu, tv;
        orthonormalBasis(rec.normal, tu, tv);
        // Ray r of `strata` from the record's stream `key`, or none below the geometric surface.
        auto direction = [&](const Strata& strata, std::uint64_t key, int r, Vec3& wi) {
            Vec2 u{kernels::uniform(key, 2 * std::uint32_t(r)),
                   kernels::uniform(key, 2 * std::uint32_t(r) + 1)};
            Vec3 l = kernels::cosineStratum(r / strata.phi, r % strata.phi, strata.theta,
                                            strata.phi, u, m_stratify);
            wi = normalize(tu * l.x + tv * l.y + rec.normal * l.z);
            return dot(wi, rec.geometricNormal) > 0;
        };
        const std::uint64_t key = kernels::hashCombine(m_key, std::uint64_t(i));
        // Spectral mode: the record's rays' wavelengths, spread as its prepass gather's.
        const float gatherU = kernels::uniform(kernels::hashCombine(key, 0x1a3b), 0);
        for (int r = 0; r < m_gather.count(); ++r) {
            Vec3 wi;
            if (!direction(m_gather, key, r, wi)) {
                // Below the geometric surface: dark, as in the record's own gather.
                m_slots[local]->rays.fetch_add(1, std::memory_order_relaxed);
                continue;
            }
            // Sample ~0: no stratum of the record's gradients.
            pushGatherRay(ctx.out(kGatherRay), rec.gatherOrigin, wi, local, ~0u, Vec3(1.0f),
                          kernels::hashCombine(key, 0x100000u + std::uint64_t(r)), 0,
                          kFlagGatherRecord, recordLambdaU(gatherU, r, m_gather.count()));
        }
        // Correction rays: the far end's map estimate replaced by a path (a ray below the
        // surface corrects nothing; the caller counts it all the same).
        const std::uint64_t correctionKey = kernels::hashCombine(key, 0xc0ec7);
        const float correctionU = kernels::uniform(kernels::hashCombine(correctionKey, 0x1a3b), 0);
        for (int r = 0; r < m_correction.count(); ++r) {
            Vec3 wi;
            if (!direction(m_correction, correctionKey, r, wi)) continue;
            const std::uint64_t rayKey =
                kernels::hashCombine(correctionKey, 0x100000u + std::uint64_t(r));
            pushGatherRay(ctx.out(kCorrectionRay), rec.gatherOrigin, wi, local, ~0u,
                          Vec3(1.0f), rayKey, 1, 0,
                          recordLambdaU(correctionU, r, m_correction.count()));
        }
    }
    return true;
}

} // namespace rayproc
