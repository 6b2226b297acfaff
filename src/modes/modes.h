// The paper's multi-mode system: each mode is one Settings struct (defaults, the scene file's
// "render" block, CLI overrides, toString() for the render log) and one driver.
#pragma once

#include "gi/gi_context.h"
#include "modes/render_job.h"
#include "scene/scene.h"

#include <memory>
#include <string>
#include <vector>

namespace rayproc {

class ModeOptions;
struct ModeSettings;

// Preview (the paper's real-time mode): ray casting, one sample per pixel, area lights as
// point lights at their corners with hard shadows, one bounce of mirror reflection, glass as
// straight-through transmission with a minimum translucency, unshadowed sky light.
struct PreviewSettings {
    int spp = 1;
    int maxDepth = 1;
    float minTranslucency = 0.35f;
    int maxGlassLayers = 4;
    std::string toString() const;
};

// Raytrace (the paper's gather-only mode): direct light with soft shadows (stratified samples
// over each area light), recursive mirror reflection and Fresnel refraction, no indirect
// diffuse; antialiasing by stratified sub-pixel samples.
struct RaytraceSettings {
    int spp = 16;
    int maxDepth = 8;
    int lightSamples = 4;
    float rrThreshold = 0.05f;
    bool roulette = true;
    std::string toString() const;
};

// Path (the in-house reference): unbiased path tracing with next-event estimation and
// multiple importance sampling (power heuristic), Russian roulette after a few bounces.
struct PathSettings {
    int spp = 64;
    int maxDepth = 64;
    int rrStartDepth = 3;
    bool roulette = true;
    std::string toString() const;
};

// The command line's options that several modes read (a mode's own are its ModeOptions,
// modes/mode_options.h). Unset counts (0) keep the scene's or the mode's default.
struct ModeOverrides {
    int spp = 0, maxDepth = 0, lightSamples = 0;
    bool roulette = true; // off: --no-russian-roulette (raytrace, path, gi)
    // --debug-view's name; gi takes its own views (photons, ic-records, caustics, indirect),
    // path's noise view is the engine's (RenderControl::noiseBreakdown).
    std::string debugView = "none";
};

// The light-sampling switches of the command line (--no-stratification, --no-glossy-mis,
// --no-diffuse-mis, --no-light-choice) in the policy of a mode whose stages sample lights at
// its hits (raytrace, gi's render passes).
inline void applyLightSwitches(const EngineSettings& engine, ShadingPolicy& policy) {
    policy.stratify = engine.stratification;
    policy.glossyMis = engine.glossyMis;
    policy.diffuseMis = engine.diffuseMis;
    policy.lightChoice = engine.lightChoice;
}

// A setting's value by precedence: the command line's, else the scene file's, else the mode's
// default already in `field`. Zero means "not set" in both sources.
inline void applySetting(int& field, int fromScene, int fromCli) {
    if (fromScene > 0) field = fromScene;
    if (fromCli > 0) field = fromCli;
}

const std::vector<std::string>& knownModes();
std::string defaultMode(); // the best mode implemented

PreviewSettings previewSettings(const SceneRenderSettings& scene, const ModeOverrides& cli);
RaytraceSettings raytraceSettings(const SceneRenderSettings& scene, const ModeOverrides& cli);

// gi's caustic photon count follows the scene's image size (defaultCausticPhotons), the rest its
// render settings.
GiSettings giSettings(const Scene& scene, const ModeOverrides& cli);
// gi's own command-line options (modes/gi_options.cpp).
std::unique_ptr<ModeOptions> giOptions();
// gi's settings in bench's words (ModeEntry::settingWords), beside its options.
std::string giSettingWords(const ModeSettings& settings);
// --no-russian-roulette's word when roulette is off (raytrace, path, gi): "no-russian-roulette".
inline std::string rouletteWord(bool roulette) { return roulette ? "" : "no-russian-roulette"; }
PathSettings pathSettings(const SceneRenderSettings& scene, const ModeOverrides& cli);

// Each render takes the caller's hooks and stops beside its settings (engine/render_control.h);
// none by default.
RenderResult renderPreview(const Scene& scene, const EmbreeScene& accel, const PreviewSettings& s,
                           const EngineSettings& engine, const RenderControl& control = {});
// The same with the scene's LightSet::buildPreview made once: it does not depend on the camera,
// and rebuilding it for every frame of a live view costs as much as a small frame's rays.
RenderResult renderPreview(const Scene& scene, const EmbreeScene& accel, const LightSet& all,
                           const PreviewSettings& s, const EngineSettings& engine,
                           const RenderControl& control = {});
RenderResult renderRaytrace(const Scene& scene, const EmbreeScene& accel,
                            const RaytraceSettings& s, const EngineSettings& engine,
                            const RenderControl& control = {});
// gi (Jensen's photon mapping with final gathering and Ward's irradiance cache): GiSettings in
// gi/gi_context.h.
RenderResult renderGi(const Scene& scene, const EmbreeScene& accel, const GiSettings& s,
                      const EngineSettings& engine, const RenderControl& control = {});
RenderResult renderPath(const Scene& scene, const EmbreeScene& accel, const PathSettings& s,
                        const EngineSettings& engine, const RenderControl& control = {});

} // namespace rayproc
