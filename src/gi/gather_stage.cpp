#include "gi/gather_stage.h"

#include "engine/path_state.h"
#include "gi/gi_context.h"
#include "gi/irradiance_cache.h"
#include "gi/photon_map.h"
#include "kernels/sampling.h"

#include <cmath>

namespace rayproc {

Vec3 GatherStage::globalIrradiance(const Vec3& p, const Vec3& n) const {
    const GiData& gi = *m_rc.gi;
    if (!gi.global || gi.global->size() == 0) return Vec3(0.0f);
    if (gi.settings.precomputedIrradiance && gi.global->hasPrecomputedIrradiance())
        return gi.global->irradianceFast(p, n, gi.settings.globalK, gi.globalRadius);
    return gi.global->irradiance(p, n, gi.settings.globalK, gi.globalRadius);
}

void GatherStage::spawn(const RayBatch& b, const HitList& hits, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, StageId::Gather);
    const GiData& gi = *m_rc.gi;
    const GiSettings& s = gi.settings;
    std::uint64_t spawned = 0;
    for (int k = 0; k < hits.count; ++k) {
        int i = hits.lane[k];
        const SurfaceHit& h = hits.hit[k];
        const Material& mat = m_rc.scene.materials[h.material];
        Vec3 wo = -laneDirection(b, i);
        Vec3 ng, ns;
        facingNormals(h, wo, ng, ns);
        Vec3 w = laneThroughput(b, i);
        Vec3 reflect = w * mat.color * kInvPi; // Lambertian: L = albedo / pi * E
        bool firstDiffuse = (b.flags[i] & kFlagCountEmission) != 0;

        if (!firstDiffuse) {
            ++stats.globalLookups;
            m_rc.film.add(b.pixel[i], reflect * globalIrradiance(h.p, ns), stats);
            continue;
        }
        bool prepass = gi.requests != nullptr;
        if (!prepass && s.caustics && gi.caustic && gi.caustic->size() > 0 &&
            (s.debugView == GiDebugView::None || s.debugView == GiDebugView::Caustics)) {
            ++stats.causticLookups;
            Vec3 e = gi.caustic->irradiance(h.p, ns, s.causticK, gi.causticRadius);
            m_rc.film.add(b.pixel[i], reflect * e, stats);
        }
        if (s.debugView == GiDebugView::Caustics) continue;
        if (gi.cache) {
            ++stats.cacheLookups;
            IrradianceCache::LookupResult r;
            if (gi.cache->lookup(h.p, ns, r)) {
                ++stats.cacheHits;
                if (!prepass) m_rc.film.add(b.pixel[i], reflect * r.irradiance, stats);
                continue;
            }
        }
        // A new final gather: for a cache record in the prepass, into the film otherwise.
        std::uint32_t target = b.pixel[i];
        std::uint8_t flags = 0;
        Vec3 weight = w * mat.color / float(s.gatherRays); // cosine sampling: f cos / pdf = albedo
        if (prepass) {
            std::uint32_t slot = gi.requests->used.fetch_add(1);
            if (slot >= gi.requests->slots.size()) continue; // more than the pass can hold
            IcRequest& rq = *gi.requests->slots[slot];
            rq.key = (std::uint64_t(b.pixel[i]) << 32) ^ (b.rngKey[i] & 0xffffffffu);
            rq.position = h.p;
            rq.normal = ns;
            target = slot;
            flags = kFlagGatherRecord;
            weight = Vec3(1.0f);
        }
        std::uint64_t key = kernels::hashCombine(b.rngKey[i], 0x6a7e);
        Vec3 origin = offsetRayOrigin(h, ng, ns);
        for (int r = 0; r < s.gatherRays; ++r) {
            Vec2 u = kernels::stratified2D(std::uint32_t(r), std::uint32_t(s.gatherRays), key);
            Vec3 wi = kernels::toWorld(kernels::cosineHemisphere(u), ns);
            if (dot(wi, ng) <= 0) continue;
            RayBatch& out = ctx.out(RayKind::Gather);
            int j = out.push(origin.x, origin.y, origin.z, wi.x, wi.y, wi.z, 0.0f, kInfinity);
            out.pixel[j] = target;
            out.sample[j] = b.sample[i];
            out.wr[j] = weight.x; out.wg[j] = weight.y; out.wb[j] = weight.z;
            out.rngKey[j] = kernels::hashCombine(key, std::uint64_t(r));
            out.depth[j] = b.depth[i];
            out.specularDepth[j] = 0;
            out.flags[j] = flags;
            out.prevPdf[j] = 0;
            out.prevCos[j] = 0;
            ++spawned;
        }
    }
    stats.stages[int(StageId::Gather)].raysOut += spawned;
}

void GatherStage::retrace(RayBatch& b, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, StageId::Gather);
    stats.stages[int(StageId::Gather)].raysIn += std::uint64_t(b.count);
    const GiData& gi = *m_rc.gi;
    for (int i = 0; i < b.count; ++i) {
        Vec3 radiance(0.0f);
        float distance = kInfinity;
        if (b.hit(i)) {
            Vec3 o{b.ox[i], b.oy[i], b.oz[i]}, d = laneDirection(b, i);
            SurfaceHit h = m_rc.accel.surface(b.instId[i], b.geomId[i], b.primId[i], b.u[i], b.v[i], o, d, b.t[i]);
            distance = b.t[i];
            const Material& mat = m_rc.scene.materials[h.material];
            // Emitters are light sampled at the gather's origin; specular surfaces reflect
            // what the caustic map and the direct light already account for.
            if (mat.type == MaterialType::Diffuse || mat.type == MaterialType::Glossy) {
                Vec3 ng, ns;
                facingNormals(h, -d, ng, ns);
                ++stats.globalLookups;
                radiance = mat.color * kInvPi * globalIrradiance(h.p, ns);
            }
        }
        if (b.flags[i] & kFlagGatherRecord) {
            IcRequest& rq = *gi.requests->slots[b.pixel[i]];
            for (int c = 0; c < 3; ++c)
                rq.radiance[c].fetch_add(std::llround(double(radiance[c]) * IcRequests::kScale),
                                         std::memory_order_relaxed);
            if (std::isfinite(distance) && distance > 0)
                rq.inverseDistance.fetch_add(std::llround(IcRequests::kScale / double(distance)),
                                             std::memory_order_relaxed);
            rq.rays.fetch_add(1, std::memory_order_relaxed);
        } else {
            m_rc.film.add(b.pixel[i], laneThroughput(b, i) * radiance, stats);
        }
    }
}

} // namespace rayproc
