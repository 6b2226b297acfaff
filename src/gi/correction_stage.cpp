#include "gi/correction_stage.h"

#include "engine/material_bsdf.h"
#include "engine/path_stage.h"
#include "engine/path_state.h"
#include "engine/pipeline.h"
#include "engine/shadow_stage.h"
#include "engine/sample_numbers.h"
#include "gi/gather_stage.h"
#include "gi/gi_context.h"
#include "gi/photon_map.h"
#include "kernels/bsdf_sampling.h"
#include "kernels/pbrt_bsdfs.h"
#include "kernels/sampling.h"

#include <algorithm>

namespace rayproc {

namespace {
// Random dimensions: the ray from x; at the vertex that replaces the map, its light sample (3)
// and its BSDF sample (3) and Russian roulette.
enum CorrectionDim : std::uint32_t { kDimRay = 60, kDimLight = 62, kDimBsdf = 65, kDimRr = 68 };

// The shared sample generator without Sobol points: several correction paths of one record
// and pass share a pixel and a sample index, so each takes its lane's own stream.
Vec2 uniform2(const RayBatch& b, int i, std::uint32_t dim) {
    return SampleNumbers(b, i, false, 0).get2D(dim);
}
} // namespace

CorrectionStage::CorrectionStage(const RenderContext& rc, const GiData& gi,
                                 const GatherStage& gather)
    : m_policy(rc.policy),
      m_rc{rc.scene, rc.accel, rc.lights, m_policy, rc.film, rc.seed, nullptr, rc.spectral},
      m_gi(gi), m_gather(gather), m_paths(m_rc, kPathOutputs) {
    m_policy.maxDepth = std::max(1, gi.settings.maxPhotonDepth - 1);
}

void CorrectionStage::spawn(const RayBatch& b, const HitList& hits, StageContext& ctx) {
    const GiData& gi = m_gi;
    if (!gi.settings.mapCorrection || m_rc.policy.handlersOnly ||
        gi.settings.debugView != GiDebugView::None || !gi.global || gi.global->size() == 0)
        return;
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, kCorrectionStageId);
    std::uint64_t spawned = 0;
    LaneShading wl(m_rc.spectral);
    for (int k = 0; k < hits.count; ++k) {
        int i = hits.lane[k];
        const SurfaceHit& h = hits.hit[k];
        wl.select(b.lambdaU[i]);
        if (!visiblePoint(b.flags[i])) {
            // Past a glossy bounce: the gather stage adds the map's estimate of all the light
            // reflected here (GatherStage::spawn, its BSDF stream 0).
            spawned += replaceMap(b, i, h, false, 0, ctx);
            continue;
        }
        // A first diffuse hit (from the camera through specular surfaces only), whose indirect
        // light is the cache's or a final gather's: one ray like a gather ray.
        if (b.depth[i] + 1 > m_rc.policy.maxDepth) continue;
        Vec3 wo = -laneDirection(b, i);
        Vec3 ng, ns;
        facingNormals(h, wo, ng, ns);
        Vec3 wi = kernels::toWorld(kernels::cosineHemisphere(uniform2(b, i, kDimRay)), ns);
        if (dot(wi, ng) <= 0) continue; // below the surface: dark, as in the gathers
        Vec3 albedo = kernels::lambertianAlbedo(
            bsdfAt(m_rc.scene, h.material, h, 0, wl.shading()), wo, h.ng, h.ns);
        Vec3 weight = laneThroughput(b, i) * albedo; // cosine sampling: f cos / pdf = albedo
        if (isBlack(weight)) continue;
        spawnRay(ctx.out(kCorrectionRay), b, i, offsetRayOrigin(h, ng, wi), wi, weight,
                 std::uint8_t(b.depth[i] + 1), 0, 0, 11);
        ++spawned;
    }
    stats.stages[int(kCorrectionStageId)].raysOut += spawned;
}

void CorrectionStage::retrace(RayBatch& b, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    StageTimer timer(stats, kCorrectionStageId);
    stats.stages[int(kCorrectionStageId)].raysIn += std::uint64_t(b.count);
    std::uint64_t spawned = 0;
    for (int i = 0; i < b.count; ++i) {
        if (!b.hit(i)) continue; // the sky seen from x is light sampled at x: nothing to correct
        Vec3 o{b.ox[i], b.oy[i], b.oz[i]}, d = laneDirection(b, i);
        SurfaceHit h =
            m_rc.accel.surface(b.instId[i], b.geomId[i], b.primId[i], b.u[i], b.v[i], o, d, b.t[i]);
        resolveShading(m_rc.scene, h, -d);
        // A dispersive material (a coat's) keeps the hero wavelength alone, as the gather
        // stage's does at the same hit.
        if (m_rc.spectral && dispersiveMaterial(m_rc.scene.materials[h.material]))
            b.lambdaU[i] = SpectralRender::terminatedU(b.lambdaU[i]);
        // The gather's far end: its BSDF stream (GatherStage::retrace).
        spawned += replaceMap(b, i, h, true, kernels::hashCombine(b.rngKey[i], 43), ctx);
    }
    stats.stages[int(kCorrectionStageId)].raysOut += spawned;
}

std::uint64_t CorrectionStage::replaceMap(const RayBatch& b, int i, const SurfaceHit& h,
                                          bool gatherEnd, std::uint64_t bsdfKey,
                                          StageContext& ctx) const {
    const GiData& gi = m_gi;
    const ShadingPolicy& policy = m_rc.policy;
    ThreadStats& stats = *ctx.stats;
    const MaterialType type = m_rc.scene.materials[h.material].type;
    const MaterialClass cls = materialClass(m_rc.scene.materials, h.material);
    LaneShading wl(m_rc.spectral); // spectral mode: the path's wavelengths
    wl.select(b.lambdaU[i]);
    kernels::BsdfParams bsdf = bsdfAt(m_rc.scene, h.material, h, bsdfKey, wl.shading());
    const Vec3 wo = -laneDirection(b, i), w = laneThroughput(b, i);
    Vec3 ng, ns;
    facingNormals(h, wo, ng, ns);
    const bool diffuse = type == MaterialType::Diffuse || type == MaterialType::CoatedDiffuse;
    const bool glossy = cls == MaterialClass::Glossy && !kernels::hasTransmission(bsdf);
    // A glossy surface is read only at a gather's far end; a diffuse transmitter's light through
    // it, mirrors and glass are not the map's.
    if (!(diffuse || (glossy && gatherEnd))) return 0;
    // The sun's and the sky's direct light: the gather's light samples at a diffuse far end.
    const bool leaveDirect = diffuse && gatherEnd && gi.globalIndirect != nullptr;
    // Minus the map's estimate, as gi takes it; the vertex's lobe: a Lambertian one of the
    // albedo gi weighs the map with (a coated surface's base; its coat is traced by gi itself).
    ++giCounter(stats, kGiGlobalLookups);
    Vec3 mapRadiance;
    if (diffuse) {
        Vec3 albedo = kernels::lambertianAlbedo(bsdf, wo, h.ng, h.ns);
        const PhotonMap* map = leaveDirect ? gi.globalIndirect : gi.global;
        mapRadiance = albedo * kInvPi * m_gather.lightAt(m_gather.mapIrradiance(map, h.p, ns),
                                                         wl.lane());
        bsdf = kernels::BsdfParams{};
        bsdf.kind = kernels::BsdfKind::Diffuse;
        bsdf.color = albedo;
    } else {
        mapRadiance = m_gather.glossyRadiance(bsdf, h, wo, ns, &wl.lane());
    }
    const Vec3 removed = -(w * mapRadiance);
    m_rc.film.add(b.pixel[i], m_rc.spectral ? m_rc.spectral->toFilm(removed, wl.lane()) : removed,
                  stats);

    std::uint64_t spawned = 0;
    if (sampleOneLight(m_rc.lights, b, i, h, bsdf, wo, w, uniform2(b, i, kDimLight),
                       kernels::uniform(b.rngKey[i], kDimLight + 2), leaveDirect,
                       policy.skyCompensation, ctx.outShadow(RayKind::Shadow), wl.shading()))
        ++spawned;
    // The bounce, as path mode takes it (its depth limit and Russian roulette).
    const std::uint8_t flags = leaveDirect ? kFlagSkipEnvironment : 0;
    if (spawnBounce(policy, b, i, h, bsdf, wo, w, uniform2(b, i, kDimBsdf),
                    kernels::uniform(b.rngKey[i], kDimBsdf + 2),
                    kernels::uniform(b.rngKey[i], kDimRr), flags, kPathOutputs, 12,
                    ctx) != Bounce::None)
        ++spawned;
    return spawned;
}

void addCorrectionStages(Pipeline& pipeline, CorrectionStage& correction, ShadowStage& shadow) {
    pipeline.stage("correction", {kCorrectionQueue}, correction)
        .stage("correction path", {kCorrectionPathQueue}, correction.pathStage());
    if (!pipeline.routes(RayKind::Shadow))
        pipeline.stage("shadow", {engineRoute(RayKind::Shadow)}, shadow);
}

} // namespace rayproc
