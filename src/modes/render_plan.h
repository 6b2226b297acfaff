// Scene analysis: before rendering, decide from the scene and the light set which passes and
// stages can contribute to the image, so the mode drivers skip the rest. Each decision keeps
// its reason, printed in the render log and by `rayproc info`. Only work that provably adds
// nothing is skipped (see docs/architecture.md, "Scene analysis"); `--no-scene-analysis`
// (EngineSettings::sceneAnalysis = false) runs everything.
#pragma once

#include "accel/embree_scene.h"
#include "engine/render_context.h"
#include "lighting/light_set.h"
#include "modes/render_job.h"
#include "scene/scene.h"

#include <cstdint>
#include <string>
#include <vector>

namespace rayproc {

// The modes a skip concerns, as a bit set.
enum PlanModes : unsigned {
    kPlanPreview = 1,
    kPlanRaytrace = 2,
    kPlanGi = 4,
    kPlanPath = 8,
    kPlanAllModes = 15,
};

// One pass or stage that does not run, and why.
struct PlanSkip {
    std::string what;
    std::string why;
    unsigned modes = kPlanAllModes;
};

struct LightDecision {
    bool sampled = true;
    std::string reason; // why not, when not sampled
};

struct RenderPlan {
    bool analysed = false; // false: --no-scene-analysis, every decision below is "run"

    // What the scene holds: placed leaves by material type, and lights.
    std::size_t diffuseLeaves = 0, glossyLeaves = 0, mirrorLeaves = 0, dielectricLeaves = 0;
    std::size_t coatLeaves = 0; // coated diffuse: their coats reflect light onto other surfaces
    std::size_t radiatingLights = 0; // sampled lights (non-zero power, can reach something) + sky
    bool environment = false;
    bool deltaLightsOnly = false;    // point, spot and directional lights only (no area, no sky)

    // Decisions.
    bool render = true;          // false: nothing emits light, the image is black
    bool causticMap = true;      // gi: a mirror or glass surface can carry light to a diffuse one
    bool globalMap = true;       // gi: global photon map, final gather, irradiance cache
    bool refractionStage = true; // a dielectric is placed
    bool reflectionStage = true; // a mirror or glossy surface is placed
    bool shadowStage = true;     // a diffuse or glossy surface is placed
    bool lightStratification = true;
    std::vector<LightDecision> lights; // one per light of the analysed LightSet

    std::vector<PlanSkip> skipped;

    std::size_t sampledLightCount() const;
    // The lights to sample: the analysed set without the lights found not worth sampling.
    LightSet sampledLights(const LightSet& all) const;
    // Sets the stage switches and the light sample count of a mode's shading policy.
    void apply(ShadingPolicy& policy) const;
    // "skipped <what>: <why>" for every skip that concerns `mode` (kPlan* bit).
    std::vector<std::string> logLines(unsigned mode) const;
};

// The analysis: a pure function of the scene (its placed leaves and camera) and the light set
// the mode samples (LightSet::build, or LightSet::buildPreview for preview mode).
RenderPlan analyseScene(const Scene& scene, const EmbreeScene& accel, const LightSet& lights);
// Every pass and stage runs and every light is sampled (--no-scene-analysis).
RenderPlan fullPlan(const LightSet& lights);

// What a mode driver does first: the analysis (or the full plan when the engine settings turn
// it off), its lines in the render log unless quiet, and a warning when nothing emits.
RenderPlan planRender(const Scene& scene, const EmbreeScene& accel, const LightSet& lights,
                      const EngineSettings& engine, unsigned mode);
// The result of a render the plan skipped because nothing emits: a black image.
RenderResult blackRender(const Scene& scene);

} // namespace rayproc
