#include "bench/ablation.h"

#include "bench/machine_info.h"
#include "core/error.h"
#include "engine/cancel.h"
#include "image/metrics.h"
#include "modes/mode_options.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace rayproc::bench {

const std::vector<AblationSwitch>& ablationSwitches() {
    static const std::vector<AblationSwitch> table = {
        {"packets (Embree width 16 vs 1)", "path", "--packet-width 1",
         [](RenderConfig& c) { c.engine.packetWidth = 1; }},
        {"packets (Embree width 16 vs 1)", "gi", "--packet-width 1",
         [](RenderConfig& c) { c.engine.packetWidth = 1; }},
        {"irradiance cache", "gi", "--no-irradiance-cache"},
        {"cache refinement", "gi", "--ic-refine-rays 0"},
        {"record correction", "gi", "--ic-correction-rays 0"},
        {"correction smoothing", "gi", "--no-ic-smoothing"},
        {"precomputed irradiance", "gi", "--no-precomputed-irradiance"},
        {"lazy precomputed irradiance", "gi", "--no-lazy-irradiance"},
        {"photon rounds", "gi", "--photon-rounds 1"},
        {"direct light at gather hits", "gi", "--no-gather-direct"},
        {"caustic map", "gi", "--no-caustics"},
        {"progressive caustics", "gi", "--no-progressive-caustics"},
        {"caustic radius per pixel", "gi", "--no-caustic-pixel-radius"},
        {"glossy MIS", "gi", "--no-glossy-mis",
         [](RenderConfig& c) { c.engine.glossyMis = false; }},
        {"diffuse MIS", "gi", "--no-diffuse-mis",
         [](RenderConfig& c) { c.engine.diffuseMis = false; }},
        {"light choice", "gi", "--no-light-choice",
         [](RenderConfig& c) { c.engine.lightChoice = false; }},
        {"Russian roulette", "path", "--no-russian-roulette",
         [](RenderConfig& c) { c.path.roulette = false; }},
        {"Russian roulette", "gi", "--no-russian-roulette",
         [](RenderConfig& c) { c.gi.roulette = false; }},
        {"stratification", "path", "--no-stratification",
         [](RenderConfig& c) { c.engine.stratification = false; }},
        {"stratification", "gi", "--no-stratification",
         [](RenderConfig& c) { c.engine.stratification = false; }},
        {"sky compensation", "path", "--no-sky-compensation",
         [](RenderConfig& c) { c.engine.skyCompensation = false; }},
    };
    return table;
}

// A mode's own option goes through the parser the mode registered (ModeEntry::options), so the
// table names it as the command line does and a new option needs no setter here. The parser's
// apply() sets every switch it has: the config's must be the scene's, as forMode leaves them.
void switchOff(const AblationSwitch& sw, RenderConfig& c) {
    if (sw.disable) {
        sw.disable(c);
        return;
    }
    const ModeEntry* entry = findMode(c.mode);
    if (!entry || !entry->options) throw InputError(c.mode + " has no option " + sw.cliOption);
    std::unique_ptr<ModeOptions> options = entry->options();
    CLI::App app;
    options->add(app);
    try {
        app.parse(sw.cliOption, false);
    } catch (const CLI::ParseError& e) {
        throw InputError(sw.cliOption + ": " + e.what());
    }
    options->apply(c);
}

std::string formatAblationCsvRow(const AblationRow& r) {
    auto q = quoteCsvField;
    char nums[256];
    std::snprintf(nums, sizeof nums, "%.17g,%.17g,%llu,%llu,%.17g,%.17g", r.secondsOn,
                  r.secondsOff, (unsigned long long)r.raysOn, (unsigned long long)r.raysOff,
                  r.relmseOn, r.relmseOff);
    return q(r.scene) + "," + q(r.optimisation) + "," + q(r.mode) + "," + q(r.settingsOn) + "," +
           q(r.settingsOff) + "," + nums;
}

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

RenderConfig baseConfig(const BenchScene& b, const BenchSuite& suite, const std::string& mode,
                        int threads) {
    int spp = mode == "gi" ? suite.ablationGiSpp : suite.ablationPathSpp;
    RenderConfig c = RenderConfig::forMode(*b.scene, mode, spp);
    c.engine.threads = threads;
    if (mode == "gi" && !suite.giVariants.empty()) applyGiVariant(c, suite.giVariants.front());
    return c;
}

std::string ratio(double num, double den) {
    if (!(den > 0)) return "–";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2fx", num / den);
    return buf;
}

std::string g3(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

} // namespace

AblationRun runAblation(const std::vector<SceneJob>& jobs, const BenchSuite& suite,
                        const BenchOptions& options, const std::string& csvPath,
                        const BenchLog& log) {
    std::ofstream csv(csvPath, std::ios::trunc);
    if (!csv) throw InputError(csvPath + ": cannot open for writing");
    csv << kAblationCsvHeader << "\n" << std::flush;
    AblationRun run;
    run.interrupted = !forEachBenchScene(jobs, suite, options, log, run.scenes,
                                         [&](const BenchScene& b) {
        for (const AblationSwitch& sw : ablationSwitches()) {
            RenderConfig on = baseConfig(b, suite, sw.mode, options.threads);
            RenderConfig off = on;
            switchOff(sw, off);
            AblationRow row{b.name, sw.name, sw.mode, on.settingsString(), off.settingsString()};
            std::vector<double> tOn, tOff;
            // Interleaved, so a change in the machine's load falls on both alike.
            for (int rep = 0; rep < std::max(1, suite.ablationRepeats); ++rep) {
                for (int which = 0; which < 2; ++which) {
                    const RenderConfig& c = which == 0 ? on : off;
                    TimedRender t = renderTimed(*b.scene, *b.accel, c);
                    if (t.cancelled || interruptRequested()) return false;
                    (which == 0 ? tOn : tOff).push_back(t.seconds);
                    if (rep == 0) { // the image is the same in every repeat (fixed seed)
                        double e = compareImages(t.image, b.reference.image).relmse;
                        (which == 0 ? row.relmseOn : row.relmseOff) = e;
                        (which == 0 ? row.raysOn : row.raysOff) = t.rays;
                    }
                }
            }
            row.secondsOn = median(tOn);
            row.secondsOff = median(tOff);
            csv << formatAblationCsvRow(row) << "\n" << std::flush;
            if (!csv) throw InputError(csvPath + ": cannot write");
            run.rows.push_back(row);
            log(b.name + " ablation " + sw.name + " (" + sw.mode + "): on " + g3(row.secondsOn) +
                " s relMSE " + g3(row.relmseOn) + ", off " + g3(row.secondsOff) + " s relMSE " +
                g3(row.relmseOff));
        }
        return true;
    });
    return run;
}

std::string renderAblationMarkdown(const AblationRun& run, const BenchSuite& suite,
                                   const std::string& commandLine, const std::string& loadAtStart,
                                   const std::string& loadAtEnd) {
    std::string sizeText = commonRenderSize(run.scenes, suite);
    if (sizeText.empty()) { // per-scene sizes: name each
        sizeText = "its scene's size (";
        for (std::size_t i = 0; i < run.scenes.size(); ++i)
            sizeText += (i ? ", " : "") + run.scenes[i].name + " " +
                        std::to_string(run.scenes[i].width) + "x" +
                        std::to_string(run.scenes[i].height);
        sizeText += ")";
    }
    std::ostringstream o;
    o << "# rayproc bench --ablation: suite `" << suite.name << "`\n\n";
    if (run.interrupted) o << "**Interrupted (Ctrl-C): only the rows that completed.**\n\n";
    o << "- Command: `" << commandLine << "`, " << utcTimestamp() << ".\n"
      << "- Machine: " << hardwareThreads() << " hardware threads, " << cpuModel()
      << ". Load average (1 min) " << loadAtStart << " at the start, " << loadAtEnd
      << " at the end: a shared machine, so time ratios within about 25% are noise.\n"
      << "- Each row renders the mode at " << sizeText << " with the "
      << "optimisation on and off, everything else equal (path " << suite.ablationPathSpp
      << " spp, gi " << suite.ablationGiSpp << " spp with the suite's first gi setting); "
      << "times are the median of " << std::max(1, suite.ablationRepeats)
      << " interleaved renders, relMSE against the scene's reference (the image does not vary "
         "between repeats).\n"
      << "- *time off/on* above 1: the optimisation saves time; *relMSE off/on* above 1: it "
         "lowers the error; *efficiency gain* = (time x relMSE) off / on, the factor by which "
         "the optimisation improves error-times-time (Monte Carlo efficiency).\n";
    std::string scene;
    for (const AblationRow& r : run.rows) {
        if (r.scene != scene) {
            scene = r.scene;
            o << "\n## " << scene << "\n\n| optimisation | mode | turned off by | time on | "
                 "time off | time off/on | relMSE on | relMSE off | relMSE off/on | efficiency "
                 "gain |\n|---|---|---|---|---|---|---|---|---|---|\n";
        }
        std::string cli;
        for (const AblationSwitch& sw : ablationSwitches())
            if (sw.name == r.optimisation && sw.mode == r.mode) cli = sw.cliOption;
        o << "| " << r.optimisation << " | " << r.mode << " | `" << cli << "` | "
          << g3(r.secondsOn) << " s | " << g3(r.secondsOff) << " s | "
          << ratio(r.secondsOff, r.secondsOn) << " | " << g3(r.relmseOn) << " | "
          << g3(r.relmseOff) << " | " << ratio(r.relmseOff, r.relmseOn) << " | "
          << ratio(r.secondsOff * r.relmseOff, r.secondsOn * r.relmseOn) << " |\n";
    }
    o << "\nEvery row: `ablation.csv`.\n";
    return o.str();
}

} // namespace rayproc::bench
