// Path stage: the retrace stage of path mode, an unbiased path tracer on the same queue and
// intersection handler as the other modes. At each hit of a camera or bounce ray it
//  - adds the emission it lands on (or the sky it escapes to), weighted by multiple importance
//    sampling against light sampling (Veach's power heuristic) unless the ray came off a
//    delta lobe or the camera;
//  - at non-delta surfaces samples one light (LightSampler's choice among the lights and the sky)
//    and emits a shadow ray carrying the MIS-weighted contribution (next-event estimation);
//  - samples the BSDF for the next ray, with Russian roulette after `rrStartDepth` bounces;
//    past the last vertex (depth == maxDepth) only a non-delta sample goes on, flagged
//    kFlagEmissionOnly: it adds its MIS share of the emission or sky it finds, nothing else.
// The shadow stage's retrace adds unoccluded contributions to the film.
// gi mode runs one too, for its correction paths (gi/correction_stage.h): there its bounces are
// rays of gi's correction-path kind (Outputs), and an escaping ray flagged kFlagSkipEnvironment
// adds no sky.
#pragma once

#include "engine/material_bsdf.h"
#include "engine/render_context.h"
#include "engine/stage.h"
#include "kernels/bsdf_params.h"

namespace rayproc {

// Next-event estimation at a path vertex, lane i of b at hit h (throughput w, BSDF bsdf, wo
// towards the previous vertex): one light or the sky chosen by LightSet::sampler at h.p (`up`)
// and sampled (`u`), MIS-weighted against the BSDF by the power heuristic (both pdfs with the
// choice's probability); an occlusion ray into `out` carries the
// unoccluded contribution. `areaLightsOnly`: a delta light or the sky chosen adds nothing (gi's
// correction paths leave their direct light to the gather). `compensated`: an image sky by
// its excess over its mean (ShadingPolicy::skyCompensation; the escaped BSDF rays' MIS weights
// must use the same density). With `spectral`, the light's emission at the lane's wavelengths.
// Whether a ray was spawned.
bool sampleOneLight(const LightSet& lights, const RayBatch& b, int i, const SurfaceHit& h,
                    const kernels::BsdfParams& bsdf, const Vec3& wo, const Vec3& w, Vec2 u,
                    float up, bool areaLightsOnly, bool compensated, ShadowBatch& out,
                    const SpectralShading* spectral = nullptr);

class PathStage : public RetraceStage {
public:
    // The kinds of the rays it spawns: bounces (reflected, transmitted) and light samples.
    struct Outputs {
        RayKind reflected = RayKind::Reflection, transmitted = RayKind::Refraction;
        RayKind shadow = RayKind::Shadow;
    };
    // Path mode's own paths: one per pixel sample, whose numbers are Owen-scrambled Sobol points
    // over the pixel's samples at every depth (with stratification on).
    explicit PathStage(const RenderContext& rc) : m_rc(rc), m_lowDiscrepancy(true) {}
    // Paths that are not one per pixel sample (gi's correction paths: several per record and
    // pass): independent numbers of each ray's own stream.
    PathStage(const RenderContext& rc, Outputs outputs) : m_rc(rc), m_outputs(outputs) {}
    void retrace(RayBatch& batch, StageContext& ctx) override;

private:
    const RenderContext& m_rc;
    Outputs m_outputs;
    bool m_lowDiscrepancy = false;
};

// The path's next ray at a vertex, lane i of b at hit h (throughput w, BSDF bsdf, wo towards the
// previous vertex): one BSDF sample (`u`, `uc`); path mode's depth limit (past maxDepth only a
// non-delta sample goes on, flagged kFlagEmissionOnly) and Russian roulette after rrStartDepth
// (`ur`); its prevPdf and prevCos for the MIS weight of the light it finds. `flags` are added to
// the ray's; it goes to `outputs`' reflected or transmitted kind.
enum class Bounce { None, Reflected, Transmitted };
Bounce spawnBounce(const ShadingPolicy& policy, const RayBatch& b, int i, const SurfaceHit& h,
                   const kernels::BsdfParams& bsdf, const Vec3& wo, const Vec3& w, Vec2 u,
                   float uc, float ur, std::uint8_t flags, const PathStage::Outputs& outputs,
                   std::uint32_t branch, StageContext& ctx);

} // namespace rayproc
