#include "modes/modes.h"
#include "modes/render_plan.h"

#include <sstream>

namespace rayproc {

std::string PathSettings::toString() const {
    std::ostringstream o;
    o << "mode=path spp=" << spp << " max_depth=" << maxDepth
      << " rr_start_depth=" << rrStartDepth << " roulette=" << (roulette ? "on" : "off");
    return o.str();
}

PathSettings pathSettings(const SceneRenderSettings& scene, const ModeOverrides& cli) {
    PathSettings s;
    applySetting(s.spp, scene.spp, cli.spp);
    applySetting(s.maxDepth, scene.maxDepth, cli.maxDepth);
    return s;
}

RenderResult renderPath(const Scene& scene, const EmbreeScene& accel, const PathSettings& s,
                        const EngineSettings& engine) {
    // The path stage picks one light per vertex among the sampled lights: a light the
    // analysis drops frees its share of the picks (the estimate stays unbiased; only noise
    // changes), and its emission, zero wherever a path can see it, needs no MIS weight.
    LightSet all = LightSet::build(scene, accel);
    RenderPlan plan = planRender(scene, accel, all, engine, kPlanPath);
    if (!plan.render) return blackRender(scene);
    LightSet lights = plan.sampledLights(all);
    ShadingPolicy policy;
    policy.maxDepth = s.maxDepth;
    policy.rouletteEnabled = s.roulette;
    policy.rrStartDepth = s.rrStartDepth;
    policy.sppTotal = s.spp;
    policy.stratify = engine.stratification;
    plan.apply(policy);
    policy.reflectionStage = true; // path mode's bounces are all reflection-kind rays
    return runRenderJob("path", scene, accel, lights, policy, s.spp, engine, RadianceStage::Path);
}

} // namespace rayproc
