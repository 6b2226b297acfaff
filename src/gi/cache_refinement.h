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
// Two halves: the film puts even and odd passes into two half buffers, whose difference is the
// relMSE estimate (--target-relmse, --error-log). Each record keeps its refinement's and its
// corrections' sums per pass parity, and a pass reads only those of its own parity (and the
// prepass's gather, which both share): so the two halves see independent record noise and the
// estimate measures it, instead of the records' error being common to both halves and hidden
// (docs/irradiance-cache.md, "Two halves"). The image is the mean of the halves, so a record's
// noise in it is that of all its rays, as before.
//
// Correction (`GiSettings::icCorrectionRays`, 4 by default): the map's bias at the records,
// taken out with the passes. Each record also traces that many kCorrectionRay rays per
// pass (cosine strata from its gather origin); at a ray's far end the correction stage
// subtracts the map's estimate exactly as a gather reads it and traces a path in its place
// (path mode's vertex: one light sample, one BSDF sample, then gi's PathStage, as deep as the
// photons go; the sun's and the sky's direct light, which the gather samples itself, left out
// of both). What the paths find goes to the record's pixel of the pass's film. A control
// variate: with C the sums of a record's corrections over its m correction rays so far,
//   E_i = max(0, pi (S_0 + ... + S_p) / (n_0 + ... + n_p) + w pi C / m),
// whose expectation is the exact gather's irradiance, not the map's, once w = 1 and the clamp
// no longer acts. w is one weight for the whole cache (shrinkageWeight below, on the records'
// mean corrections and their variances across passes): where the map is right the corrections
// are only noise and w stays near 0; where it is biased, or once the corrections' noise has
// fallen, w goes to 1 (docs/irradiance-cache.md, "Correcting the records"). One weight for all
// records selects none by its own noise (a per-record weight did, and biased the image).
// Before the weight, each record's correction is averaged over its nearest records, as many as
// Stein's unbiased risk estimate says (gi/correction_smoothing.h; GiSettings::icSmoothing): wide
// while the corrections are noisy, fading to the record's own as the passes add paths.
// Surfaces the map is not read at (mirrors, glass: the gather looks through them) are not
// corrected.
//
// Consumes: the cache after its prepass, the pass index. Produces: the records' irradiance for
// the pass (IrradianceCache::setIrradiance), between passes.
// Deterministic: each ray's direction is a function of (seed, pass, record, ray), the sums are
// fixed point (IcRequest) and are folded in record order. Under MPI each rank gathers for a
// contiguous share of the records and the sums are added over the ranks.
#pragma once

#include "engine/engine_settings.h"
#include "engine/stats.h"
#include "gi/correction_smoothing.h"
#include "gi/gi_context.h"
#include "gi/gi_pipeline.h"

#include <cstdint>
#include <vector>

namespace rayproc {

class Cluster;
class PhaseLog;
class EmbreeScene;
class IrradianceCache;
struct LightSet;
struct Scene;

// The common weight w in [0, 1] for estimates b_i of quantities beta_i, given each estimate's
// variance v_i: positive-part James-Stein towards zero with one weight for all,
//   w = max(0, 1 - sum(v_i) / sum(b_i^2)),
// which estimates the w minimising sum((w b_i - beta_i)^2), sum(beta^2) / (sum(beta^2) +
// sum(v)), because E[b_i^2] = beta_i^2 + v_i. 0 when every b_i is 0.
double shrinkageWeight(const std::vector<double>& means, const std::vector<double>& variances);

class CacheRefinement {
public:
    CacheRefinement(const Scene& scene, const EmbreeScene& accel, const LightSet& lights,
                    const GiData& gi, IrradianceCache& cache, const EngineSettings& engine,
                    const Cluster& cluster, PhaseLog* phases, Stats& stats);
    // Gathers pass `pass`'s rays for every record and updates the cache. A collective under
    // MPI (every rank calls it for every pass).
    void beginPass(int pass);
    std::uint64_t raysGathered() const { return m_rays; }
    // Correction rays traced so far, over all records (those below a record's surface too).
    std::uint64_t correctionRays() const {
        return (m_correctionCounts[0] + m_correctionCounts[1]) * m_counts[0].size();
    }
    // The weight w the records' corrections are applied with in the current pass (0 to 1).
    double correctionWeight() const { return m_correctionWeight; }
    // The records each correction is averaged over in the current pass (1: its own only;
    // gi/correction_smoothing.h).
    int correctionSmoothing() const { return m_smoothing; }

private:
    const Scene& m_scene;
    const EmbreeScene& m_accel;
    const LightSet& m_lights;
    const GiData& m_gi;
    IrradianceCache& m_cache;
    EngineSettings m_engine;
    const Cluster& m_cluster;
    PhaseLog* m_phases;
    Stats& m_stats;
    // Per pass parity, per record: the radiance sums of its gathers (per channel; the
    // prepass's in both) and their ray count.
    std::vector<double> m_sums[2];
    std::vector<std::uint64_t> m_counts[2];
    std::uint64_t m_rays = 0;
    // Per pass parity, per record: the sums of its corrections' radiance (per channel); the
    // corrections each record has had in passes of that parity (the same for all records).
    std::vector<double> m_corrections[2];
    std::uint64_t m_correctionCounts[2] = {0, 0};
    // Per record: the sum over passes of its per-pass mean correction's luminance, squared;
    // the passes that corrected; the weight the corrections are applied with.
    std::vector<double> m_correctionSquares;
    std::uint64_t m_correctionPasses = 0;
    double m_correctionWeight = 0.0;
    // Smoothing of the corrections over neighbouring records (GiSettings::icSmoothing): the
    // lists, the size chosen for this pass and, when it is above 1, the smoothed corrections'
    // sums of the pass's parity (per channel).
    RecordNeighbours m_neighbours;
    int m_smoothing = 1;
    std::vector<double> m_smoothed;

    // One pass's sums over every rank, in record order: per record its gathers' radiance (3
    // channels, fixed point in units of radianceScale) and ray count; with corrections, their
    // radiance (3 channels) from correctionsPerRecord rays each.
    struct PassSums {
        std::vector<std::uint64_t> gathers;
        double radianceScale = 1;
        std::vector<double> corrections;
        int correctionsPerRecord = 1;
    };
    // Traces pass `pass`'s gather (and correction) rays for this rank's share of the records.
    PassSums tracePass(int pass, bool correcting);
    // Adds the pass's corrections to those of its parity and re-estimates the weight.
    void foldCorrections(const PassSums& sums, int parity);
    // The records' irradiance for the pass: their gathers so far plus the weighted corrections.
    void updateRecords(const PassSums& sums, int parity, bool correcting);
    // Chooses the smoothing and the weight for the corrections folded in so far (both
    // parities'), and smooths those of `parity`.
    void estimateCorrection(int parity);
};

} // namespace rayproc
