// What every stage of one render reads: the scene, its Embree mapping, the lights, the shading
// policy of the mode, and the film it writes. Read-only but for the film's atomic sums.
#pragma once

#include "accel/embree_scene.h"
#include "engine/film.h"
#include "kernels/ray_offset.h"
#include "lighting/light_set.h"
#include "scene/scene.h"

#include <cstdint>

namespace rayproc {

class NoiseBreakdown;
class SpectralRender;

// How surfaces are shaded: the knobs that make preview and raytrace modes differ.
struct ShadingPolicy {
    int maxDepth = 8;          // reflection + refraction bounces along a path
    int lightSamples = 4;      // stratified light samples per hit (see lightChoice) and of the sky
    float rrThreshold = 0.05f; // below this throughput (max channel), Russian roulette
    bool rouletteEnabled = true;
    // Preview: glass lets light straight through (no bending) and keeps at least this much
    // transmission, so it never turns black or vanishes; the environment lights surfaces
    // unshadowed (ambient) instead of by shadow rays.
    bool previewGlass = false;
    float minTranslucency = 0.0f;
    int maxGlassLayers = 0;
    bool ambientEnvironment = false;
    // Path mode: Russian roulette starts after this many bounces; the stratified first-hit
    // dimensions need the render's samples per pixel.
    int rrStartDepth = 3;
    int sppTotal = 1;
    // A prepass for the surface stage's diffuse-hit handlers (gi's irradiance cache): no direct
    // light and no glossy or coated lobe, only the handlers and the specular chains that lead
    // to diffuse hits get work. And a debug view may keep only one component (directLight
    // off: direct light and emission are dropped).
    bool handlersOnly = false;
    bool directLight = true;
    // Stratified camera, light and gather samples; off (--no-stratification): independent
    // uniform numbers from the same streams.
    bool stratify = true;
    // Stages the scene analysis found unneeded (modes/render_plan.h): never given work.
    bool reflectionStage = true, refractionStage = true, shadowStage = true;
    // raytrace, gi: a glossy lobe's light comes from both light samples and its sampled
    // reflection ray, combined by the power heuristic (engine/glossy_mis.h); off
    // (--no-glossy-mis): light samples only, the reflection ray ignores emitters.
    bool glossyMis = false;
    // raytrace, gi: a diffuse surface's light from area lights comes from both light samples
    // and one cosine-sampled ray that collects only emission, combined by the power heuristic
    // (engine/glossy_mis.h); off (--no-diffuse-mis): light samples only.
    bool diffuseMis = false;
    // raytrace, gi: with several area lights a hit takes lightSamples samples per light that
    // matters, each choosing a light with LightSet::areaSampler (lighting/light_set.h); off
    // (--no-light-choice): lightSamples samples of every area light.
    bool lightChoice = false;
    // path: an image sky's light samples follow its excess over its mean and the MIS weights
    // use that density (pbrt-v4's allowIncompletePDF; lighting/environment_map.h); off
    // (--no-sky-compensation): they follow its luminance.
    bool skyCompensation = false;
};

struct RenderContext {
    const Scene& scene;
    const EmbreeScene& accel;
    const LightSet& lights;
    const ShadingPolicy& policy;
    Film& film;
    std::uint64_t seed = 0;
    // Path mode's --debug-view noise: every contribution is also filed by pixel and strategy.
    NoiseBreakdown* noise = nullptr;
    // Spectral mode (engine/spectral_render.h); null: RGB.
    const SpectralRender* spectral = nullptr;
};

// The origin of a ray leaving hit h in direction `dir`: off the surface along the geometric
// normal `ng` (either side's) by the hit point's error bound, on the side of `dir`
// (kernels/ray_offset.h, docs/robustness.md).
inline Vec3 offsetRayOrigin(const SurfaceHit& h, const Vec3& ng, const Vec3& dir) {
    return kernels::offsetRayOrigin(h.p, h.pError, ng, dir);
}

} // namespace rayproc
