// Every mode, registered once: its name, a line that says what it does, its own command-line
// options, and its entry points: the samples per pixel of its settings, the render log's text of
// them, bench's words for those that are not the defaults, the photons the memory check counts,
// and its render. The render command, bench and serve read this list instead of naming the
// modes themselves.
//
// Where the command-line options live:
//  - A mode's own options, those only its settings read, are declared beside its settings
//    (ModeEntry::options, modes/mode_options.h; gi's in modes/gi_options.cpp) and listed in
//    render --help under "<mode> options". Only gi has such options today.
//  - Options several modes read stay with the render command (cli/render_command.cpp), in one
//    place instead of one copy per mode, and reach the settings through ModeOverrides (--spp,
//    --max-depth, --light-samples, --no-russian-roulette, --debug-view), which each mode's
//    settings function applies with the scene's render block. A CLI11 option belongs to one
//    group, and these have one meaning across the modes that read them.
//  - Options of the engine, which every mode's stages read (the profiling switches such as
//    --no-stratification or --no-sky-compensation, --spectral, --threads, the stops and the
//    watchers), stay with the render command, which sets them on EngineSettings (the stops and
//    watchers on the RenderControl it passes beside them): engine/ knows nothing of the modes.
#pragma once

#include "modes/mode_options.h"
#include "modes/modes.h"

#include <cstdint>
#include <memory>
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
    // The mode's own command-line options, a new set of values per call; null when it has none.
    std::unique_ptr<ModeOptions> (*options)();

    int (*spp)(const ModeSettings& s);
    // The render log's text of the mode's settings (their toString()).
    std::string (*describe)(const ModeSettings& s);
    // The mode's own settings as bench's results name them (its settings column, after "spp=N"):
    // each one that differs from the mode's default, as `name=value` or `no-<switch>` after the
    // option that sets it; gi's swept counts (gather, ic, photons) always. Empty when there is
    // nothing to say. A new setting of a mode adds its word here, not in bench/.
    std::string (*settingWords)(const ModeSettings& s);
    // The engine's sampling switches its stages read (EngineSwitch flags; engine_settings.h).
    unsigned engineSwitches;
    // Photons the memory check counts (engine/memory_budget.h): the global map's and the
    // largest caustic map's; none outside gi.
    std::pair<std::uint64_t, std::uint64_t> (*photons)(const ModeSettings& s);
    // The render: what the image is made with (`s`, `engine`) and how the caller steers and
    // watches it (`control`: stops, progressive output, error log, cluster, phases).
    RenderResult (*render)(const Scene& scene, const EmbreeScene& accel, const ModeSettings& s,
                           const EngineSettings& engine, const RenderControl& control);
};

// The modes in the order --help lists them.
const std::vector<ModeEntry>& modeRegistry();
// The mode called `name`; null when there is none.
const ModeEntry* findMode(const std::string& name);
// The modes' names in the registry's order, ", " between them and `last` before the last one:
// "preview, raytrace, gi or path" with " or ".
std::string modeNameList(const std::string& last);

} // namespace rayproc
