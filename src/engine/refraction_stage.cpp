#include "engine/refraction_stage.h"

#include "engine/path_state.h"
#include "kernels/bsdf.h"

namespace rayproc {

void RefractionStage::spawn(const RayBatch& b, const HitList& hits, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, StageId::Refraction);
    stats.stages[int(StageId::Refraction)].raysIn += std::uint64_t(hits.count);
    std::uint64_t spawned = 0;
    const ShadingPolicy& policy = m_rc.policy;
    for (int k = 0; k < hits.count; ++k) {
        int i = hits.lane[k];
        const SurfaceHit& h = hits.hit[k];
        const Material& mat = m_rc.scene.materials[h.material];
        Vec3 wo = -laneDirection(b, i);
        // The front side of a closed dielectric is its outside.
        bool entering = dot(wo, h.ng) > 0;
        Vec3 ng = entering ? h.ng : -h.ng;
        Vec3 ns = entering ? h.ns : -h.ns;
        float eta = entering ? mat.ior : 1.0f / mat.ior;
        Vec3 w = laneThroughput(b, i);
        float fr = kernels::fresnelDielectric(dot(wo, ns), eta);
        int depth = b.depth[i] + 1;
        int spec = b.specularDepth[i] + 1;
        std::uint8_t flags = b.flags[i];

        // Reflected part.
        Vec3 wr = kernels::reflect(wo, ns);
        if (dot(wr, ng) <= 0) wr = kernels::reflect(wo, ng);
        Vec3 wRefl = w * fr;
        if (spec <= policy.maxDepth && continuePath(policy, depth, b.rngKey[i], 1, wRefl)) {
            spawnRay(ctx.out(RayKind::Reflection), b, i, offsetRayOrigin(h, ng, wr),
                     wr, wRefl, std::uint8_t(depth), std::uint8_t(spec), flags, 1);
            ++spawned;
        }

        // Transmitted part.
        Vec3 wt;
        Vec3 wTrans;
        std::uint8_t tDepth = std::uint8_t(depth);
        if (policy.previewGlass) {
            // No bending, no depth cost; layers of glass are limited instead.
            if (b.specularDepth[i] >= policy.maxGlassLayers) continue;
            wt = -wo;
            wTrans = w * std::max(1.0f - fr, policy.minTranslucency);
            tDepth = b.depth[i];
        } else {
            if (!kernels::refract(wo, ns, eta, wt) || dot(wt, ng) >= 0) continue;
            // Radiance scales by 1/eta^2 across the interface and back by eta^2 on leaving a
            // closed object, so the pair cancels and is left out: exact while the camera and
            // the lights are outside the glass (pbrt keeps the factor for radiance paths).
            wTrans = w * (1.0f - fr);
            if (spec > policy.maxDepth) continue;
        }
        if (entering)
            wTrans = wTrans * (m_rc.spectral ? m_rc.spectral->materialColor(
                                                   h.material, mat.color,
                                                   m_rc.spectral->lane(b.lambdaU[i]))
                                             : mat.color);
        if (!policy.previewGlass && !continuePath(policy, depth, b.rngKey[i], 2, wTrans)) continue;
        spawnRay(ctx.out(RayKind::Refraction), b, i, offsetRayOrigin(h, ng, wt),
                 wt, wTrans, tDepth, std::uint8_t(spec), flags, 2);
        ++spawned;
    }
    stats.stages[int(StageId::Refraction)].raysOut += spawned;
}

} // namespace rayproc
