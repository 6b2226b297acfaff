#include "gi/record_emitter.h"

#include "gi/gather_stage.h"
#include "gi/gi_context.h"
#include "gi/irradiance_cache.h"
#include "kernels/random.h"
#include "kernels/sampling.h"

namespace rayproc {

RecordEmitter::RecordEmitter(const std::vector<IrradianceRecord>& records, std::size_t first,
                             std::size_t last, int rays, bool stratify, std::uint64_t key,
                             IcRequest* const* slots)
    : m_records(records), m_first(first), m_last(last), m_rays(std::max(rays, 1)),
      m_stratify(stratify), m_key(key), m_slots(slots) {
    gatherStrata(m_rays, m_thetaCount, m_phiCount);
    m_rays = m_thetaCount * m_phiCount;
}

bool RecordEmitter::emit(StageContext& ctx) {
    std::size_t begin = m_first + m_next.fetch_add(kRecordsPerUnit);
    if (begin >= m_last) return false;
    std::size_t end = std::min(m_last, begin + kRecordsPerUnit);
    for (std::size_t i = begin; i < end; ++i) {
        const IrradianceRecord& rec = m_records[i];
        IcRequest& slot = *m_slots[i - m_first];
        Vec3 tu, tv;
        orthonormalBasis(rec.normal, tu, tv);
        const std::uint64_t key = kernels::hashCombine(m_key, std::uint64_t(i));
        for (int r = 0; r < m_rays; ++r) {
            Vec2 u{kernels::uniform(key, 2 * std::uint32_t(r)),
                   kernels::uniform(key, 2 * std::uint32_t(r) + 1)};
            Vec3 l = kernels::cosineStratum(r / m_phiCount, r % m_phiCount, m_thetaCount,
                                            m_phiCount, u, m_stratify);
            Vec3 wi = normalize(tu * l.x + tv * l.y + rec.normal * l.z);
            if (dot(wi, rec.geometricNormal) <= 0) {
                // Below the geometric surface: dark, as in the record's own gather.
                slot.rays.fetch_add(1, std::memory_order_relaxed);
                continue;
            }
            // Sample ~0: no stratum of the record's gradients.
            pushGatherRay(ctx.out(RayKind::Gather), rec.gatherOrigin, wi,
                          std::uint32_t(i - m_first), ~0u, Vec3(1.0f),
                          kernels::hashCombine(key, 0x100000u + std::uint64_t(r)), 0,
                          kFlagGatherRecord);
        }
    }
    return true;
}

} // namespace rayproc
