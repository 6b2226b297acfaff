#include "modes/modes.h"

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
    LightSet lights = LightSet::build(scene, accel);
    ShadingPolicy policy;
    policy.maxDepth = s.maxDepth;
    policy.rouletteEnabled = s.roulette;
    policy.rrStartDepth = s.rrStartDepth;
    policy.sppTotal = s.spp;
    return runRenderJob("path", scene, accel, lights, policy, s.spp, engine, RadianceStage::Path);
}

} // namespace rayproc
