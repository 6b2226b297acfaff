#include "modes/modes.h"

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
    if (scene.spp > 0) s.spp = scene.spp;
    if (scene.maxDepth > 0) s.maxDepth = scene.maxDepth;
    if (scene.lightSamples > 0) s.lightSamples = scene.lightSamples;
    if (cli.spp > 0) s.spp = cli.spp;
    if (cli.maxDepth > 0) s.maxDepth = cli.maxDepth;
    if (cli.lightSamples > 0) s.lightSamples = cli.lightSamples;
    return s;
}

RenderResult renderRaytrace(const Scene& scene, const EmbreeScene& accel,
                            const RaytraceSettings& s, const EngineSettings& engine) {
    LightSet lights = LightSet::build(scene, accel);
    ShadingPolicy policy;
    policy.maxDepth = s.maxDepth;
    policy.lightSamples = s.lightSamples;
    policy.rrThreshold = s.rrThreshold;
    policy.rouletteEnabled = s.roulette;
    return runRenderJob("raytrace", scene, accel, lights, policy, s.spp, engine);
}

const std::vector<std::string>& knownModes() {
    static const std::vector<std::string> modes{"preview", "raytrace", "gi", "path"};
    return modes;
}

// The most complete mode implemented: full global illumination.
std::string defaultMode() { return "path"; }

} // namespace rayproc
