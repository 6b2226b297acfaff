// `rayproc bench`: run time against error. Renders each scene of a suite in each mode at
// increasing budgets, measures each image against the scene's reference, and writes
// results.csv, one log-log plot per scene (SVG) and summary.md; or, with --ablation, what each
// optimisation buys (ablation.csv, ablation.md). The work is in src/bench/.
#include "bench/ablation.h"
#include "bench/machine_info.h"
#include "bench/mode_curves.h"
#include "bench/results_csv.h"
#include "cli/output_paths.h"
#include "bench/runner.h"
#include "bench/scene_plot.h"
#include "bench/suite.h"
#include "bench/summary.h"
#include "bench/svg_plot.h"
#include "cli/commands.h"
#include "core/error.h"
#include "engine/cancel.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

namespace rayproc::cli {

namespace {

namespace fs = std::filesystem;
using namespace rayproc::bench;

struct BenchArgs {
    std::string suite;
    bool quick = false, ablation = false, reportOnly = false;
    BenchOptions options;
};

// The scenes/ folder: in the current directory, else next to the build directory holding the
// executable (build/rayproc -> scenes/).
std::string defaultScenesDir() {
    if (fs::is_directory("scenes")) return "scenes";
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        fs::path candidate = exe.parent_path().parent_path() / "scenes";
        if (fs::is_directory(candidate)) return candidate.string();
    }
    return "scenes";
}

void writeText(const std::string& path, const std::string& text) {
    std::string tmp = path + ".tmp";
    {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        f << text;
        f.flush();
        if (!f) {
            fs::remove(tmp);
            throw InputError(path + ": cannot write");
        }
    }
    fs::rename(tmp, path);
}

std::string commandLine(const BenchArgs& a, const std::string& suite) {
    std::string s = "rayproc bench " + suite;
    if (a.ablation) s += " --ablation";
    if (a.reportOnly) s += " --report-only";
    s += " -o " + a.options.outDir;
    if (!a.options.refsDir.empty()) s += " --refs " + a.options.refsDir;
    for (const std::string& f : a.options.sceneFiles) s += " --scene " + f;
    for (const std::string& r : a.options.referenceImages) s += " --reference " + r;
    if (!a.options.modes.empty()) {
        s += " --modes ";
        for (std::size_t i = 0; i < a.options.modes.size(); ++i)
            s += (i ? "," : "") + a.options.modes[i];
    }
    if (a.options.progressive) s += " --progressive";
    if (a.options.spectral) s += " --spectral";
    for (const std::string& f : a.options.peerCsvs) s += " --peer-csv " + f;
    if (a.options.threads > 0) s += " --threads " + std::to_string(a.options.threads);
    if (a.options.timeCapSeconds > 0) {
        char buf[32];
        std::snprintf(buf, sizeof buf, " --time-cap %g", a.options.timeCapSeconds);
        s += buf;
    }
    return s;
}

// The plots and summary.md from the run's rows and the peers' rows.
void writeReport(std::vector<BenchRow> rows, SummaryContext& ctx, const std::string& outDir) {
    for (const std::string& peer : ctx.peerCsvs) {
        std::vector<BenchRow> p = readResultsCsv(peer);
        rows.insert(rows.end(), p.begin(), p.end());
    }
    for (const std::string& scene : sceneNames(rows)) {
        // The scene's render size (a peer-only scene, unknown to the run: the suite's).
        std::string size = std::to_string(ctx.suite->width) + "x" +
                           std::to_string(ctx.suite->height);
        for (const SceneInfo& s : ctx.scenes)
            if (s.name == scene) size = std::to_string(s.width) + "x" + std::to_string(s.height);
        std::string subtitle = "relMSE against render time, " + size;
        std::string path = (fs::path(outDir) / plotFileName(scene)).string();
        writeText(path, renderSvg(scenePlot(rows, scene, subtitle)));
        std::printf("%s\n", fs::absolute(path).c_str());
    }
    std::string summary = (fs::path(outDir) / "summary.md").string();
    writeText(summary, renderSummary(rows, ctx));
    std::printf("%s\n", fs::absolute(summary).c_str());
}

// The suite the options name, after the checks that need no file.
const BenchSuite& selectSuite(BenchArgs& a, const std::string& suiteName) {
    if (a.quick && suiteName != "quick")
        throw InputError("--quick selects the suite 'quick'; it cannot be combined with suite '" +
                         suiteName + "'");
    const BenchSuite& suite = findSuite(suiteName);
    BenchOptions& o = a.options;
    if (o.scenesDir.empty()) o.scenesDir = defaultScenesDir();
    if (a.ablation && o.progressive)
        throw InputError("--progressive renders the curves; --ablation renders each "
                         "optimisation on and off at one budget: pick one");
    if (a.ablation && o.spectral)
        throw InputError("--spectral renders the curves spectrally; --ablation measures the "
                         "optimisations in RGB: pick one");
    if (a.ablation && !o.modes.empty())
        throw InputError("--modes selects the curves' modes; --ablation renders its own fixed "
                         "list of optimisations in path and gi mode");
    return suite;
}

// The run's files before any work: the peer CSVs read, no output one of the inputs, the output
// directory made and writable.
void checkBenchFiles(const BenchArgs& a, const std::vector<SceneJob>& jobs,
                     const std::string& resultsPath) {
    const BenchOptions& o = a.options;
    if (a.reportOnly && !fs::is_regular_file(resultsPath))
        throw InputError(resultsPath + ": no results to report (--report-only reads the "
                                       "results.csv of an earlier run)");
    for (const std::string& peer : o.peerCsvs) readResultsCsv(peer); // fail before rendering
    // No output of the run may be one of its inputs.
    std::vector<NamedPath> files;
    for (const std::string& peer : o.peerCsvs) files.push_back({"--peer-csv", peer, false});
    for (const SceneJob& job : jobs)
        if (job.source == ReferenceSource::Given)
            files.push_back({"--reference", job.reference, false});
    for (const std::string& scene : o.sceneFiles) files.push_back({"--scene", scene, false});
    for (const char* name : {"results.csv", "summary.md", "ablation.csv", "ablation.md"})
        files.push_back({"the output " + std::string(name), (fs::path(o.outDir) / name).string(),
                         !a.reportOnly || std::string(name) == "summary.md"});
    checkDistinctFiles(files);
    std::error_code ec;
    fs::create_directories(o.outDir, ec);
    if (ec || !fs::is_directory(o.outDir))
        throw InputError(o.outDir + ": cannot create the output directory" +
                         (ec ? " (" + ec.message() + ")" : std::string()));
    if (::access(o.outDir.c_str(), W_OK) != 0)
        throw InputError(o.outDir + ": the output directory is not writable");
}

// --ablation: each optimisation on and off, into ablation.csv and ablation.md.
int runAblationBench(const std::vector<SceneJob>& jobs, const BenchSuite& suite,
                     const BenchOptions& o, const SummaryContext& ctx, const BenchLog& log) {
    std::string csv = (fs::path(o.outDir) / "ablation.csv").string();
    AblationRun run = runAblation(jobs, suite, o, csv, log);
    std::string md = (fs::path(o.outDir) / "ablation.md").string();
    writeText(md, renderAblationMarkdown(run, suite, ctx.commandLine, ctx.loadAtStart,
                                         loadAverage()));
    std::printf("%s\n%s\n", fs::absolute(csv).c_str(), fs::absolute(md).c_str());
    if (run.interrupted) {
        std::fprintf(stderr, "rayproc bench: interrupted; kept the %zu rows that completed\n",
                     run.rows.size());
        return interruptExitStatus();
    }
    return 0;
}

// The curves: the spp ladders or the progressive renders, into results.csv and the report.
int runCurvesBench(const std::vector<SceneJob>& jobs, const BenchSuite& suite,
                   const BenchOptions& o, const std::string& resultsPath, SummaryContext& ctx,
                   const BenchLog& log, std::chrono::steady_clock::time_point start) {
    ResultsCsvWriter results(resultsPath, /*truncate=*/true);
    LadderRun run = o.progressive ? runProgressive(jobs, suite, o, results, log)
                                  : runLadders(jobs, suite, o, results, log);
    ctx.scenes = run.scenes;
    ctx.interrupted = run.interrupted;
    ctx.loadAtEnd = loadAverage();
    ctx.totalSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%s\n", fs::absolute(resultsPath).c_str());
    writeReport(run.rows, ctx, o.outDir);
    if (run.interrupted) {
        std::fprintf(stderr,
                     "rayproc bench: interrupted; results.csv and the report hold the %zu "
                     "renders that completed\n",
                     run.rows.size());
        return interruptExitStatus();
    }
    return 0;
}

int runBench(BenchArgs& a) {
    std::string suiteName = a.suite.empty() ? (a.quick ? "quick" : "default") : a.suite;
    const BenchSuite& suite = selectSuite(a, suiteName);
    BenchOptions& o = a.options;
    // Scene files, --reference and --modes: fail before any work. The runs take these jobs
    // (given references already read).
    std::vector<SceneJob> jobs = benchSceneJobs(suite, o);
    selectedLadders(suite, o);
    std::string resultsPath = (fs::path(o.outDir) / "results.csv").string();
    checkBenchFiles(a, jobs, resultsPath);

    BenchLog log = [&](const std::string& line) {
        if (!o.quiet) std::fprintf(stderr, "rayproc bench: %s\n", line.c_str());
    };
    SummaryContext ctx;
    ctx.suite = &suite;
    ctx.peerCsvs = o.peerCsvs;
    ctx.commandLine = commandLine(a, suiteName);
    ctx.started = utcTimestamp();
    ctx.loadAtStart = loadAverage();
    ctx.threads = o.threads;
    ctx.timeCapSeconds = o.timeCapSeconds;
    auto start = std::chrono::steady_clock::now();
    installInterruptHandler();

    if (a.reportOnly) {
        std::vector<BenchRow> rows = readResultsCsv(resultsPath);
        for (const SceneJob& job : jobs) ctx.scenes.push_back(describeSceneJob(job, suite, o));
        ctx.regenerated = true;
        writeReport(rows, ctx, o.outDir);
        return 0;
    }
    if (a.ablation) return runAblationBench(jobs, suite, o, ctx, log);
    return runCurvesBench(jobs, suite, o, resultsPath, ctx, log, start);
}

} // namespace

std::function<int()> addBenchCommand(CLI::App& app) {
    auto args = std::make_shared<BenchArgs>();
    CLI::App* cmd = app.add_subcommand(
        "bench", "Run time against error: render each scene of a suite in each mode at "
                 "increasing budgets and measure the error against a reference");
    std::string suites;
    for (const BenchSuite& s : benchSuites())
        suites += "\n  " + s.name + ": " + s.description;
    cmd->add_option("suite", args->suite, "Suite to run (default: default):" + suites);
    cmd->add_flag("--quick", args->quick, "The quick suite (about a minute): the CI smoke test");
    cmd->add_option("-o,--output", args->options.outDir,
                    "Output directory (created; default bench-results): results.csv, "
                    "<scene>.svg, summary.md; with --ablation ablation.csv, ablation.md");
    cmd->add_option("--refs", args->options.refsDir,
                    "Reference cache directory (default <output>/refs): "
                    "<scene>-<w>x<h>-path-<spp>-<hash of the scene file>.exr, rendered once");
    cmd->add_option("--scenes-dir", args->options.scenesDir,
                    "Where the suite's scene files are (default: ./scenes, else the scenes/ "
                    "next to the build directory)");
    cmd->add_option("--scene", args->options.sceneFiles,
                    "Bench this scene file instead of the suite's scenes (repeatable); the "
                    "suite's resolution, ladders and settings still apply")
        ->check(CLI::ExistingFile);
    cmd->add_option("--reference", args->options.referenceImages,
                    "Reference image (EXR/PFM/HDR/PNG) instead of the cached path render: FILE "
                    "when the run has one scene, NAME=FILE for the scene called NAME (the "
                    "results' scene column; repeatable). The scene renders at the reference's "
                    "size");
    cmd->add_option("--modes", args->options.modes,
                    "Only these of the suite's modes, comma-separated (e.g. gi,path)")
        ->delimiter(',');
    cmd->add_flag("--progressive", args->options.progressive,
                  "Instead of the ladders: each mode renders once with its defaults, passes of "
                  "1 spp until the time cap, its error measured after every pass (one "
                  "results.csv row per pass): the curve of a user's time-limited render");
    cmd->add_flag("--spectral", args->options.spectral,
                  "Render spectrally (docs/spectral.md): every mode's renders and the cached "
                  "path references (refs/<scene>-<w>x<h>-path-spectral-...; the shipped golden "
                  "images are RGB, so they are not used); --ablation refuses --spectral");
    cmd->add_option("--peer-csv", args->options.peerCsvs,
                    "Results of another renderer, columns as results.csv (repeatable): added to "
                    "the plots and tables as their own modes")
        ->check(CLI::ExistingFile);
    cmd->add_option("--threads", args->options.threads, "Engine threads (default: all cores)")
        ->check(CLI::Range(1, 1024));
    cmd->add_option("--time-cap", args->options.timeCapSeconds,
                    "Seconds: a ladder stops before a render predicted to take longer; with "
                    "--progressive, each render's time limit (default: the suite's, 24 for "
                    "default, 4 for quick, 120 for public)")
        ->check(finiteNumber())
        ->check(CLI::PositiveNumber);
    cmd->add_flag("--ablation", args->ablation,
                  "Instead of the ladders: render each optimisation (packets, irradiance cache, "
                  "precomputed irradiance and its laziness, photon rounds, direct light at "
                  "gather hits, caustic map, progressive caustics, glossy MIS, diffuse MIS, light "
                  "choice, Russian roulette, stratification) on and off at one budget and report "
                  "what it buys in time and error");
    cmd->add_flag("--report-only", args->reportOnly,
                  "Render nothing: rewrite the plots and summary.md from <output>/results.csv "
                  "(and --peer-csv files)");
    cmd->add_flag("--quiet,-q", args->options.quiet, "No progress lines on stderr");
    cmd->footer(
        "Budgets: each mode renders a geometric spp ladder (one render per budget, seed 1), "
        "stopping before a render predicted to exceed the suite's time cap; gi also sweeps its "
        "gather rays, irradiance-cache accuracy and photon count, and its curve is the best "
        "setting at each time. Times are wall time of the mode's whole render (gi's photon "
        "passes and cache prepass included). Error: relMSE and RMSE against a path-mode reference "
        "with its own seed: the golden image of tests/golden/ where the suite names one at its "
        "resolution (default: 8192 spp), else rendered at the suite's reference spp and cached "
        "in --refs, or --reference FILE. With --progressive each mode renders once under a time "
        "limit of the time cap and its error is read after every pass (the clock stopped "
        "meanwhile). results.csv is written row by row, so "
        "Ctrl-C, SIGTERM or SIGHUP keeps every finished render (and still writes the report).\n"
        "Exit status: 0 done, 1 bad input or I/O error, 130 interrupted by Ctrl-C, 143 by "
        "SIGTERM, 129 by SIGHUP.");
    return [args] { return runBench(*args); };
}

} // namespace rayproc::cli
