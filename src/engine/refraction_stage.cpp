#include "engine/refraction_stage.h"

#include "engine/material_bsdf.h"
#include "engine/path_state.h"
#include "kernels/bsdf_sampling.h"

namespace rayproc {

void RefractionStage::spawn(const RayBatch& b, const HitList& hits, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, StageId::Refraction);
    stats.stages[int(StageId::Refraction)].raysIn += std::uint64_t(hits.count);
    std::uint64_t spawned = 0;
    const ShadingPolicy& policy = m_rc.policy;
    LaneShading wl(m_rc.spectral);
    for (int k = 0; k < hits.count; ++k) {
        int i = hits.lane[k];
        const SurfaceHit& h = hits.hit[k];
        Vec3 wo = -laneDirection(b, i);
        wl.select(b.lambdaU[i]); // the surface stage marked a dispersive hit's lane
        const kernels::BsdfParams bsdf =
            bsdfAt(m_rc.scene, h.material, h, b.rngKey[i], wl.shading());
        const kernels::SmoothInterface s = kernels::smoothInterface(bsdf, wo, h.ng, h.ns);
        Vec3 w = laneThroughput(b, i);
        int depth = b.depth[i] + 1;
        int spec = b.specularDepth[i] + 1;
        std::uint8_t flags = b.flags[i];

        // Reflected part.
        Vec3 wRefl = w * s.reflectance;
        if (spec <= policy.maxDepth && continuePath(policy, depth, b.rngKey[i], 1, wRefl)) {
            spawnRay(ctx.out(RayKind::Reflection), b, i, offsetRayOrigin(h, s.g, s.reflected),
                     s.reflected, wRefl, std::uint8_t(depth), std::uint8_t(spec), flags, 1, wl.u());
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
            wTrans = w * std::max(1.0f - s.reflectance, policy.minTranslucency);
            tDepth = b.depth[i];
        } else {
            if (!s.transmits) continue;
            wt = s.transmitted;
            // Radiance scales by 1/eta^2 across the interface and back by eta^2 on leaving a
            // closed object, so the pair cancels and is left out: exact while the camera and
            // the lights are outside the glass (pbrt keeps the factor for radiance paths).
            wTrans = w * (1.0f - s.reflectance);
            if (spec > policy.maxDepth) continue;
        }
        if (s.entering) wTrans = wTrans * bsdf.color; // the tint, as sampleBsdf applies it
        if (!policy.previewGlass && !continuePath(policy, depth, b.rngKey[i], 2, wTrans)) continue;
        spawnRay(ctx.out(RayKind::Refraction), b, i, offsetRayOrigin(h, s.g, wt), wt, wTrans,
                 tDepth, std::uint8_t(spec), flags, 2, wl.u());
        ++spawned;
    }
    stats.stages[int(StageId::Refraction)].raysOut += spawned;
}

} // namespace rayproc
