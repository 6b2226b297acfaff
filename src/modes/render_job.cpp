#include "modes/render_job.h"

#include "engine/camera_emitter.h"
#include "engine/cancel.h"
#include "engine/intersect.h"
#include "engine/path_stage.h"
#include "engine/processor.h"
#include "engine/progress.h"
#include "engine/reflection_stage.h"
#include "engine/refraction_stage.h"
#include "engine/shadow_stage.h"
#include "engine/surface_stage.h"
#include "gi/gather_stage.h"

#include "image/metrics.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <sstream>

namespace rayproc {

std::string EngineSettings::toString() const {
    std::ostringstream o;
    o << "threads=" << (threads > 0 ? std::to_string(threads) : std::string("all"))
      << " packet_width=" << packetWidth << " seed=" << seed
      << " scene_analysis=" << (sceneAnalysis ? "on" : "off")
      << " stratification=" << (stratification ? "on" : "off");
    return o.str();
}

namespace {
constexpr int kMinTargetPasses = 8;
} // namespace

RenderResult runRenderJob(const std::string& label, const Scene& scene, const EmbreeScene& accel,
                          const LightSet& lights, const ShadingPolicy& policy, int spp,
                          const EngineSettings& engine, RadianceStage radiance,
                          const GiData* gi) {
    auto start = engine.workStart ? *engine.workStart : std::chrono::steady_clock::now();
    Film film(scene.camera.width, scene.camera.height);
    RenderContext rc{scene, accel, lights, policy, film, engine.seed};
    rc.gi = gi;

    // The pipeline: one emitter, one intersection handler, the retrace stages by ray kind.
    Stats stats;
    Intersector intersector(accel.root(), engine.packetWidth);
    RayProcessor processor(intersector, stats, engine.threads);
    CameraEmitter camera(rc, spp);
    ShadowStage shadow(rc);
    ReflectionStage reflection(rc);
    RefractionStage refraction(rc);
    GatherStage gather(rc);
    SurfaceStage surface(rc, shadow, reflection, refraction, gi ? &gather : nullptr);
    PathStage path(rc);
    RetraceStage* radianceStage = radiance == RadianceStage::Path
                                      ? static_cast<RetraceStage*>(&path)
                                      : static_cast<RetraceStage*>(&surface);
    processor.setStage(RayKind::Camera, radianceStage);
    processor.setStage(RayKind::Reflection, radianceStage);
    // Kinds of rays the scene analysis rules out get no stage: one would fail a check.
    processor.setStage(RayKind::Refraction, policy.refractionStage ? radianceStage : nullptr);
    processor.setStage(RayKind::Shadow, policy.shadowStage ? &shadow : nullptr);
    processor.setStage(RayKind::Gather, gi ? &gather : nullptr);

    RenderResult result;
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> errorLog(nullptr, &std::fclose);
    // A write that fails (a full disk) ends the log, not the render: the image is still saved.
    auto logFailed = [&] {
        int err = errno;
        result.errorLogFailure = "cannot write the error log " + engine.errorLogPath + ": " +
                                 std::strerror(err) + "; its rows stop there";
        if (errorLog) std::fclose(errorLog.release());
    };
    if (engine.reference && !engine.errorLogPath.empty()) {
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
    int passSpp = stopEarly ? 1 : std::clamp(spp / 32, 1, 16);
    // Half buffers (alternate passes) give the relMSE estimate the target and the log use.
    if (engine.targetRelMse > 0 || errorLog) film.enableHalfBuffers();
    int passes = (spp + passSpp - 1) / passSpp;
    std::atomic<int> passIndex{0};
    std::atomic<std::uint64_t> unitsBefore{0};
    std::uint64_t totalUnits = 0;
    {
        int tiles = int(((scene.camera.width + 15) / 16) * ((scene.camera.height + 15) / 16));
        totalUnits = std::uint64_t(tiles) * std::uint64_t(spp);
    }
    std::atomic<double> targetFraction{0.0};
    Progress progress(
        label, engine.quiet,
        [&] {
            double f = double(unitsBefore.load() + camera.unitsEmitted()) / double(totalUnits);
            return engine.targetRelMse > 0 ? std::max(f, targetFraction.load()) : f;
        },
        [&] { return std::uint64_t(stats.merged().raysTraced); });

    auto lastProgressive = std::chrono::steady_clock::now();
    for (int pass = 0; pass < passes; ++pass) {
        if (interruptRequested()) break;
        int first = pass * passSpp;
        int count = std::min(passSpp, spp - first);
        camera.beginPass(first, count);
        processor.run(camera, [] { return interruptRequested(); });
        unitsBefore += std::min<std::uint64_t>(camera.unitsEmitted(), camera.unitsPerPass());
        film.commitPass(pass % 2);
        if (film.hasHalfBuffers()) result.relMseEstimate = film.relMseEstimate();
        passIndex = pass + 1;
        ++result.passesDone;
        result.samplesDone = first + count;
        auto now = std::chrono::steady_clock::now();
        if (errorLog) {
            // The log's clock stops while the error is measured.
            double seconds = std::chrono::duration<double>(now - start).count();
            ImageMetrics m = compareImages(film.resolve(), *engine.reference);
            if (std::fprintf(errorLog.get(), "%d,%.6f,%.9g,%.9g,%.9g\n", first + count, seconds,
                             m.relmse, m.rmse, result.relMseEstimate) < 0 ||
                std::fflush(errorLog.get()) != 0)
                logFailed();
            start += std::chrono::steady_clock::now() - now;
        }
        if (film.hasHalfBuffers() && std::isfinite(result.relMseEstimate) &&
            result.relMseEstimate > 0)
            // The variance part falls as 1/spp: the share of the work done is target/estimate.
            targetFraction = std::min(1.0, engine.targetRelMse / result.relMseEstimate);
        // At least kMinTargetPasses passes: with one or two samples per half the estimate is
        // itself too noisy to stop on (a 3-spp render estimated 0.044 measured 0.066).
        if (engine.targetRelMse > 0 && pass + 1 >= kMinTargetPasses &&
            result.relMseEstimate <= engine.targetRelMse) {
            result.targetReached = true;
            break;
        }
        if (engine.timeLimitSeconds > 0 && pass + 1 < passes &&
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >=
                engine.timeLimitSeconds) {
            result.timeLimitReached = true;
            break;
        }
        if (engine.onProgress && pass + 1 < passes &&
            std::chrono::duration<double>(now - lastProgressive).count() >= engine.progressiveSeconds) {
            engine.onProgress(film.resolve());
            lastProgressive = now;
        }
    }
    result.cancelled = interruptRequested();
    progress.finish(!result.cancelled);
    if (errorLog && std::fclose(errorLog.release()) != 0 && result.errorLogFailure.empty())
        logFailed();
    result.image = film.resolve();
    result.stats.totals = stats.merged();
    result.stats.wallSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result.stats.peakMemoryBytes = peakResidentBytes();
    result.stats.batchesAllocated = processor.batchesAllocated();
    result.stats.pixelsWithoutSamples = film.pixelsWithoutSamples();
    return result;
}

} // namespace rayproc
