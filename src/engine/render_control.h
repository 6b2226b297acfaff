// How a caller steers and watches a render, beside what the image is made with
// (EngineSettings): the progressive output, serve's watcher and stop, the error log against a
// reference and bench's rows of it, the stops (time limit, error target), path mode's noise
// layers, the MPI cluster and the phase log. None of it is in the render log's settings line:
// the image depends on it only through the stops, which decide the passes. Every render takes
// one beside its EngineSettings; a caller without hooks passes a default-constructed one.
#pragma once

#include "cluster/cluster.h"
#include "image/image.h"

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace rayproc {

class PhaseLog;

struct RenderControl {
    // Called with the image so far after each pass when set (progressive output); the job
    // calls it at most once per `progressiveSeconds`.
    std::function<void(const Image&)> onProgress;
    double progressiveSeconds = 5.0;
    // A watcher of the render while it runs (rayproc serve, --display-server): `begin` gets
    // the image so far (the film's samples up to now, through the film's sensor as every image
    // the render hands out: callable from another thread), the fraction of the work done and
    // the rays traced so far, all callable at any time until `end`, which is called before the
    // film goes away.
    struct Watcher {
        std::function<void(std::function<Image()> image, std::function<double()> fraction,
                           std::function<std::uint64_t()> rays)> begin;
        std::function<void()> end;
    };
    const Watcher* watcher = nullptr;
    // A stop besides the interrupt, when set: polled with it before each emission (from the
    // render's threads at once) and after each pass, and true stops the render as a cancel
    // does (the result is cancelled), without the process-wide interrupt that Ctrl-C sets.
    // rayproc serve stops a preview that a newer edit has made stale. Only the camera passes
    // poll it (not gi's photon passes). The ranks of a distributed render stop together.
    std::function<bool()> stop;
    // Convergence log: after each pass, the samples, seconds, error against `reference` and
    // the reference-free estimate (Film::relMseEstimate) are appended to `errorLogPath` as CSV
    // (spp,seconds,relmse,rmse,relmse_estimate; the estimate is nan after the first pass).
    const Image* reference = nullptr;
    std::string errorLogPath;
    // The same row handed to a caller (rayproc bench --progressive), on rank 0, when set with
    // `reference`; `rays` counts the render passes' rays so far (not gi's photon passes).
    struct PassError {
        int spp = 0;
        double seconds = 0, relmse = 0, rmse = 0, relmseEstimate = 0;
        std::uint64_t rays = 0;
    };
    std::function<void(const PassError&)> onPassError;
    // When the mode's work started (gi sets it before its photon pass): the error log's
    // seconds, the time limit and the reported wall time count from here. Unset: from the
    // start of the render passes.
    std::optional<std::chrono::steady_clock::time_point> workStart;
    // > 0: stop after the first pass that ends past this many seconds (from workStart, the
    // error log's measuring excluded). Passes are then 1 spp, so the budget is kept closely.
    double timeLimitSeconds = 0;
    // > 0: passes of 1 spp alternate between two half buffers, and the render stops once the
    // relMSE estimated from their difference (Film::relMseEstimate) is at most this, or at
    // the mode's spp, the time limit or an interrupt, whichever comes first.
    double targetRelMse = 0;
    // Path mode's --debug-view noise: RenderResult::layers gets each pixel's noise and mean by
    // the strategy that sampled it (engine/noise_breakdown.h).
    bool noiseBreakdown = false;
    // The processes sharing the render (cluster/cluster.h); null: this process alone. Each
    // takes a share of the tiles (and of gi's photons and cache prepass); the image, the
    // statistics and the stop decisions are combined so the result is one process's, to the
    // bit. Only rank 0's result holds the whole image.
    const Cluster* cluster = nullptr;
    // The processes sharing the render: `cluster`, or this process alone when it is null.
    const Cluster& clusterOrAlone() const {
        static const Cluster alone;
        return cluster ? *cluster : alone;
    }
    // When set, every phase of the render (light set, photon passes, cache prepass, render
    // passes, film resolve...) adds its wall time here (engine/phases.h; --stats).
    PhaseLog* phases = nullptr;
};

} // namespace rayproc
