// Settings of the engine itself, common to every mode and printed in the render log: threads,
// packet width, seed, the profiling switches, spectral rendering and adaptive sampling. The
// hooks and stops of its callers are not here: they are a RenderControl of their own
// (engine/render_control.h), a parameter of every render beside these settings.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace rayproc {

struct EngineSettings {
    int threads = 0;      // 0: all cores
    int packetWidth = 16; // 1 = single rays (rtcIntersect1); 4, 8, 16 = Embree packets
    std::uint64_t seed = 1;
    bool quiet = false;
    // Profiling switches: the scene analysis (modes/render_plan.h) skips what a scene does not
    // need; stratification of camera, light and gather samples.
    bool sceneAnalysis = true;
    bool stratification = true;
    // raytrace, gi: MIS of light samples and the sampled reflection of glossy lobes
    // (ShadingPolicy::glossyMis).
    bool glossyMis = true;
    // raytrace, gi: MIS of area-light samples and a cosine-sampled emission ray at diffuse
    // surfaces (ShadingPolicy::diffuseMis).
    bool diffuseMis = true;
    // raytrace, gi: choose among several area lights per sample (ShadingPolicy::lightChoice).
    bool lightChoice = true;
    // path: light samples of an image sky by its excess over its mean, the rest left to the
    // BSDF samples (ShadingPolicy::skyCompensation).
    bool skyCompensation = true;
    // Spectral rendering (engine/spectral_render.h, docs/spectral.md): three hero wavelengths
    // per path, in every mode (gi's photons carry wavelengths of their own).
    bool spectral = false;
    // Adaptive sampling (engine/adaptive_sampler.h): after adaptiveMinSpp samples everywhere,
    // pairs of passes go to the pixels whose noise needs them; the mode's spp is then the mean
    // over the image (the cap per pixel under targetRelMse).
    bool adaptiveSampling = false;
    int adaptiveMinSpp = 16;
    std::string toString() const;
};

// The sampling switches above that only some modes read, as the command line names them
// (--no-<word>). A mode says which its stages read (ModeEntry::engineSwitches); bench's
// settings column and the command line's warnings go by that, not by mode names.
enum EngineSwitch : unsigned {
    kSwitchStratification = 1u << 0,
    kSwitchSkyCompensation = 1u << 1,
    kSwitchGlossyMis = 1u << 2,
    kSwitchLightChoice = 1u << 3,
    kSwitchDiffuseMis = 1u << 4,
};
struct EngineSwitchName {
    EngineSwitch flag;
    const char* word; // the option is --no-<word>
    bool EngineSettings::*on;
};
// Every switch, in the order bench's settings column lists them.
const EngineSwitchName* engineSwitchNames(std::size_t& count);

} // namespace rayproc
