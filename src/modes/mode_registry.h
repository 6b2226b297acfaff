// Every mode, registered once: its name, a line that says what it does, and its entry points:
// the samples per pixel of its settings, the render log's text of them, the photons the memory
// check counts, and its render. The render command, bench and serve read this list instead of
// naming the modes themselves. The modes' own command-line options are still declared by the
// render command (cli/render_command.cpp), which sets them on ModeSettings.
#pragma once

#include "modes/modes.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace rayproc {

// Every mode's settings side by side; a mode reads its own.
struct ModeSettings {
    PreviewSettings preview;
    RaytraceSettings raytrace;
    GiSettings gi;
    PathSettings path;
    // Every mode's settings from the scene's render block and the command line's overrides.
    static ModeSettings forScene(const Scene& scene, const ModeOverrides& cli);
    void setSpp(int spp) { preview.spp = raytrace.spp = gi.spp = path.spp = spp; }
};

struct ModeEntry {
    const char* name;
    const char* description; // for render --help's --mode

    int (*spp)(const ModeSettings& s);
    // The render log's text of the mode's settings (their toString()).
    std::string (*describe)(const ModeSettings& s);
    // Photons the memory check counts (engine/memory_budget.h): the global map's and the
    // largest caustic map's; none outside gi.
    std::pair<std::uint64_t, std::uint64_t> (*photons)(const ModeSettings& s);
    RenderResult (*render)(const Scene& scene, const EmbreeScene& accel, const ModeSettings& s,
                           const EngineSettings& engine);
};

// The modes in the order --help lists them.
const std::vector<ModeEntry>& modeRegistry();
// The mode called `name`; null when there is none.
const ModeEntry* findMode(const std::string& name);

} // namespace rayproc
