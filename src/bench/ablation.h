// --ablation: what each optimisation buys. For each scene of the suite and each switch of the
// table below, the switch's mode renders at the suite's ablation budget with the optimisation
// on and off (the same seed, budget and settings otherwise); the report gives both times (the
// median of the suite's repeats) and both relMSEs, and their ratios.
//
// The switches are one table (ablationSwitches): adding one is one line naming the
// optimisation, the mode it serves, the `rayproc render` option that turns it off, and how it
// is turned off in a RenderConfig.
#pragma once

#include "bench/bench_render.h"
#include "bench/runner.h"
#include "bench/suite.h"

#include <string>
#include <vector>

namespace rayproc::bench {

struct AblationSwitch {
    std::string name;      // the optimisation: "irradiance cache"
    std::string mode;      // the mode whose render it speeds up or improves
    std::string cliOption; // how `rayproc render` turns it off
    // Turns it off on a render's settings; null for a mode's own option (ModeEntry::options),
    // which `cliOption` turns off through the mode's own parser, as on the command line.
    void (*disable)(RenderConfig&) = nullptr;
};

const std::vector<AblationSwitch>& ablationSwitches();
// The switch off on `c` (a mode's settings from the scene, as RenderConfig::forMode makes them).
void switchOff(const AblationSwitch& sw, RenderConfig& c);

struct AblationRow {
    std::string scene, optimisation, mode, settingsOn, settingsOff;
    double secondsOn = 0, secondsOff = 0; // medians over the repeats
    std::uint64_t raysOn = 0, raysOff = 0;
    double relmseOn = 0, relmseOff = 0;
};

inline const char* kAblationCsvHeader =
    "scene,optimisation,mode,settings_on,settings_off,seconds_on,seconds_off,rays_on,rays_off,"
    "relmse_on,relmse_off";
std::string formatAblationCsvRow(const AblationRow& row);

struct AblationRun {
    std::vector<SceneInfo> scenes;
    std::vector<AblationRow> rows;
    bool interrupted = false;
};

// Renders the ablation of every scene of `jobs` (benchSceneJobs), appending each finished row to
// `csvPath` (header first).
AblationRun runAblation(const std::vector<SceneJob>& jobs, const BenchSuite& suite,
                        const BenchOptions& options, const std::string& csvPath,
                        const BenchLog& log);

// ablation.md: one table per scene (time on/off, relMSE on/off, ratios).
std::string renderAblationMarkdown(const AblationRun& run, const BenchSuite& suite,
                                   const std::string& commandLine, const std::string& loadAtStart,
                                   const std::string& loadAtEnd);

} // namespace rayproc::bench
