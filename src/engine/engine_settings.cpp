#include "engine/engine_settings.h"

#include <sstream>

namespace rayproc {

std::string EngineSettings::toString() const {
    std::ostringstream o;
    o << "threads=" << (threads > 0 ? std::to_string(threads) : std::string("all"))
      << " packet_width=" << packetWidth << " seed=" << seed
      << " scene_analysis=" << (sceneAnalysis ? "on" : "off")
      << " stratification=" << (stratification ? "on" : "off")
      << " glossy_mis=" << (glossyMis ? "on" : "off")
      << " light_choice=" << (lightChoice ? "on" : "off")
      << " diffuse_mis=" << (diffuseMis ? "on" : "off")
      << " sky_compensation=" << (skyCompensation ? "on" : "off")
      << " spectral=" << (spectral ? "on" : "off")
      << " adaptive=" << (adaptiveSampling ? "on" : "off");
    if (adaptiveSampling) o << " adaptive_min_spp=" << adaptiveMinSpp;
    return o.str();
}

const EngineSwitchName* engineSwitchNames(std::size_t& count) {
    static const EngineSwitchName names[] = {
        {kSwitchStratification, "stratification", &EngineSettings::stratification},
        {kSwitchSkyCompensation, "sky-compensation", &EngineSettings::skyCompensation},
        {kSwitchGlossyMis, "glossy-mis", &EngineSettings::glossyMis},
        {kSwitchLightChoice, "light-choice", &EngineSettings::lightChoice},
        {kSwitchDiffuseMis, "diffuse-mis", &EngineSettings::diffuseMis},
    };
    count = sizeof names / sizeof names[0];
    return names;
}

} // namespace rayproc
