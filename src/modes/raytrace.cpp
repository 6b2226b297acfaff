#include "modes/modes.h"
#include "modes/render_plan.h"

#include "engine/phases.h"

#include <sstream>

namespace rayproc {

std::string RaytraceSettings::toString() const {
    std::ostringstream o;
    o << "mode=raytrace spp=" << spp << " max_depth=" << maxDepth
      << " light_samples=" << lightSamples << " rr_threshold=" << rrThreshold
      << " roulette=" << (roulette ? "on" : "off");
    return o.str();
}

RaytraceSettings raytraceSettings(const SceneRenderSettings& scene, const ModeOverrides& cli) {
    RaytraceSettings s;
    applySetting(s.spp, scene.spp, cli.spp);
    applySetting(s.maxDepth, scene.maxDepth, cli.maxDepth);
    applySetting(s.lightSamples, scene.lightSamples, cli.lightSamples);
    s.roulette = cli.roulette;
    return s;
}

RenderResult renderRaytrace(const Scene& scene, const EmbreeScene& accel,
                            const RaytraceSettings& s, const EngineSettings& engine,
                            const RenderControl& control) {
    PhaseTimer lightPhase(control.phases, "light_set"); // and the scene analysis
    LightSet all = LightSet::build(scene, accel);
    RenderPlan plan = planRender(scene, accel, all, engine, kPlanRaytrace);
    if (!plan.render) return blackRender(scene);
    LightSet lights = plan.sampledLights(all);
    lightPhase.stop();
    ShadingPolicy policy;
    policy.maxDepth = s.maxDepth;
    policy.lightSamples = s.lightSamples;
    policy.rrThreshold = s.rrThreshold;
    policy.rouletteEnabled = s.roulette;
    applyLightSwitches(engine, policy);
    plan.apply(policy);
    return runRenderJob("raytrace", scene, accel, lights, policy, s.spp, engine, control);
}

// The most complete mode implemented: full global illumination.
std::string defaultMode() { return "path"; }

} // namespace rayproc
