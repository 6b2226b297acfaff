// One bench render: a mode with its full settings, run in-process through the mode's driver and
// timed from the start of the mode's work to the finished image (for gi: photon tracing,
// precomputed irradiance and the irradiance cache's prepass included, since the whole
// renderGi call is timed). Scene loading and the BVH build are not timed: they are the same
// for every mode.
#pragma once

#include "accel/embree_scene.h"
#include "image/image.h"
#include "modes/mode_registry.h"
#include "modes/modes.h"
#include "scene/scene.h"

#include <cstdint>
#include <string>

namespace rayproc::bench {

// Every mode's settings; `mode` picks the one used (modes/mode_registry.h).
struct RenderConfig : ModeSettings {
    std::string mode;
    EngineSettings engine;
    // The render's stops and error rows (--progressive); none by default. Not in the settings
    // string: the caller names the stop it sets.
    RenderControl control;

    // The mode's settings from the scene's render block (as `rayproc render` would take them,
    // without CLI overrides) and `spp` samples per pixel.
    static RenderConfig forMode(const Scene& scene, const std::string& mode, int spp);
    int spp() const;
    // The results.csv settings column: "spp=N", the mode's own words for its settings
    // (ModeEntry::settingWords: for gi the swept "gather=64 ic=0.25 photons=200000" and every
    // setting off its default, "no-irradiance-cache", ...), every engine switch that is off
    // ("packets=1", "no-stratification", ...), and "spectral" for a spectral render. Enough to
    // reproduce the render with `rayproc render`.
    std::string settingsString() const;
};

struct GiVariant;
// `variant`'s swept gi settings (gather rays, IC accuracy, the global map's photons) on `c`.
void applyGiVariant(RenderConfig& c, const GiVariant& variant);

struct TimedRender {
    Image image;
    double seconds = 0;     // wall time of the mode driver's call
    std::uint64_t rays = 0; // every ray handed to Embree (RenderStats totals)
    bool cancelled = false; // Ctrl-C: the image is partial
};

// Renders with the mode's driver. Throws InputError for an unknown mode.
TimedRender renderTimed(const Scene& scene, const EmbreeScene& accel, const RenderConfig& c);

} // namespace rayproc::bench
