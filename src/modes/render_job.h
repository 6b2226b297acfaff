// The driver every mode shares: builds the pipeline (camera emitter -> queue -> intersect ->
// surface / shadow / reflection / refraction stages -> film) for a shading policy and a light
// set, runs it pass by pass with progress, cancel and progressive output, and returns the image.
#pragma once

#include "accel/embree_scene.h"
#include "engine/engine_settings.h"
#include "engine/render_control.h"
#include "engine/render_context.h"
#include "engine/stats.h"
#include "image/image.h"
#include "lighting/light_set.h"
#include "scene/scene.h"

#include <chrono>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>

namespace rayproc {

class ModeStages;

// Which retrace stage continues camera rays: the Whitted-style surface stage (preview,
// raytrace) or the path stage (path).
enum class RadianceStage { Surface, Path };

struct RenderResult {
    Image image;
    RenderStats stats;
    bool cancelled = false;
    int passesDone = 0;
    int samplesDone = 0;          // samples per pixel rendered (fewer than asked under a time limit)
    bool timeLimitReached = false;
    bool targetReached = false;     // --target-relmse: the estimate got there
    double relMseEstimate = std::numeric_limits<double>::quiet_NaN(); // last one, with halves
    // Set when the error log (--error-log) could not be written (a full disk, say): the log
    // stopped there, the render went on; the caller reports it and fails.
    std::string errorLogFailure;
    // The largest |radiance| one contribution could carry (Film::fixedLimit: it follows the
    // scene's brightness); stats.totals.clampedSamples counts those beyond.
    double filmLimit = 18446744073709551616.0; // Film::kFixedLimit, the default
    // Extra per-pixel images (RenderControl::noiseBreakdown), on rank 0.
    std::vector<ImageLayer> layers;
};

// `modeStages` (optional) attaches a mode's own stages beside the engine's (gi's gather and
// correction; engine/mode_stages.h). beforePass (optional) runs before each pass with its index
// and the samples per pixel the pass takes, on every rank (gi's progressive caustics trace the
// pass's photon map there, sized by those samples); its time counts in the render's.
RenderResult runRenderJob(const std::string& label, const Scene& scene, const EmbreeScene& accel,
                          const LightSet& lights, const ShadingPolicy& policy, int spp,
                          const EngineSettings& engine, const RenderControl& control,
                          RadianceStage radiance = RadianceStage::Surface,
                          ModeStages* modeStages = nullptr,
                          const std::function<void(int pass, int samples)>& beforePass = {});

} // namespace rayproc
