#include "gi/cache_refinement.h"

#include "cluster/cluster.h"
#include "engine/cancel.h"
#include "engine/film.h"
#include "engine/phases.h"
#include "engine/pipeline.h"
#include "engine/shadow_stage.h"
#include "gi/correction_stage.h"
#include "gi/gather_stage.h"
#include "gi/irradiance_cache.h"
#include "gi/photon_pass.h"
#include "gi/record_emitter.h"
#include "kernels/random.h"

#include <algorithm>

namespace rayproc {

CacheRefinement::CacheRefinement(const Scene& scene, const EmbreeScene& accel,
                                 const LightSet& lights, const GiData& gi, IrradianceCache& cache,
                                 const EngineSettings& engine, const Cluster& cluster,
                                 PhaseLog* phases, Stats& stats)
    : m_scene(scene), m_accel(accel), m_lights(lights), m_gi(gi), m_cache(cache), m_engine(engine),
      m_cluster(cluster), m_phases(phases), m_stats(stats) {
    // The prepass's gathers: S_0 = E_0 n_0 / pi.
    // Both parities start from it.
    const std::vector<IrradianceRecord>& records = cache.records();
    m_sums[0].resize(3 * records.size());
    m_counts[0].resize(records.size());
    for (std::size_t i = 0; i < records.size(); ++i) {
        const IrradianceRecord& r = records[i];
        const double n = double(std::max(r.gatherRays, 1));
        for (int c = 0; c < 3; ++c)
            m_sums[0][3 * i + std::size_t(c)] = double(r.irradiance[c]) * n / kPi;
        m_counts[0][i] = std::uint64_t(std::max(r.gatherRays, 1));
    }
    m_sums[1] = m_sums[0];
    m_counts[1] = m_counts[0];
    for (std::vector<double>& c : m_corrections) c.assign(3 * records.size(), 0.0);
    m_correctionSquares.assign(records.size(), 0.0);
    if (gi.settings.icCorrectionRays > 0 && gi.settings.icSmoothing)
        m_neighbours = RecordNeighbours(records);
}

double shrinkageWeight(const std::vector<double>& means, const std::vector<double>& variances) {
    double squares = 0.0, noise = 0.0;
    for (std::size_t i = 0; i < means.size(); ++i) {
        squares += means[i] * means[i];
        noise += variances[i];
    }
    if (!(squares > 0.0)) return 0.0;
    return std::clamp(1.0 - noise / squares, 0.0, 1.0);
}

namespace {
double luminanceAt(const std::vector<double>& rgb, std::size_t i) {
    return 0.2126 * rgb[3 * i] + 0.7152 * rgb[3 * i + 1] + 0.0722 * rgb[3 * i + 2];
}
} // namespace

void CacheRefinement::estimateCorrection(int parity) {
    // Each record's mean correction per ray and that mean's variance, from the spread of its
    // per-pass means: P passes give P - 1 degrees of freedom, so none before the second pass.
    // Both parities' passes count: the weight and the smoothing are those of the image, whose
    // records are the mean of the two halves'.
    const std::uint64_t passes = m_correctionPasses;
    m_smoothing = 1;
    m_correctionWeight = 0.0;
    if (passes < 2) return;
    const double count = double(m_correctionCounts[0] + m_correctionCounts[1]);
    std::vector<double> means(m_correctionSquares.size()), variances(means.size());
    for (std::size_t i = 0; i < means.size(); ++i) {
        const double b =
            (luminanceAt(m_corrections[0], i) + luminanceAt(m_corrections[1], i)) / count;
        const double spread =
            std::max(0.0, m_correctionSquares[i] - double(passes) * b * b) / double(passes - 1);
        means[i] = b;
        variances[i] = spread / double(passes);
    }
    if (m_neighbours.size() != means.size()) {
        m_correctionWeight = shrinkageWeight(means, variances);
        return;
    }
    // Smoothed over neighbouring records, as many as the risk estimate says; the weight is then
    // the smoothed corrections' (their variance falls with the records averaged). Tried, not
    // kept: smoothing fractions of each record's gathered light instead, with the risk in
    // relative terms (docs/irradiance-cache.md).
    std::vector<double> smoothMeans, smoothVariances;
    m_smoothing = m_neighbours.chooseSize(means, variances, smoothMeans);
    m_neighbours.smoothVariance(variances, m_smoothing, smoothVariances);
    m_correctionWeight = shrinkageWeight(smoothMeans, smoothVariances);
    if (m_smoothing > 1) m_neighbours.smooth(m_corrections[parity], 3, m_smoothing, m_smoothed);
}

void CacheRefinement::beginPass(int pass) {
    const GiSettings& s = m_gi.settings;
    const std::vector<IrradianceRecord>& records = m_cache.records();
    const bool correcting = s.icCorrectionRays > 0 && m_gi.global && m_gi.global->size() > 0;
    if ((s.icRefineRays <= 0 && !correcting) || records.empty() || stopped(m_cluster)) return;
    // The film's half buffer this pass goes to (render_job.cpp: pass % 2).
    const int parity = pass % 2;
    PassSums sums = tracePass(pass, correcting);
    if (correcting) foldCorrections(sums, parity);
    updateRecords(sums, parity, correcting);
}

CacheRefinement::PassSums CacheRefinement::tracePass(int pass, bool correcting) {
    const GiSettings& s = m_gi.settings;
    const std::vector<IrradianceRecord>& records = m_cache.records();
    std::uint64_t first = 0, last = 0;
    shareOf(records.size(), m_cluster.rank(), m_cluster.size(), first, last);

    // This rank's records, one request slot each, claimed in record order.
    IcRequests requests;
    const int filmExponent = Film::exponentFor(m_lights.radianceScale(m_scene.worldBounds()));
    requests.setRadianceScale(IcRequest::radianceScale(filmExponent));
    requests.beginLevel(std::size_t(last - first));
    std::vector<IcRequest*> slots(std::size_t(last - first));
    for (IcRequest*& slot : slots) {
        std::uint32_t index = 0;
        slot = requests.claim(index);
    }

    // Gather rays add to a record's slot; correction rays and their paths to the record's
    // pixel of this film (pixel i - first).
    Film film(correcting ? int(std::max<std::uint64_t>(last - first, 1)) : 1, 1, filmExponent);
    ShadingPolicy policy;
    policy.maxDepth = s.maxDepth;
    policy.handlersOnly = true;
    policy.stratify = m_engine.stratification;
    policy.rouletteEnabled = s.roulette;
    RenderContext rc{m_scene, m_accel, m_lights, policy, film, m_engine.seed};
    rc.spectral = m_gi.spectral;
    GatherStage gather(rc, m_gi, &requests); // the records' gathers add to their slots
    CorrectionStage correction(rc, m_gi, gather);
    ShadowStage shadow(rc);
    // record emitter -> queue -> intersect -> gather [-> correction, correction path, shadow]
    Pipeline pipeline("cache refinement", "record", m_accel.root(), m_engine.packetWidth,
                      m_stats, m_engine.threads);
    pipeline.stage("gather", {kGatherQueue, kGatherShadowQueue}, gather)
        .timedAs(m_phases, "cache_refinement");
    if (correcting) addCorrectionStages(pipeline, correction, shadow);
    const std::uint64_t key =
        kernels::hashCombine(kernels::hashCombine(m_engine.seed, 0x1c7e), std::uint64_t(pass));
    RecordEmitter emitter(records, std::size_t(first), std::size_t(last),
                          std::max(s.icRefineRays, 0), correcting ? s.icCorrectionRays : 0,
                          m_engine.stratification, key, slots.data());
    // Not interruptible halfway: the pass's sums are all or nothing (a cancel stops the render
    // after its current pass anyway).
    pipeline.run(emitter, [] { return false; });
    film.commitPass();

    // The pass's sums, every rank's, in record order.
    PassSums out;
    out.radianceScale = requests.radianceScale();
    out.gathers.assign(4 * records.size(), 0);
    for (std::size_t i = std::size_t(first); i < std::size_t(last); ++i) {
        const IcRequest& r = *slots[i - std::size_t(first)];
        for (int c = 0; c < 3; ++c)
            out.gathers[4 * i + std::size_t(c)] = std::uint64_t(r.radiance[c].load());
        out.gathers[4 * i + 3] = std::uint64_t(r.rays.load());
    }
    m_cluster.sumAll(out.gathers); // two's complement: the signed sums add exactly
    // The corrections: one rank's values and exact zeros from the others.
    if (correcting) {
        out.corrections.assign(3 * records.size(), 0.0);
        const std::vector<double>& mine = film.sums();
        for (std::size_t j = 0; j < 3 * std::size_t(last - first); ++j)
            out.corrections[3 * std::size_t(first) + j] = mine[j];
        m_cluster.sumAll(out.corrections);
        out.correctionsPerRecord = std::max(emitter.correctionRaysPerRecord(), 1);
    }
    return out;
}

void CacheRefinement::foldCorrections(const PassSums& sums, int parity) {
    const int perPass = sums.correctionsPerRecord;
    m_correctionCounts[parity] += std::uint64_t(perPass);
    ++m_correctionPasses;
    std::vector<double>& own = m_corrections[parity];
    for (std::size_t i = 0; i < m_correctionSquares.size(); ++i) {
        const double c = luminanceAt(sums.corrections, i) / double(perPass);
        m_correctionSquares[i] += c * c;
        for (std::size_t j = 3 * i; j < 3 * i + 3; ++j) own[j] += sums.corrections[j];
    }
    estimateCorrection(parity);
}

void CacheRefinement::updateRecords(const PassSums& sums, int parity, bool correcting) {
    const std::size_t records = m_cache.records().size();
    // The corrections as applied: smoothed over neighbours, or each record's own; this
    // parity's.
    const std::vector<double>& applied = m_smoothing > 1 ? m_smoothed : m_corrections[parity];
    const double correctionCount = double(std::max<std::uint64_t>(m_correctionCounts[parity], 1));
    std::vector<double>& gathered = m_sums[parity];
    std::vector<std::uint64_t>& counts = m_counts[parity];
    for (std::size_t i = 0; i < records; ++i) {
        const std::uint64_t rays = sums.gathers[4 * i + 3];
        counts[i] += rays;
        m_rays += rays;
        Vec3 e;
        for (int c = 0; c < 3; ++c) {
            double& sum = gathered[3 * i + std::size_t(c)];
            sum += double(std::int64_t(sums.gathers[4 * i + std::size_t(c)])) / sums.radianceScale;
            double irradiance = kPi * sum / double(counts[i]);
            if (correcting)
                irradiance += m_correctionWeight * kPi * applied[3 * i + std::size_t(c)] /
                              correctionCount;
            // Clamped at zero, the correction too: while it is noisy that biases the record up
            // (the sunlit room of the gather-direct test: +1% at 16 spp), but an unclamped one
            // made veach-mis's dark plates noisy (docs/irradiance-cache.md); once the record
            // has converged the clamp no longer acts.
            e[c] = float(std::max(0.0, irradiance));
        }
        m_cache.setIrradiance(i, e);
    }
}

} // namespace rayproc
