#include "modes/render_job.h"

#include "engine/adaptive_sampler.h"
#include "engine/camera_emitter.h"
#include "engine/cancel.h"
#include "engine/film_sensor.h"
#include "engine/noise_breakdown.h"
#include "engine/path_stage.h"
#include "engine/phases.h"
#include "engine/pipeline.h"
#include "engine/progress.h"
#include "engine/reflection_stage.h"
#include "engine/refraction_stage.h"
#include "engine/shadow_stage.h"
#include "engine/spectral_render.h"
#include "engine/surface_stage.h"
#include "engine/mode_stages.h"

#include "cluster/cluster.h"
#include "image/metrics.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <sstream>

namespace rayproc {

namespace {
constexpr int kMinTargetPasses = 8;
// Adaptive sampling without a target: no pixel takes more than this times the mean asked.
constexpr int kAdaptiveMaxFactor = 16;

// What the ranks of a distributed render decide together after each pass.
enum PassDecision : std::uint32_t {
    kDecideTimeUp = 2,      // rank 0's clock passed the time limit
    kDecideProgressive = 4, // rank 0 writes the progressive image now
    kDecideStopped = 8,     // some rank's RenderControl::stop said so: all stop
    // interruptBits() from bit 4 on: some rank was interrupted (all stop), and by which signal.
    kDecideSignalShift = 4,
    kDecideInterrupted = kInterruptBit << kDecideSignalShift,
};

using Clock = std::chrono::steady_clock;

// The engine's retrace stages of a render.
struct EngineStageSet {
    ShadowStage shadow;
    ReflectionStage reflection;
    RefractionStage refraction;
    SurfaceStage surface;
    PathStage path;
    explicit EngineStageSet(const RenderContext& rc)
        : shadow(rc), reflection(rc), refraction(rc), surface(rc, shadow, reflection, refraction),
          path(rc) {}

    // The render's pipeline, in order:
    //   camera emitter -> queue -> intersect
    //     -> surface (or path) [camera, reflection, refraction]
    //     -> shadow [shadow: occlusion]
    //     -> the mode's own stages (gi: gather [gather, gather-shadow], correction, ...)
    // Kinds of rays the scene analysis rules out get no stage: one would end the run with
    // an error that names it.
    void build(Pipeline& pipeline, const RenderContext& rc, RadianceStage radiance,
               ModeStages* modeStages) {
        std::vector<RayRoute> radianceQueues{engineRoute(RayKind::Camera),
                                             engineRoute(RayKind::Reflection)};
        if (rc.policy.refractionStage) radianceQueues.push_back(engineRoute(RayKind::Refraction));
        if (radiance == RadianceStage::Path) pipeline.stage("path", radianceQueues, path);
        else pipeline.stage("surface", radianceQueues, surface);
        if (rc.policy.shadowStage) pipeline.stage("shadow", {engineRoute(RayKind::Shadow)}, shadow);
        if (modeStages) modeStages->attach({rc, pipeline, surface, shadow});
    }
};

// The convergence log (RenderControl::errorLogPath), on rank 0. A write that fails (a full
// disk) ends the log, not the render: the image is still saved; `failure` says why.
class ErrorLog {
public:
    ErrorLog(const std::string& path, std::string& failure) : m_path(path), m_failure(failure) {}
    void open() {
        m_file.reset(std::fopen(m_path.c_str(), "w"));
        if (!m_file) throw std::runtime_error("cannot write the error log " + m_path);
        if (std::fprintf(m_file.get(), "spp,seconds,relmse,rmse,relmse_estimate\n") < 0 ||
            std::fflush(m_file.get()) != 0)
            failed();
    }
    bool isOpen() const { return bool(m_file); }
    void row(double spp, double seconds, const ImageMetrics& m, double estimate) {
        if (m_file && (std::fprintf(m_file.get(), "%.9g,%.6f,%.9g,%.9g,%.9g\n", spp, seconds,
                                    m.relmse, m.rmse, estimate) < 0 ||
                       std::fflush(m_file.get()) != 0))
            failed();
    }
    void close() {
        if (m_file && std::fclose(m_file.release()) != 0 && m_failure.empty()) failed();
    }

private:
    void failed() {
        int err = errno;
        m_failure = "cannot write the error log " + m_path + ": " + std::strerror(err) +
                    "; its rows stop there";
        if (m_file) std::fclose(m_file.release());
    }
    const std::string& m_path;
    std::string& m_failure;
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> m_file{nullptr, &std::fclose};
};

// One render job: its film, pipeline and log, and the passes with their decisions.
class RenderJob {
public:
    RenderJob(const std::string& label, const Scene& scene, const EmbreeScene& accel,
              const LightSet& lights, const ShadingPolicy& policy, int spp,
              const EngineSettings& engine, const RenderControl& control,
              RadianceStage radiance, ModeStages* modeStages,
              const std::function<void(int pass, int samples)>& beforePass);
    RenderResult run();

private:
    void planPasses();
    // Seconds of the mode's clock at t (the error log's measuring excluded).
    double secondsAt(Clock::time_point t) const {
        return std::chrono::duration<double>(t.time_since_epoch() -
                                             Clock::duration(m_startTicks.load()))
            .count();
    }
    double fraction() const;
    std::uint64_t raysSoFar() const { return std::uint64_t(m_stats.merged().raysTraced); }
    bool stopRequested() const { return m_control.stop && m_control.stop(); }
    Image wholeImage();
    // This rank's film so far, passes in flight included, through the sensor: the watcher's.
    Image imageSoFar() const {
        Image img = m_film.resolveInProgress();
        applySensor(m_sensor, img);
        return img;
    }
    // One pass; false when the render ends after it.
    bool renderPass(int pass);
    void tracePass(int pass, int first, int count);
    bool adaptiveStep(int pass);
    void logPass(Clock::time_point now);
    std::uint32_t decide(int pass, Clock::time_point now);
    void finish();

    // The film, the stages and the log before the first pass: one thread.
    PhaseTimer m_setupPhase;
    const std::string& m_label;
    const EngineSettings& m_engine;
    const RenderControl& m_control;
    const int m_spp;
    const std::function<void(int, int)>& m_beforePass;
    // The mode's clock: its start, moved on by the time the error log spends measuring; it
    // decides the time limit, and the progress monitor's thread reads it.
    std::atomic<Clock::rep> m_startTicks;
    const Cluster& m_cluster;
    Film m_film;
    // The film's sensor, applied to every image the job hands out: the result, the progressive
    // and watched images, the error log's, and (through the luminance it weighs) the noise layers.
    SensorMatrix m_sensor;
    RenderContext m_rc;
    std::optional<NoiseBreakdown> m_noise;
    std::optional<SpectralRender> m_spectral; // spectral mode's conversions
    // The pipeline: one emitter, one intersection handler, the retrace stages by ray kind.
    Stats m_stats;
    Pipeline m_pipeline;
    CameraEmitter m_camera;
    EngineStageSet m_stages;
    RenderResult m_result;
    ErrorLog m_errorLog;
    bool m_logging = false; // the log's image merge, on every rank
    // Passes of a few samples per pixel: the film commits between passes, which is where
    // progressive output is written and where a cancel leaves a consistent image.
    int m_passSpp = 1;
    int m_passes = 0;
    std::optional<AdaptiveSampler> m_adaptive;
    // The samples per pixel of each pass of the next pair, once adaptive sampling decides.
    int m_adaptiveCount = 0;
    double m_meanSpp = 0;     // samples per pixel taken so far, the mean over the image
    double m_activeShare = 1; // the share of the pixels the current pair samples
    std::atomic<int> m_passIndex{0};
    std::atomic<std::uint64_t> m_unitsBefore{0};
    // Whether the camera's count is of a pass not yet in unitsBefore: between passes (gi's
    // refinement runs there) the last pass counted twice without it.
    std::atomic<bool> m_passInFlight{false};
    std::uint64_t m_totalUnits = 0;
    std::atomic<double> m_targetFraction{0.0};
    Clock::time_point m_lastProgressive;
    bool m_stop = false;
    bool m_stopped = false; // by the caller's stop, which leaves the interrupt alone
};

RenderJob::RenderJob(const std::string& label, const Scene& scene, const EmbreeScene& accel,
                     const LightSet& lights, const ShadingPolicy& policy, int spp,
                     const EngineSettings& engine, const RenderControl& control,
                     RadianceStage radiance, ModeStages* modeStages,
                     const std::function<void(int pass, int samples)>& beforePass)
    : m_setupPhase(control.phases, "render_setup"), m_label(label), m_engine(engine),
      m_control(control), m_spp(spp),
      m_beforePass(beforePass),
      m_startTicks((control.workStart ? *control.workStart : Clock::now())
                       .time_since_epoch()
                       .count()),
      m_cluster(control.clusterOrAlone()),
      m_film(scene.camera.width, scene.camera.height,
             Film::exponentFor(lights.radianceScale(scene.worldBounds()))),
      m_sensor(sensorMatrix(scene.sensor, spectral::colorSpace(spectral::ColorSpaceId::Srgb))),
      m_rc{scene, accel, lights, policy, m_film, engine.seed},
      m_pipeline("render", "camera", accel.root(), engine.packetWidth, m_stats, engine.threads),
      m_camera(m_rc), m_stages(m_rc),
      m_errorLog(control.errorLogPath, m_result.errorLogFailure) {
    if (control.noiseBreakdown) {
        m_noise.emplace(m_film.width(), m_film.height(), m_film.exponent(), m_sensor);
        m_rc.noise = &*m_noise;
    }
    if (engine.spectral) {
        // Every stage reads the lane's wavelengths from its rays (a mode's own too: gi's
        // gathers and corrections).
        m_spectral.emplace(scene, lights);
        m_rc.spectral = &*m_spectral;
    }
    m_camera.setShare(m_cluster.rank(), m_cluster.size());
    m_stages.build(m_pipeline, m_rc, radiance, modeStages);
    m_pipeline.timedAs(control.phases, "render_passes");
    // Every stage for --stats in pipeline order: the engine's, then the mode's.
    m_result.stats.pipeline = enginePipeline();
    if (modeStages)
        for (const StageLabel& stage : modeStages->labels())
            m_result.stats.pipeline.push_back(stage);
    // Every rank takes part in the log's image merge; rank 0 writes it.
    m_logging = control.reference &&
                (!control.errorLogPath.empty() || control.onPassError);
    if (m_logging && m_cluster.root() && !control.errorLogPath.empty()) m_errorLog.open();
    planPasses();
}

// Under a time limit or an error target, passes of 1 spp keep the budget closely; the noise
// breakdown takes each pass's sums for one sample's values.
void RenderJob::planPasses() {
    const EngineSettings& engine = m_engine;
    const RenderControl& control = m_control;
    const int spp = m_spp;
    const bool stopEarly = control.timeLimitSeconds > 0 || control.targetRelMse > 0;
    m_passSpp = stopEarly || m_noise ? 1 : std::clamp(spp / 32, 1, 16);
    // Half buffers (alternate passes) give the relMSE estimate the target, the log and adaptive
    // sampling use.
    if (control.targetRelMse > 0 || m_logging || engine.adaptiveSampling)
        m_film.enableHalfBuffers();
    // Adaptive sampling: `spp` is the mean over the pixels (or the cap under a target).
    if (engine.adaptiveSampling) {
        AdaptiveSampler::Settings as;
        as.minSpp = std::min(engine.adaptiveMinSpp, spp);
        as.targetRelMse = control.targetRelMse;
        as.meanSpp = spp;
        as.maxSpp = control.targetRelMse > 0 ? spp : kAdaptiveMaxFactor * spp;
        as.passSpp = m_passSpp;
        as.maxPassSpp = m_noise ? 1 : 16 * m_passSpp;
        m_adaptive.emplace(m_film.width(), m_film.height(), as);
    }
    m_passes = m_adaptive ? std::numeric_limits<int>::max() : (spp + m_passSpp - 1) / m_passSpp;
    // This rank's share: progress is rank 0's, which the others keep pace with.
    m_totalUnits = std::uint64_t(std::max(m_camera.tilesInShare(), 1)) * std::uint64_t(spp);
}

// Under a time limit the share of the budget spent, when it is ahead of the samples' (a
// render asked for 100,000 spp and 90 s said 0.1% done and an ETA of hours).
double RenderJob::fraction() const {
    const std::uint64_t current = m_passInFlight.load() ? m_camera.unitsEmitted() : 0;
    double f = double(m_unitsBefore.load() + current) / double(m_totalUnits);
    if (m_control.timeLimitSeconds > 0)
        f = std::max(f, std::min(1.0, secondsAt(Clock::now()) / m_control.timeLimitSeconds));
    return m_control.targetRelMse > 0 ? std::max(f, m_targetFraction.load()) : f;
}

// The image of the whole job (every rank's tiles), on rank 0; a collective.
Image RenderJob::wholeImage() {
    Image img;
    if (!m_cluster.distributed()) {
        img = m_film.resolve();
    } else {
        std::vector<double> sums = m_film.sums();
        std::vector<std::uint64_t> samples = m_film.sampleCounts();
        m_cluster.sumToRoot(sums);
        m_cluster.sumToRoot(samples);
        img = Film::resolve(m_film.width(), m_film.height(), sums, samples);
    }
    applySensor(m_sensor, img);
    return img;
}

RenderResult RenderJob::run() {
    Progress progress(m_label, m_engine.quiet, [this] { return fraction(); },
                      [this] { return raysSoFar(); });
    // The watcher stops watching before the film goes away, whatever ends the render.
    struct WatchScope {
        const RenderControl::Watcher* w;
        ~WatchScope() {
            if (w && w->end) w->end();
        }
    } watch{m_control.watcher};
    if (m_control.watcher && m_control.watcher->begin)
        m_control.watcher->begin([this] { return imageSoFar(); }, [this] { return fraction(); },
                                 [this] { return raysSoFar(); });
    m_lastProgressive = Clock::now();
    m_stop = m_cluster.distributed() ? agreeInterrupted(m_cluster) : interruptRequested();
    if (!m_cluster.distributed() && stopRequested()) m_stop = m_stopped = true;
    m_setupPhase.stop();
    for (int pass = 0; pass < m_passes && !m_stop; ++pass)
        if (!renderPass(pass)) break;
    PhaseTimer resolvePhase(m_control.phases, "film_resolve");
    m_result.cancelled = interruptRequested() || m_stopped;
    progress.finish(!m_result.cancelled);
    m_errorLog.close();
    finish();
    return std::move(m_result);
}

// The pass's hook (gi's), its processor run and the film's commit.
void RenderJob::tracePass(int pass, int first, int count) {
    if (m_beforePass) {
        // gi's caustic maps and cache refinement time their own phases; the rest is here.
        PhaseTimer hookPhase(m_control.phases, "pass_hooks");
        m_beforePass(pass, count);
    }
    m_camera.beginPass(first, count);
    m_passInFlight = true;
    m_pipeline.run(m_camera, [&] { return interruptRequested() || stopRequested(); });
    m_unitsBefore += std::min<std::uint64_t>(m_camera.unitsEmitted(), m_camera.unitsPerPass());
    m_passInFlight = false;
    {
        PhaseTimer commitPhase(m_control.phases, "film_commit", PhaseKind::Parallel);
        m_film.commitPass(pass % 2);
    }
    if (m_noise) m_noise->commitPass();
    if (m_film.hasHalfBuffers()) {
        std::vector<double> parts = m_film.relMseParts();
        m_cluster.sumAll(parts);
        m_result.relMseEstimate = Film::relMseFromParts(parts);
    }
}

// Adaptive sampling decides between pairs of passes (one into each half), once every pixel
// has its first samples; whether the budget is spent.
bool RenderJob::adaptiveStep(int pass) {
    if (!m_adaptive || pass % 2 != 1 || m_meanSpp < m_adaptive->settings().minSpp) return false;
    AdaptiveSampler::Decision d = m_adaptive->update(m_film, [&](std::vector<double>& v) {
        m_cluster.sumAll(v);
    });
    m_meanSpp = d.meanSpp;
    m_activeShare = d.pixels > 0 ? double(d.activePixels) / double(d.pixels) : 0;
    m_adaptiveCount = d.passSamples;
    m_camera.setMask(&m_adaptive->activeMask());
    return d.done;
}

// The error log's row and the caller's; the log's clock stops while the error is measured.
void RenderJob::logPass(Clock::time_point now) {
    double seconds = secondsAt(now);
    Image whole = wholeImage();
    if (m_cluster.root() && (m_errorLog.isOpen() || m_control.onPassError)) {
        ImageMetrics m = compareImages(whole, *m_control.reference);
        m_errorLog.row(m_meanSpp, seconds, m, m_result.relMseEstimate);
        if (m_control.onPassError)
            m_control.onPassError({m_result.samplesDone, seconds, m.relmse, m.rmse,
                                  m_result.relMseEstimate, raysSoFar()});
    }
    m_startTicks += (Clock::now() - now).count();
}

// Rank 0's clock and progressive schedule rule; an interrupt anywhere stops every rank.
std::uint32_t RenderJob::decide(int pass, Clock::time_point now) {
    std::uint32_t decision = interruptBits() << kDecideSignalShift;
    if (stopRequested()) decision |= kDecideStopped;
    if (m_cluster.root() && m_control.timeLimitSeconds > 0 && pass + 1 < m_passes &&
        secondsAt(Clock::now()) >= m_control.timeLimitSeconds)
        decision |= kDecideTimeUp;
    if (m_cluster.root() && m_control.onProgress && pass + 1 < m_passes &&
        std::chrono::duration<double>(now - m_lastProgressive).count() >=
            m_control.progressiveSeconds)
        decision |= kDecideProgressive;
    if (m_cluster.distributed()) decision = m_cluster.orAll(decision);
    return decision;
}

bool RenderJob::renderPass(int pass) {
    // What a pass does besides its hook, its processor run and the film's commit: the
    // estimates, the log, the decisions; on this thread.
    PhaseTimer betweenPhase(m_control.phases, "between_passes");
    int first = m_adaptiveCount > 0 ? 0 : pass * m_passSpp;
    int count = m_adaptiveCount > 0 ? m_adaptiveCount : std::min(m_passSpp, m_spp - first);
    tracePass(pass, first, count);
    m_passIndex = pass + 1;
    ++m_result.passesDone;
    m_meanSpp = m_adaptiveCount > 0 ? m_meanSpp + double(count) * m_activeShare : first + count;
    m_result.samplesDone = int(std::lround(m_meanSpp));
    // Without adaptive sampling the passes end the loop.
    const bool budgetSpent = adaptiveStep(pass);
    auto now = Clock::now();
    if (m_logging) logPass(now);
    if (m_film.hasHalfBuffers() && std::isfinite(m_result.relMseEstimate) &&
        m_result.relMseEstimate > 0)
        // The variance part falls as 1/spp: the share of the work done is target/estimate.
        m_targetFraction = std::min(1.0, m_control.targetRelMse / m_result.relMseEstimate);
    const std::uint32_t decision = decide(pass, now);
    if (decision & kDecideInterrupted) {
        adoptInterrupt(decision >> kDecideSignalShift); // and the signal some rank received
        m_stop = true;
    }
    if (decision & kDecideStopped) m_stop = m_stopped = true;
    // At least kMinTargetPasses passes: with one or two samples per half the estimate is
    // itself too noisy to stop on (a 3-spp render estimated 0.044 measured 0.066).
    if (m_control.targetRelMse > 0 && pass + 1 >= kMinTargetPasses &&
        m_result.relMseEstimate <= m_control.targetRelMse) {
        m_result.targetReached = true;
        return false;
    }
    if (decision & kDecideTimeUp) {
        m_result.timeLimitReached = true;
        return false;
    }
    if (budgetSpent) return false;
    if (decision & kDecideProgressive) {
        Image whole = wholeImage();
        if (m_control.onProgress && m_cluster.root()) m_control.onProgress(whole);
        m_lastProgressive = now;
    }
    return true;
}

// The whole job's film on rank 0 (each pixel is one rank's, the others add exact zeros), the
// noise layers and the statistics.
void RenderJob::finish() {
    std::vector<double> sums = m_film.sums();
    std::vector<std::uint64_t> samples = m_film.sampleCounts();
    m_cluster.sumToRoot(sums);
    m_cluster.sumToRoot(samples);
    m_result.image = Film::resolve(m_film.width(), m_film.height(), sums, samples);
    applySensor(m_sensor, m_result.image);
    if (m_noise) {
        std::vector<std::vector<double>> moments = m_noise->moments();
        for (auto& m : moments) m_cluster.sumToRoot(m);
        m_result.layers = NoiseBreakdown::layers(m_film.width(), m_film.height(), moments, samples);
    }
    m_result.filmLimit = m_film.fixedLimit();
    m_result.stats.totals = m_stats.merged();
    sumToRoot(m_cluster, m_result.stats.totals);
    m_result.stats.wallSeconds = secondsAt(Clock::now());
    m_result.stats.peakMemoryBytes = peakResidentBytes();
    m_result.stats.batchesAllocated = m_pipeline.batchesAllocated();
    m_result.stats.pipelines = m_stats.pipelineRuns(m_result.stats.totals);
    m_result.stats.pixelsWithoutSamples =
        std::size_t(std::count(samples.begin(), samples.end(), 0));
}

} // namespace

RenderResult runRenderJob(const std::string& label, const Scene& scene, const EmbreeScene& accel,
                          const LightSet& lights, const ShadingPolicy& policy, int spp,
                          const EngineSettings& engine, const RenderControl& control,
                          RadianceStage radiance, ModeStages* modeStages,
                          const std::function<void(int pass, int samples)>& beforePass) {
    RenderJob job(label, scene, accel, lights, policy, spp, engine, control, radiance,
                  modeStages, beforePass);
    return job.run();
}

} // namespace rayproc
