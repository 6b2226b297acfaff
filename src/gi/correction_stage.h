// Correction stage: gi's per-pass correction of the global photon map's bias, a control variate.
// gi reads the global map where its final gathers land (the diffuse light of the surfaces a
// first diffuse hit x sees, through the irradiance cache) and at diffuse hits past a glossy
// bounce. The map's k-nearest estimates are biased (dark beside furniture finer than their discs:
// docs/photon-map.md), and that bias stays in the image however many passes are added. So every
// render pass (GiSettings::mapCorrection), at each place the map is read for the film, or one
// cosine-weighted ray away from each first diffuse hit x (weight throughput x albedo: the
// Lambertian lobe's cosine sampling; the ray's far end y stands for the gather's far ends):
//  - the film gets minus the map's estimate there, exactly as gi takes it (a diffuse surface's or
//    a coated one's base: albedo / pi x irradiance; an opaque glossy one: the map's radiance
//    estimate with the BSDF);
//  - and a vertex of path mode's tracer in its place: one light sample, then one sample of the
//    same lobe (kCorrectionPathRay rays, gi's PathStage from there on). Where a gather's
//    own light samples took the sun's and the sky's direct light at y (GiSettings::gatherDirect,
//    diffuse far ends), that light is the same on both sides and left out of both: the vertex
//    samples area lights only and an escape from it counts nothing.
// A correction's expectation is the difference between the traced and the map's radiance, so the
// image converges to what the gathers would see with an exact map: the map's bias goes, the
// cache's interpolation error stays. Surfaces the map is not read at (mirrors, glass) and rays
// that miss correct nothing.
#pragma once

#include "engine/hit_list.h"
#include "engine/path_stage.h"
#include "engine/render_context.h"
#include "engine/stage.h"
#include "engine/surface_stage.h"
#include "gi/gi_pipeline.h"

namespace rayproc {

class GatherStage;
class Pipeline;
class ShadowStage;
struct GiData;

class CorrectionStage : public RetraceStage, public DiffuseHitHandler {
public:
    // `rc`: the render's (or the cache refinement's) context. The correction paths run in a
    // copy of it whose policy's depth limit follows the photons' (GiSettings::maxPhotonDepth D):
    // they stand for the light of the global map's photons whose estimate they replace, which
    // hold up to D - 1 intersections (gi/photon_pass.cpp), so a correction path's vertices
    // take light samples up to depth D - 1 and a path through it has at most D scattering
    // events from the visible point on, as pbrt-v4's SPPM at maxdepth D. gi's own maxDepth
    // limits its specular chains (at that depth, 8, the inside-out furnace's albedo-0.8
    // channel came out 11% dark).
    CorrectionStage(const RenderContext& rc, const GiData& gi, const GatherStage& gather);
    // At the hits the gather stage takes in a render pass: one correction ray from each first
    // diffuse hit, the map replaced in place at those past a glossy bounce.
    void spawn(const RayBatch& parent, const HitList& hits, StageContext& ctx) override;
    void retrace(RayBatch& batch, StageContext& ctx) override;
    // The stage for kCorrectionPathRay rays: gi's PathStage, tracing the paths on.
    RetraceStage& pathStage() { return m_paths; }

private:
    // The kinds of the correction paths' rays.
    static constexpr PathStage::Outputs kPathOutputs{kCorrectionPathRay,
                                                     kCorrectionPathRay, RayKind::Shadow};
    // The map's estimate at hit h of lane i of b replaced by a path vertex (above); `gatherEnd`:
    // a gather's far end, else a hit past a glossy bounce; `bsdfKey` the BSDF's stream gi used
    // there. Returns the rays spawned.
    std::uint64_t replaceMap(const RayBatch& b, int i, const SurfaceHit& h, bool gatherEnd,
                             std::uint64_t bsdfKey, StageContext& ctx) const;
    ShadingPolicy m_policy; // rc's, with the photons' depth limit
    RenderContext m_rc;     // rc with m_policy
    const GiData& m_gi;
    const GatherStage& m_gather;
    PathStage m_paths;
};

// Appends the correction stages to `pipeline`: correction rays to `correction`, the paths
// traced on from them to its path stage, and those paths' light samples to `shadow` unless
// the pipeline's shadow rays have a stage already.
void addCorrectionStages(Pipeline& pipeline, CorrectionStage& correction, ShadowStage& shadow);

} // namespace rayproc
