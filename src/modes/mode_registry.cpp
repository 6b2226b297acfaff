#include "modes/mode_registry.h"

#include "gi/progressive_caustics.h"

#include <algorithm>

namespace rayproc {

namespace {

std::pair<std::uint64_t, std::uint64_t> noPhotons(const ModeSettings&) { return {0, 0}; }

// One round of the global map: most scenes take one (docs/robustness.md, "Memory").
// Progressive caustics' passes of several samples trace maps of several times the photons.
std::pair<std::uint64_t, std::uint64_t> giPhotons(const ModeSettings& m) {
    const GiSettings& s = m.gi;
    const std::uint64_t caustic = std::uint64_t(std::max(0, s.causticPhotons));
    return {std::uint64_t(std::max(0, s.photons)),
            !s.caustics             ? 0
            : s.progressiveCaustics ? progressiveMaxPassPhotons(caustic)
                                    : caustic};
}

} // namespace

ModeSettings ModeSettings::forScene(const Scene& scene, const ModeOverrides& cli) {
    ModeSettings m;
    m.preview = previewSettings(scene.render, cli);
    m.raytrace = raytraceSettings(scene.render, cli);
    m.gi = giSettings(scene, cli);
    m.path = pathSettings(scene.render, cli);
    return m;
}

// What raytrace's and gi's stages read where they sample lights (applyLightSwitches).
constexpr unsigned kLightSwitches =
    kSwitchStratification | kSwitchGlossyMis | kSwitchLightChoice | kSwitchDiffuseMis;

const std::vector<ModeEntry>& modeRegistry() {
    static const std::vector<ModeEntry> modes{
        {"preview",
         "real-time approximation: point lights at area-light corners, hard shadows",
         nullptr,
         [](const ModeSettings& m) { return m.preview.spp; },
         [](const ModeSettings& m) { return m.preview.toString(); },
         [](const ModeSettings&) { return std::string(); }, kSwitchStratification, noPhotons,
         [](const Scene& scene, const EmbreeScene& accel, const ModeSettings& m,
            const EngineSettings& engine, const RenderControl& control) {
             return renderPreview(scene, accel, m.preview, engine, control);
         }},
        {"raytrace",
         "direct light with soft shadows, mirror reflection, Fresnel refraction",
         nullptr,
         [](const ModeSettings& m) { return m.raytrace.spp; },
         [](const ModeSettings& m) { return m.raytrace.toString(); },
         [](const ModeSettings& m) { return rouletteWord(m.raytrace.roulette); }, kLightSwitches,
         noPhotons,
         [](const Scene& scene, const EmbreeScene& accel, const ModeSettings& m,
            const EngineSettings& engine, const RenderControl& control) {
             return renderRaytrace(scene, accel, m.raytrace, engine, control);
         }},
        {"gi",
         "photon mapping with final gathering and an irradiance cache",
         giOptions,
         [](const ModeSettings& m) { return m.gi.spp; },
         [](const ModeSettings& m) { return m.gi.toString(); }, giSettingWords, kLightSwitches,
         giPhotons,
         [](const Scene& scene, const EmbreeScene& accel, const ModeSettings& m,
            const EngineSettings& engine, const RenderControl& control) {
             return renderGi(scene, accel, m.gi, engine, control);
         }},
        {"path",
         "unbiased path tracing with next-event estimation and MIS: the reference",
         nullptr,
         [](const ModeSettings& m) { return m.path.spp; },
         [](const ModeSettings& m) { return m.path.toString(); },
         [](const ModeSettings& m) { return rouletteWord(m.path.roulette); },
         kSwitchStratification | kSwitchSkyCompensation, noPhotons,
         [](const Scene& scene, const EmbreeScene& accel, const ModeSettings& m,
            const EngineSettings& engine, const RenderControl& control) {
             return renderPath(scene, accel, m.path, engine, control);
         }},
    };
    return modes;
}

const ModeEntry* findMode(const std::string& name) {
    for (const ModeEntry& m : modeRegistry())
        if (name == m.name) return &m;
    return nullptr;
}

std::string modeNameList(const std::string& last) {
    std::string s;
    const std::vector<ModeEntry>& modes = modeRegistry();
    for (std::size_t i = 0; i < modes.size(); ++i)
        s += (i == 0 ? "" : i + 1 < modes.size() ? ", " : last) + std::string(modes[i].name);
    return s;
}

const std::vector<std::string>& knownModes() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> out;
        for (const ModeEntry& m : modeRegistry()) out.push_back(m.name);
        return out;
    }();
    return names;
}

} // namespace rayproc
