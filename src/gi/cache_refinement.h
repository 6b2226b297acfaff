// Cache refinement: the irradiance cache's records keep gathering during the render, so their
// noise is not frozen into the image. A record's irradiance comes from one final gather in the
// cache's prepass (64 rays by default); every pixel that interpolates it carries that gather's
// error for the whole render, however many passes follow. Before each render pass, each record
// gets `GiSettings::icRefineRays` more gather rays (RecordEmitter -> ray processor -> the gather
// stage, exactly the prepass's gather: global map at the far ends, light samples of the sun and
// sky there), and its irradiance becomes the mean over all its rays so far:
//   E_i = pi (S_0 + S_1 + ... + S_p) / (n_0 + n_1 + ... + n_p),
// S the sums of a gather's radiance, n its rays. The records converge to the gather's exact
// answer with this photon map (the map's own bias stays; gi/correction_stage.h is about that);
// their positions, radii and gradients stay the prepass's, so lookups and the octree do not
// change. The film averages the passes, so an early pass's cruder records keep their share
// (1 / passes) of the image.
//
// Correction (`GiSettings::icCorrectionRays`, off by default): the map's bias at the records,
// taken out with the passes. Each record also traces that many RayKind::Correction rays per
// pass (cosine strata from its gather origin); at a ray's far end the correction stage
// subtracts the map's estimate exactly as a gather reads it and traces a path in its place
// (path mode's vertex: one light sample, one BSDF sample, then gi's PathStage, as deep as the
// photons go; the sun's and the sky's direct light, which the gather samples itself, left out
// of both). What the paths find goes to the record's pixel of the pass's film. A control
// variate: with C the sums of a record's corrections over its m correction rays so far,
//   E_i = max(0, pi (S_0 + ... + S_p) / (n_0 + ... + n_p) + pi C / m),
// whose expectation is the exact gather's irradiance, not the map's, once the clamp no longer
// acts: the map's bias leaves the records as m grows, at the price of path tracing's noise in
// C (docs/irradiance-cache.md, "Correcting the records"). Surfaces the map is not read at
// (mirrors, glass: the gather looks through them) are not corrected.
//
// Consumes: the cache after its prepass, the pass index. Produces: the records' irradiance for
// the pass (IrradianceCache::setIrradiance), between passes.
// Deterministic: each ray's direction is a function of (seed, pass, record, ray), the sums are
// fixed point (IcRequest) and are folded in record order. Under MPI each rank gathers for a
// contiguous share of the records and the sums are added over the ranks.
#pragma once

#include "engine/stats.h"
#include "gi/gi_context.h"
#include "modes/render_job.h"

#include <cstdint>
#include <vector>

namespace rayproc {

class Cluster;
class EmbreeScene;
class IrradianceCache;
struct LightSet;
struct Scene;

class CacheRefinement {
public:
    CacheRefinement(const Scene& scene, const EmbreeScene& accel, const LightSet& lights,
                    GiData& gi, IrradianceCache& cache, const EngineSettings& engine,
                    const Cluster& cluster, Stats& stats);
    // Gathers pass `pass`'s rays for every record and updates the cache. A collective under
    // MPI (every rank calls it for every pass).
    void beginPass(int pass);
    std::uint64_t raysGathered() const { return m_rays; }
    // Correction rays traced so far, over all records (those below a record's surface too).
    std::uint64_t correctionRays() const { return m_correctionRays; }

private:
    const Scene& m_scene;
    const EmbreeScene& m_accel;
    const LightSet& m_lights;
    GiData& m_gi;
    IrradianceCache& m_cache;
    EngineSettings m_engine;
    const Cluster& m_cluster;
    Stats& m_stats;
    // Per record: the radiance sums of all its gathers (per channel) and their ray count.
    std::vector<double> m_sums;
    std::vector<std::uint64_t> m_counts;
    std::uint64_t m_rays = 0;
    // Per record: the sums of its corrections' radiance (per channel); the corrections each
    // record has had (the same for all).
    std::vector<double> m_corrections;
    std::uint64_t m_correctionCount = 0, m_correctionRays = 0;
};

} // namespace rayproc
