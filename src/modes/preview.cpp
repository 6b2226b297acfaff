#include "modes/modes.h"
#include "modes/render_plan.h"

#include "engine/phases.h"

#include <sstream>

namespace rayproc {

std::string PreviewSettings::toString() const {
    std::ostringstream o;
    o << "mode=preview spp=" << spp << " max_depth=" << maxDepth
      << " min_translucency=" << minTranslucency << " max_glass_layers=" << maxGlassLayers;
    return o.str();
}

PreviewSettings previewSettings(const SceneRenderSettings& scene, const ModeOverrides& cli) {
    PreviewSettings s;
    // Preview is one sample per pixel by design; --spp still lets a user ask for more.
    if (cli.spp > 0) s.spp = cli.spp;
    if (cli.maxDepth > 0) s.maxDepth = cli.maxDepth;
    else if (scene.maxDepth > 0) s.maxDepth = std::min(scene.maxDepth, s.maxDepth);
    return s;
}

RenderResult renderPreview(const Scene& scene, const EmbreeScene& accel, const PreviewSettings& s,
                           const EngineSettings& engine, const RenderControl& control) {
    // The light set (serve builds it once per scene and passes it to the overload below).
    PhaseTimer lightPhase(control.phases, "light_set");
    LightSet all = LightSet::buildPreview(scene, accel);
    lightPhase.stop();
    return renderPreview(scene, accel, all, s, engine, control);
}

RenderResult renderPreview(const Scene& scene, const EmbreeScene& accel, const LightSet& all,
                           const PreviewSettings& s, const EngineSettings& engine,
                           const RenderControl& control) {
    PhaseTimer lightPhase(control.phases, "light_set"); // the scene analysis's part
    RenderPlan plan = planRender(scene, accel, all, engine, kPlanPreview);
    if (!plan.render) return blackRender(scene);
    LightSet lights = plan.sampledLights(all);
    lightPhase.stop();
    ShadingPolicy policy;
    plan.apply(policy);
    policy.stratify = engine.stratification;
    policy.maxDepth = s.maxDepth;
    policy.lightSamples = 1;
    policy.rouletteEnabled = false;
    policy.previewGlass = true;
    policy.minTranslucency = s.minTranslucency;
    policy.maxGlassLayers = s.maxGlassLayers;
    policy.ambientEnvironment = true;
    return runRenderJob("preview", scene, accel, lights, policy, s.spp, engine, control);
}

} // namespace rayproc
