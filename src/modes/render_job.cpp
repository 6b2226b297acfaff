#include "modes/render_job.h"

#include "engine/adaptive_sampler.h"
#include "engine/camera_emitter.h"
#include "engine/cancel.h"
#include "engine/intersect.h"
#include "engine/noise_breakdown.h"
#include "engine/path_stage.h"
#include "engine/phases.h"
#include "engine/processor.h"
#include "engine/progress.h"
#include "engine/reflection_stage.h"
#include "engine/refraction_stage.h"
#include "engine/shadow_stage.h"
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
    kDecideStopped = 8,     // some rank's EngineSettings::stop said so: all stop
    // interruptBits() from bit 4 on: some rank was interrupted (all stop), and by which signal.
    kDecideSignalShift = 4,
    kDecideInterrupted = kInterruptBit << kDecideSignalShift,
};
} // namespace

RenderResult runRenderJob(const std::string& label, const Scene& scene, const EmbreeScene& accel,
                          const LightSet& lights, const ShadingPolicy& policy, int spp,
                          const EngineSettings& engine, RadianceStage radiance,
                          ModeStages* modeStages,
                          const std::function<void(int pass, int samples)>& beforePass) {
    // The film, the stages and the log before the first pass: one thread.
    PhaseTimer setupPhase(engine.phases, "render_setup");
    // The mode's clock: seconds from the start of its work, less the time the error log has
    // spent measuring; it decides the time limit, and the progress monitor's thread reads it.
    using Clock = std::chrono::steady_clock;
    std::atomic<Clock::rep> startTicks{
        (engine.workStart ? *engine.workStart : Clock::now()).time_since_epoch().count()};
    auto secondsAt = [&startTicks](Clock::time_point t) {
        return std::chrono::duration<double>(t.time_since_epoch() -
                                             Clock::duration(startTicks.load()))
            .count();
    };
    static const Cluster alone;
    const Cluster& cluster = engine.cluster ? *engine.cluster : alone;
    Film film(scene.camera.width, scene.camera.height,
              Film::exponentFor(lights.radianceScale(scene.worldBounds())));
    RenderContext rc{scene, accel, lights, policy, film, engine.seed};
    std::optional<NoiseBreakdown> noise;
    if (engine.noiseBreakdown) {
        noise.emplace(film.width(), film.height(), film.exponent());
        rc.noise = &*noise;
    }

    // The pipeline: one emitter, one intersection handler, the retrace stages by ray kind.
    Stats stats;
    Intersector intersector(accel.root(), engine.packetWidth);
    RayProcessor processor(intersector, stats, engine.threads);
    CameraEmitter camera(rc);
    camera.setShare(cluster.rank(), cluster.size());
    ShadowStage shadow(rc);
    ReflectionStage reflection(rc);
    RefractionStage refraction(rc);
    SurfaceStage surface(rc, shadow, reflection, refraction);
    PathStage path(rc);
    RetraceStage* radianceStage = radiance == RadianceStage::Path
                                      ? static_cast<RetraceStage*>(&path)
                                      : static_cast<RetraceStage*>(&surface);
    processor.setStage(RayKind::Camera, radianceStage);
    processor.setStage(RayKind::Reflection, radianceStage);
    // Kinds of rays the scene analysis rules out get no stage: one would fail a check.
    processor.setStage(RayKind::Refraction, policy.refractionStage ? radianceStage : nullptr);
    processor.setStage(RayKind::Shadow, policy.shadowStage ? &shadow : nullptr);
    // The mode's own stages (gi's), and every stage for --stats in pipeline order.
    if (modeStages) modeStages->attach({rc, processor, surface, shadow});

    RenderResult result;
    result.stats.pipeline = enginePipeline();
    if (modeStages)
        for (const StageLabel& stage : modeStages->labels()) result.stats.pipeline.push_back(stage);
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> errorLog(nullptr, &std::fclose);
    // A write that fails (a full disk) ends the log, not the render: the image is still saved.
    auto logFailed = [&] {
        int err = errno;
        result.errorLogFailure = "cannot write the error log " + engine.errorLogPath + ": " +
                                 std::strerror(err) + "; its rows stop there";
        if (errorLog) std::fclose(errorLog.release());
    };
    // Every rank takes part in the log's image merge; rank 0 writes it.
    const bool logging = engine.reference && (!engine.errorLogPath.empty() || engine.onPassError);
    if (logging && cluster.root() && !engine.errorLogPath.empty()) {
        errorLog.reset(std::fopen(engine.errorLogPath.c_str(), "w"));
        if (!errorLog) throw std::runtime_error("cannot write the error log " + engine.errorLogPath);
        if (std::fprintf(errorLog.get(), "spp,seconds,relmse,rmse,relmse_estimate\n") < 0 ||
            std::fflush(errorLog.get()) != 0)
            logFailed();
    }

    // Passes of a few samples per pixel: the film commits between passes, which is where
    // progressive output is written and where a cancel leaves a consistent image.
    // Under a time limit or an error target, passes of 1 spp keep the budget closely.
    const bool stopEarly = engine.timeLimitSeconds > 0 || engine.targetRelMse > 0;
    // The noise breakdown takes each pass's sums for one sample's values.
    int passSpp = stopEarly || noise ? 1 : std::clamp(spp / 32, 1, 16);
    // Half buffers (alternate passes) give the relMSE estimate the target, the log and adaptive
    // sampling use.
    if (engine.targetRelMse > 0 || logging || engine.adaptiveSampling) film.enableHalfBuffers();
    // Adaptive sampling: `spp` is the mean over the pixels (or the cap under a target).
    std::optional<AdaptiveSampler> adaptive;
    if (engine.adaptiveSampling) {
        AdaptiveSampler::Settings as;
        as.minSpp = std::min(engine.adaptiveMinSpp, spp);
        as.targetRelMse = engine.targetRelMse;
        as.meanSpp = spp;
        as.maxSpp = engine.targetRelMse > 0 ? spp : kAdaptiveMaxFactor * spp;
        as.passSpp = passSpp;
        as.maxPassSpp = noise ? 1 : 16 * passSpp;
        adaptive.emplace(film.width(), film.height(), as);
    }
    // The samples per pixel of each pass of the next pair, once adaptive sampling decides.
    int adaptiveCount = 0;
    double meanSpp = 0;     // samples per pixel taken so far, the mean over the image
    double activeShare = 1; // the share of the pixels the current pair samples
    // The image of the whole job (every rank's tiles), on rank 0; a collective.
    auto wholeImage = [&] {
        if (!cluster.distributed()) return film.resolve();
        std::vector<double> sums = film.sums();
        std::vector<std::uint64_t> samples = film.sampleCounts();
        cluster.sumToRoot(sums);
        cluster.sumToRoot(samples);
        return Film::resolve(film.width(), film.height(), sums, samples);
    };
    int passes = adaptive ? std::numeric_limits<int>::max() : (spp + passSpp - 1) / passSpp;
    std::atomic<int> passIndex{0};
    std::atomic<std::uint64_t> unitsBefore{0};
    // Whether the camera's count is of a pass not yet in unitsBefore: between passes (gi's
    // refinement runs there) the last pass counted twice without it.
    std::atomic<bool> passInFlight{false};
    std::uint64_t totalUnits = 0;
    {
        // This rank's share: progress is rank 0's, which the others keep pace with.
        totalUnits = std::uint64_t(std::max(camera.tilesInShare(), 1)) * std::uint64_t(spp);
    }
    std::atomic<double> targetFraction{0.0};
    // Under a time limit the share of the budget spent, when it is ahead of the samples' (a
    // render asked for 100,000 spp and 90 s said 0.1% done and an ETA of hours).
    auto fraction = [&] {
        const std::uint64_t current = passInFlight.load() ? camera.unitsEmitted() : 0;
        double f = double(unitsBefore.load() + current) / double(totalUnits);
        if (engine.timeLimitSeconds > 0)
            f = std::max(f, std::min(1.0, secondsAt(Clock::now()) / engine.timeLimitSeconds));
        return engine.targetRelMse > 0 ? std::max(f, targetFraction.load()) : f;
    };
    auto raysSoFar = [&] { return std::uint64_t(stats.merged().raysTraced); };
    Progress progress(label, engine.quiet, fraction, raysSoFar);
    // The watcher stops watching before the film goes away, whatever ends the render.
    struct WatchScope {
        const EngineSettings::Watcher* w;
        ~WatchScope() {
            if (w && w->end) w->end();
        }
    } watch{engine.watcher};
    if (engine.watcher && engine.watcher->begin) engine.watcher->begin(film, fraction, raysSoFar);

    auto lastProgressive = std::chrono::steady_clock::now();
    // The caller's stop, when it has one, is a cancel that leaves the interrupt alone.
    bool stopped = false;
    auto stopRequested = [&engine] { return engine.stop && engine.stop(); };
    bool stop = cluster.distributed() ? agreeInterrupted(cluster) : interruptRequested();
    if (!cluster.distributed() && stopRequested()) stop = stopped = true;
    setupPhase.stop();
    for (int pass = 0; pass < passes && !stop; ++pass) {
        // What a pass does besides its hook, its processor run and the film's commit: the
        // estimates, the log, the decisions; on this thread.
        PhaseTimer betweenPhase(engine.phases, "between_passes");
        int first = adaptiveCount > 0 ? 0 : pass * passSpp;
        int count = adaptiveCount > 0 ? adaptiveCount : std::min(passSpp, spp - first);
        if (beforePass) {
            // gi's caustic maps and cache refinement time their own phases; the rest is here.
            PhaseTimer hookPhase(engine.phases, "pass_hooks");
            beforePass(pass, count);
        }
        camera.beginPass(first, count);
        passInFlight = true;
        timeWorkers(engine.phases, "render_passes", stats, processor.threads(), [&] {
            processor.run(camera, [&] { return interruptRequested() || stopRequested(); });
        });
        unitsBefore += std::min<std::uint64_t>(camera.unitsEmitted(), camera.unitsPerPass());
        passInFlight = false;
        {
            PhaseTimer commitPhase(engine.phases, "film_commit", PhaseKind::Parallel);
            film.commitPass(pass % 2);
        }
        if (noise) noise->commitPass();
        if (film.hasHalfBuffers()) {
            std::vector<double> parts = film.relMseParts();
            cluster.sumAll(parts);
            result.relMseEstimate = Film::relMseFromParts(parts);
        }
        passIndex = pass + 1;
        ++result.passesDone;
        meanSpp = adaptiveCount > 0 ? meanSpp + double(count) * activeShare : first + count;
        result.samplesDone = int(std::lround(meanSpp));
        bool budgetSpent = false; // without adaptive sampling the passes end the loop
        // Adaptive sampling decides between pairs of passes (one into each half), once every
        // pixel has its first samples.
        if (adaptive && pass % 2 == 1 && meanSpp >= adaptive->settings().minSpp) {
            AdaptiveSampler::Decision d = adaptive->update(film, [&](std::vector<double>& v) {
                cluster.sumAll(v);
            });
            meanSpp = d.meanSpp;
            activeShare = d.pixels > 0 ? double(d.activePixels) / double(d.pixels) : 0;
            budgetSpent = d.done;
            adaptiveCount = d.passSamples;
            camera.setMask(&adaptive->activeMask());
        }
        auto now = std::chrono::steady_clock::now();
        if (logging) {
            // The log's clock stops while the error is measured.
            double seconds = secondsAt(now);
            Image whole = wholeImage();
            if (cluster.root() && (errorLog || engine.onPassError)) {
                ImageMetrics m = compareImages(whole, *engine.reference);
                if (errorLog &&
                    (std::fprintf(errorLog.get(), "%.9g,%.6f,%.9g,%.9g,%.9g\n", meanSpp,
                                  seconds, m.relmse, m.rmse, result.relMseEstimate) < 0 ||
                     std::fflush(errorLog.get()) != 0))
                    logFailed();
                if (engine.onPassError)
                    engine.onPassError({result.samplesDone, seconds, m.relmse, m.rmse,
                                        result.relMseEstimate, raysSoFar()});
            }
            startTicks += (Clock::now() - now).count();
        }
        if (film.hasHalfBuffers() && std::isfinite(result.relMseEstimate) &&
            result.relMseEstimate > 0)
            // The variance part falls as 1/spp: the share of the work done is target/estimate.
            targetFraction = std::min(1.0, engine.targetRelMse / result.relMseEstimate);
        // Rank 0's clock and progressive schedule rule; an interrupt anywhere stops every rank.
        std::uint32_t decision = interruptBits() << kDecideSignalShift;
        if (stopRequested()) decision |= kDecideStopped;
        if (cluster.root() && engine.timeLimitSeconds > 0 && pass + 1 < passes &&
            secondsAt(Clock::now()) >= engine.timeLimitSeconds)
            decision |= kDecideTimeUp;
        if (cluster.root() && engine.onProgress && pass + 1 < passes &&
            std::chrono::duration<double>(now - lastProgressive).count() >= engine.progressiveSeconds)
            decision |= kDecideProgressive;
        if (cluster.distributed()) decision = cluster.orAll(decision);
        if (decision & kDecideInterrupted) {
            adoptInterrupt(decision >> kDecideSignalShift); // and the signal some rank received
            stop = true;
        }
        if (decision & kDecideStopped) stop = stopped = true;
        // At least kMinTargetPasses passes: with one or two samples per half the estimate is
        // itself too noisy to stop on (a 3-spp render estimated 0.044 measured 0.066).
        if (engine.targetRelMse > 0 && pass + 1 >= kMinTargetPasses &&
            result.relMseEstimate <= engine.targetRelMse) {
            result.targetReached = true;
            break;
        }
        if (decision & kDecideTimeUp) {
            result.timeLimitReached = true;
            break;
        }
        if (budgetSpent) break;
        if (decision & kDecideProgressive) {
            Image whole = wholeImage();
            if (engine.onProgress && cluster.root()) engine.onProgress(whole);
            lastProgressive = now;
        }
    }
    PhaseTimer resolvePhase(engine.phases, "film_resolve");
    result.cancelled = interruptRequested() || stopped;
    progress.finish(!result.cancelled);
    if (errorLog && std::fclose(errorLog.release()) != 0 && result.errorLogFailure.empty())
        logFailed();
    // The whole job's film on rank 0: each pixel is one rank's, the others add exact zeros.
    std::vector<double> sums = film.sums();
    std::vector<std::uint64_t> samples = film.sampleCounts();
    cluster.sumToRoot(sums);
    cluster.sumToRoot(samples);
    result.image = Film::resolve(film.width(), film.height(), sums, samples);
    if (noise) {
        std::vector<std::vector<double>> moments = noise->moments();
        for (auto& m : moments) cluster.sumToRoot(m);
        result.layers = NoiseBreakdown::layers(film.width(), film.height(), moments, samples);
    }
    result.filmLimit = film.fixedLimit();
    result.stats.totals = stats.merged();
    sumToRoot(cluster, result.stats.totals);
    result.stats.wallSeconds = secondsAt(Clock::now());
    result.stats.peakMemoryBytes = peakResidentBytes();
    result.stats.batchesAllocated = processor.batchesAllocated();
    result.stats.pixelsWithoutSamples = std::size_t(std::count(samples.begin(), samples.end(), 0));
    return result;
}

} // namespace rayproc
