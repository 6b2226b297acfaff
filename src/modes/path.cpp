#include "modes/modes.h"
#include "modes/render_plan.h"

#include "engine/phases.h"

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
    s.roulette = cli.roulette;
    return s;
}

namespace {

const char* lightKindName(const LightSource& l) {
    switch (l.kind) {
    case LightSource::Kind::Point: return "point";
    case LightSource::Kind::Spot: return "spot";
    case LightSource::Kind::Directional: return "directional";
    case LightSource::Kind::AreaMesh: return "mesh";
    case LightSource::Kind::AreaSphere: return "sphere";
    case LightSource::Kind::AreaDisk: return "disk";
    }
    return "light";
}

// Where the image's light and its noise come from, by strategy (ThreadStats::contributions):
// each category's share of the contributions' summed luminance (the image), of their summed
// squares (the noise: a firefly is one huge square) and its largest contribution. Emission seen
// through delta lobes only ("direct": a light in view) takes no share of the squares: its
// squares are its brightness, not noise.
void addContributionStats(const LightSet& lights, RenderResult& r) {
    const std::vector<ContributionMoments>& c = r.stats.totals.contributions;
    double sum = 0, squares = 0;
    for (std::size_t k = 0; k < c.size(); ++k) {
        sum += c[k].sum;
        if (k > 0) squares += c[k].sumSquares;
    }
    for (std::size_t k = 0; k < c.size(); ++k) {
        if (c[k].count == 0) continue;
        std::string label = "direct";
        if (k > 0) {
            std::size_t light = (k - 1) / 2;
            label = light < lights.lights.size()
                        ? "light" + std::to_string(light) + "_" + lightKindName(lights.lights[light])
                        : std::string("sky");
            label += (k % 2 == 1) ? "_samples" : "_found";
        }
        r.stats.extras.push_back({"path/" + label + "_image_share", sum > 0 ? c[k].sum / sum : 0.0});
        if (k > 0)
            r.stats.extras.push_back(
                {"path/" + label + "_squares_share", squares > 0 ? c[k].sumSquares / squares : 0.0});
        r.stats.extras.push_back({"path/" + label + "_largest", c[k].largest});
    }
}

} // namespace

RenderResult renderPath(const Scene& scene, const EmbreeScene& accel, const PathSettings& s,
                        const EngineSettings& engine, const RenderControl& control) {
    // The path stage picks one light per vertex among the sampled lights: a light the
    // analysis drops frees its share of the picks (the estimate stays unbiased; only noise
    // changes), and its emission, zero wherever a path can see it, needs no MIS weight.
    PhaseTimer lightPhase(control.phases, "light_set"); // and the scene analysis
    LightSet all = LightSet::build(scene, accel);
    RenderPlan plan = planRender(scene, accel, all, engine, kPlanPath);
    if (!plan.render) return blackRender(scene);
    LightSet lights = plan.sampledLights(all);
    lightPhase.stop();
    ShadingPolicy policy;
    policy.maxDepth = s.maxDepth;
    policy.rouletteEnabled = s.roulette;
    policy.rrStartDepth = s.rrStartDepth;
    policy.sppTotal = s.spp;
    policy.stratify = engine.stratification;
    policy.skyCompensation = engine.skyCompensation;
    plan.apply(policy);
    policy.reflectionStage = true; // path mode's bounces are all reflection-kind rays
    RenderResult r = runRenderJob("path", scene, accel, lights, policy, s.spp, engine, control,
                                  RadianceStage::Path);
    addContributionStats(lights, r);
    return r;
}

} // namespace rayproc
