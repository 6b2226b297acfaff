#include "accel/embree_scene.h"
#include "cli/commands.h"
#include "cli/output_paths.h"
#include "cluster/cluster.h"
#include "core/error.h"
#include "engine/cancel.h"
#include "engine/film.h"
#include "engine/intersect.h"
#include "engine/memory_budget.h"
#include "engine/phases.h"
#include "engine/thread_budget.h"
#include "image/display_client.h"
#include "image/image.h"
#include "image/metrics.h"
#include "modes/mode_options.h"
#include "modes/mode_registry.h"
#include "modes/modes.h"
#include "modes/render_watch.h"
#include "scene/scene_loader.h"

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <vector>

namespace rayproc::cli {

void printError(const std::string& message) {
    // In a distributed render the other ranks name themselves: their error may be theirs alone.
    const Cluster& cluster = Cluster::world();
    if (cluster.root())
        std::fprintf(stderr, "rayproc: %s\n", message.c_str());
    else
        std::fprintf(stderr, "rayproc (%s): %s\n", cluster.name().c_str(), message.c_str());
}

namespace {

// The samples per pixel a --target-relmse render may take without --spp: the --spp limit.
constexpr int kTargetSppCap = 1000000;

struct RenderArgs {
    std::string scene;
    std::string output;
    std::string mode;
    int spp = 0, threads = 0, width = 0, height = 0, maxDepth = 0, lightSamples = 0;
    long long seed = -1;
    int packetWidth = 16;
    bool quiet = false, stats = false, progressive = false;
    double progressiveSeconds = 5.0;
    std::string statsJson;
    float exposure = 0;
    std::string tonemap = "clamp";
    std::string reference, errorLog;
    std::string displayServer;
    double timeLimit = 0;
    double targetRelMse = 0;
    // Adaptive sampling: on with --target-relmse unless --no-adaptive, on with --adaptive.
    bool adaptive = false, noAdaptive = false;
    int adaptiveMinSpp = 16;
    std::string debugView = "none";
    // profiling switches
    bool noSceneAnalysis = false, noStratification = false, noRoulette = false;
    bool noGlossyMis = false, noDiffuseMis = false, noSkyCompensation = false;
    bool spectral = false, noSpectral = false;
    bool noLightChoice = false;
    std::string coatModel; // --coat-model: every coateddiffuse's model; empty: the scene's
    // Each mode's own options (modes/mode_options.h), in the registry's order; the options
    // above are every mode's, or several modes' (modes/mode_registry.h says which go where).
    std::vector<std::unique_ptr<ModeOptions>> modeOptions;
};

// --mode's help: every registered mode with its description.
std::string modeHelp() {
    std::string s = "Rendering mode: ";
    const std::vector<ModeEntry>& modes = modeRegistry();
    for (std::size_t i = 0; i < modes.size(); ++i) {
        if (i > 0) s += i + 1 < modes.size() ? ", " : " or ";
        s += std::string(modes[i].name) + " (" + modes[i].description + ")";
    }
    return s + ". Default: the scene's render.mode, else " + defaultMode();
}

// The files a render reads and writes, for checkDistinctFiles.
std::vector<NamedPath> renderFiles(const RenderArgs& a, const std::string& output) {
    return {{"scene", a.scene, false},
            {"--reference", a.reference, false},
            {a.output.empty() ? "the output (default)" : "-o", output, true},
            {"--stats-json", a.statsJson, true},
            {"--error-log", a.errorLog, true}};
}

// Every file the render will write is checked before the scene loads: an output that cannot
// be written, or that would overwrite an input, fails now, not after the render. Returns the
// files the command reads and writes (the scene's images are added once it is loaded).
std::vector<NamedPath> checkRenderFiles(const RenderArgs& a, const std::string& output,
                                        bool writer) {
    imageFormatFromPath(output); // throws for an unknown extension
    if (!a.reference.empty() && a.errorLog.empty())
        throw InputError("--reference needs --error-log FILE");
    if (a.reference.empty() && !a.errorLog.empty())
        throw InputError("--error-log needs --reference IMAGE");
    if (!a.displayServer.empty()) checkDisplayServer(a.displayServer);
    if (a.debugView == "noise" && imageFormatFromPath(output) != ImageFormat::Exr)
        throw InputError("--debug-view noise writes its layers beside the image in an OpenEXR "
                         "file: give -o a name ending in .exr (not " + output + ")");
    std::vector<NamedPath> files = renderFiles(a, output);
    checkDistinctFiles(files);
    if (writer) {
        checkOutputFile(a.output.empty() ? "the output (default)" : "-o", output);
        checkOutputFile("--stats-json", a.statsJson);
        checkOutputFile("--error-log", a.errorLog);
        // What a run killed while writing this output (kill -9) left: its temporary files.
        std::size_t stale = removeStaleTemporaries(output);
        if (stale > 0 && !a.quiet)
            std::fprintf(stderr, "rayproc: removed %zu temporary file(s) of %s left by a run "
                                 "that was killed\n", stale, output.c_str());
    }
    return files;
}

// The scene, its images checked against the outputs, at the command line's size.
std::unique_ptr<Scene> loadRenderScene(const RenderArgs& a, std::vector<NamedPath>& files,
                                       PhaseLog& phases) {
    PhaseTimer loadPhase(&phases, "scene_load");
    std::unique_ptr<Scene> scene = loadScene(a.scene);
    loadPhase.stop();
    // The images the scene reads (textures, the sky) are inputs too, known once it is loaded.
    for (const std::string& image : scene->imageFiles())
        files.push_back({"the scene's image", image, false});
    checkDistinctFiles(files);
    if (a.width > 0) scene->camera.width = a.width;
    if (a.height > 0) scene->camera.height = a.height;
    Material::CoatModel model;
    if (coatModelNamed(a.coatModel, model)) // CLI11 admits only the known names
        for (Material& m : scene->materials) m.coatModel = model;
    // Each side is range-checked by CLI11; the product must also stay within the scene limit.
    long long pixels = (long long)scene->camera.width * scene->camera.height;
    if (pixels > kMaxImagePixels)
        throw InputError("--width/--height: image too large: " +
                         std::to_string(scene->camera.width) + " x " +
                         std::to_string(scene->camera.height) + " pixels exceeds the limit of " +
                         std::to_string(kMaxImagePixels) + " (2^26) pixels");
    return scene;
}

// The mode the render runs: the command line's, the scene's, or the default; with the
// debug views only their own mode has.
std::string renderModeOf(const RenderArgs& a, const Scene& scene) {
    std::string mode = !a.mode.empty() ? a.mode
                       : !scene.render.mode.empty() ? scene.render.mode
                                                    : defaultMode();
    if (!findMode(mode))
        throw InputError("unknown mode '" + mode + "'; known modes: " + modeNameList(", "));
    if (a.debugView == "noise" && mode != "path")
        throw InputError("--debug-view noise is path mode's (the render's mode is " + mode + ")");
    if (a.debugView != "none" && a.debugView != "noise" && mode != "gi")
        throw InputError("--debug-view " + a.debugView + " is gi mode's (the render's mode is " +
                         mode + ")");
    return mode;
}

// A sampling switch that the mode's stages do not read changes nothing: said, not refused (a
// script may give every mode the same switches).
void warnUnreadSwitches(const std::string& mode, const EngineSettings& engine) {
    const ModeEntry& entry = *findMode(mode);
    std::size_t count = 0;
    const EngineSwitchName* names = engineSwitchNames(count);
    for (std::size_t i = 0; i < count; ++i) {
        if (engine.*names[i].on || (entry.engineSwitches & names[i].flag)) continue;
        std::string readers;
        for (const ModeEntry& m : modeRegistry())
            if (m.engineSwitches & names[i].flag)
                readers += (readers.empty() ? "" : ", ") + std::string(m.name);
        std::fprintf(stderr, "rayproc: warning: --no-%s changes nothing in %s mode (%s read it)\n",
                     names[i].word, mode.c_str(), readers.c_str());
    }
}

EngineSettings engineSettingsOf(const RenderArgs& a, const Scene& scene, int threads,
                                const Cluster& cluster) {
    EngineSettings engine;
    engine.threads = threads;
    engine.packetWidth = a.packetWidth;
    engine.seed = a.seed >= 0 ? std::uint64_t(a.seed)
                  : scene.render.seed >= 0 ? std::uint64_t(scene.render.seed)
                                           : 1;
    engine.quiet = a.quiet || !cluster.root();
    engine.sceneAnalysis = !a.noSceneAnalysis;
    engine.stratification = !a.noStratification;
    engine.glossyMis = !a.noGlossyMis;
    engine.diffuseMis = !a.noDiffuseMis;
    engine.skyCompensation = !a.noSkyCompensation;
    engine.spectral = a.noSpectral ? false : a.spectral || scene.render.spectral;
    engine.lightChoice = !a.noLightChoice;
    engine.adaptiveSampling = !a.noAdaptive && (a.adaptive || a.targetRelMse > 0);
    engine.adaptiveMinSpp = a.adaptiveMinSpp;
    return engine;
}

// The render's stops, its noise layers, its processes and its phase log; the watchers and the
// error log are added below when asked for.
RenderControl renderControlOf(const RenderArgs& a, const Cluster& cluster, PhaseLog& phases) {
    RenderControl control;
    control.cluster = &cluster;
    control.timeLimitSeconds = a.timeLimit;
    control.targetRelMse = a.targetRelMse;
    control.noiseBreakdown = a.debugView == "noise";
    control.phases = &phases;
    return control;
}

ToneMapSettings toneMapOf(const RenderArgs& a) {
    ToneMapSettings tm;
    tm.exposure = a.exposure;
    tm.op = a.tonemap == "reinhard" ? ToneMap::Reinhard
            : a.tonemap == "aces"   ? ToneMap::Aces
                                    : ToneMap::Clamp;
    return tm;
}

// --progressive: the image written every few seconds. A failed progressive write must not end
// the render: warn once, keep rendering; the final write reports its own failure.
void writeProgressively(const RenderArgs& a, const std::string& output, const ToneMapSettings& tm,
                        RenderControl& control) {
    control.progressiveSeconds = a.progressiveSeconds;
    control.onProgress = [output, tm, warned = false](const Image& img) mutable {
        try {
            writeImage(output, img, tm);
        } catch (const ImageIoError& e) {
            if (!warned) std::fprintf(stderr, "rayproc: warning: %s; rendering goes on\n", e.what());
            warned = true;
        }
    };
}

// --reference: read and checked against the render's size; the error log compares with it.
void loadReference(const RenderArgs& a, const Scene& scene, Image& reference,
                   RenderControl& control) {
    reference = readImage(a.reference);
    if (reference.width != scene.camera.width || reference.height != scene.camera.height)
        throw InputError(a.reference + ": the reference is " + std::to_string(reference.width) +
                         "x" + std::to_string(reference.height) + " but the render is " +
                         std::to_string(scene.camera.width) + "x" +
                         std::to_string(scene.camera.height));
    // Left out of the error log as diff leaves them out; none finite is an error.
    std::size_t bad = nonFiniteReferencePixels(reference, a.reference);
    if (bad > 0 && !a.quiet)
        std::fprintf(stderr,
                     "rayproc: warning: --reference: %zu pixels are NaN or infinite; the "
                     "error log leaves them out\n",
                     bad);
    control.reference = &reference;
    control.errorLogPath = a.errorLog;
}

std::unique_ptr<EmbreeScene> buildAccel(const RenderArgs& a, const Scene& scene,
                                        PhaseLog& phases, bool writer) {
    std::unique_ptr<EmbreeScene> built;
    PhaseTimer bvhPhase(&phases, "bvh_build", PhaseKind::Parallel); // Embree's builder: TBB
    try {
        built = std::make_unique<EmbreeScene>(scene);
    } catch (const InputError& e) {
        throw InputError(a.scene + ": " + e.what()); // the range checks name no file
    }
    bvhPhase.stop();
    if (writer && scene.lights.empty() && built->emitters().empty())
        std::fprintf(stderr, "rayproc: warning: %s has no lights; the image will be black\n",
                     a.scene.c_str());
    return built;
}

// --display-server: the image in the tev viewer, refreshed every second while the passes run
// and once at the end. A viewer that is not there is a warning, not a failed render.
struct TevDisplay {
    std::unique_ptr<DisplayClient> client;
    std::unique_ptr<PeriodicReport> report;

    void connect(const std::string& server, const std::string& output, RenderControl& control) {
        client = std::make_unique<DisplayClient>(server,
                                                 std::filesystem::path(output).filename().string());
        if (!client->connected()) {
            std::fprintf(stderr, "rayproc: warning: --display-server: %s; rendering goes on\n",
                         client->error().c_str());
            client.reset();
            return;
        }
        DisplayClient* shown = client.get();
        report = std::make_unique<PeriodicReport>(
            1.0, [shown](Image image, const PeriodicReport::Progress&) {
                shown->show(image);
            });
        control.watcher = report->watcher();
    }
    void showFinal(const Image& image) {
        if (!client) return;
        client->show(image); // the final image, every rank's tiles
        if (!client->connected())
            std::fprintf(stderr, "rayproc: warning: --display-server: %s\n", client->error().c_str());
    }
};

// Before the long work: a render that cannot fit in memory is refused with the figures, one
// that may not fit is warned of.
void checkMemory(long long pixels, std::uint64_t photons, std::uint64_t caustic, bool writer) {
    MemoryEstimate need = estimateRenderMemory(std::uint64_t(pixels), photons, caustic, 0);
    bool fatal = false;
    std::string problem = memoryProblem(need, systemMemory(), fatal);
    if (problem.empty()) return;
    if (fatal)
        throw InputError(problem + "; lower --width/--height" +
                         (photons > 0 ? std::string(" or --photons/--caustic-photons") : "") +
                         " (docs/robustness.md, \"Memory\")");
    if (writer) std::fprintf(stderr, "rayproc: warning: %s\n", problem.c_str());
}

// The mode's settings (each mode reads its own) with the command line's options, logged so the
// image can be reproduced, checked against the memory, then the render.
RenderResult renderWithMode(const RenderArgs& a, const Scene& scene, const EmbreeScene& accel,
                            const std::string& mode, const EngineSettings& engine,
                            const RenderControl& control) {
    // With an error target and no --spp, samples go on until the target (or the time limit,
    // or Ctrl-C) stops them.
    int sppCap = a.spp > 0 ? a.spp : a.targetRelMse > 0 ? kTargetSppCap : 0;
    ModeOverrides overrides{sppCap, a.maxDepth, a.lightSamples, !a.noRoulette, a.debugView};
    installInterruptHandler();
    const ModeEntry& entry = *findMode(mode);
    ModeSettings settings = ModeSettings::forScene(scene, overrides);
    for (const std::unique_ptr<ModeOptions>& options : a.modeOptions) options->apply(settings);
    const Cluster& cluster = control.clusterOrAlone();
    if (!engine.quiet)
        std::fprintf(stderr, "rayproc render %s: %s %s%s %dx%d\n", a.scene.c_str(),
                     entry.describe(settings).c_str(), engine.toString().c_str(),
                     cluster.distributed()
                         ? (" ranks=" + std::to_string(cluster.size())).c_str()
                         : "",
                     scene.camera.width, scene.camera.height);
    const auto [photons, causticPhotons] = entry.photons(settings);
    checkMemory((long long)scene.camera.width * scene.camera.height, photons, causticPhotons,
                cluster.root());
    RenderResult result = entry.render(scene, accel, settings, engine, control);
    // The job's communication, summed over the ranks (a collective; zero for one process).
    std::vector<std::uint64_t> sent{cluster.bytesSent()};
    cluster.sumToRoot(sent);
    if (cluster.distributed()) {
        result.stats.extras.push_back({"cluster/ranks", double(cluster.size())});
        result.stats.extras.push_back({"cluster/bytes_sent", double(sent[0])});
    }
    return result;
}

// What the render reached and what it could not hold, said on stderr.
void reportOutcome(const RenderArgs& a, const RenderResult& result) {
    if (a.targetRelMse > 0 && !a.quiet)
        std::fprintf(stderr,
                     "rayproc: relMSE estimate %.4g (target %g) %s after %d spp (%.2f s)\n",
                     result.relMseEstimate, a.targetRelMse,
                     result.targetReached ? "reached" : "not reached", result.samplesDone,
                     result.stats.wallSeconds);
    if (result.timeLimitReached && !a.quiet)
        std::fprintf(stderr, "rayproc: time limit of %g s reached after %d spp (%.2f s)\n",
                     a.timeLimit, result.samplesDone, result.stats.wallSeconds);
    // Radiance the film could not hold is said, not silently changed.
    if (result.stats.totals.clampedSamples > 0)
        std::fprintf(stderr,
                     "rayproc: warning: %llu contributions beyond the film's range (|radiance| > "
                     "%.3g) were clamped to it; the image is darker than the scene there\n",
                     (unsigned long long)result.stats.totals.clampedSamples, result.filmLimit);
    if (result.stats.totals.invalidSamples > 0)
        std::fprintf(stderr,
                     "rayproc: warning: %llu NaN or infinite contributions were discarded\n",
                     (unsigned long long)result.stats.totals.invalidSamples);
}

// The image, the statistics, and the exit status; stdout carries only the image's location,
// so scripts can capture it.
int writeRenderOutputs(const RenderArgs& a, const std::string& output, const ToneMapSettings& tm,
                       RenderResult& result, PhaseLog& phases, int threads,
                       std::chrono::steady_clock::time_point processStart) {
    PhaseTimer writePhase(&phases, "image_write");
    if (!result.layers.empty())
        writeExrWithLayers(output, result.image, result.layers);
    else
        writeImage(output, result.image, tm);
    writePhase.stop();
    result.stats.phases = phases.phases();
    result.stats.processSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - processStart).count();
    result.stats.threads = threads > 0 ? threads : tbb::this_task_arena::max_concurrency();
    if (a.stats) std::fputs(result.stats.toTable().c_str(), stderr);
    if (!a.statsJson.empty()) writeFileAtomically(a.statsJson, result.stats.toJson() + "\n");
    const std::string where = std::filesystem::absolute(output).string();
    if (!result.errorLogFailure.empty()) {
        printError(result.errorLogFailure + " (the image was written)");
        std::printf("%s\n", where.c_str());
        return 1;
    }
    if (result.cancelled) {
        std::fprintf(stderr,
                     "rayproc: interrupted: wrote the partial image (%zu pixels had no sample)\n",
                     result.stats.pixelsWithoutSamples);
        std::printf("%s\n", where.c_str());
        return interruptExitStatus();
    }
    std::printf("%s\n", where.c_str());
    return 0;
}

int runRender(const RenderArgs& a) {
    // Where the command's time goes (--stats, --stats-json "phases"; engine/phases.h).
    const auto processStart = std::chrono::steady_clock::now();
    PhaseLog phases;
    LoopLog::Scope namedLoops(&phases); // this thread's named loops are phases of their own
    // Under mpirun every rank runs this with the same arguments; rank 0 writes the files
    // (docs/distributed.md), the others render their share quietly.
    const Cluster& cluster = Cluster::world();
    const bool writer = cluster.root();
    if (!writer) quietInterruptMessages();
    std::string output = a.output;
    if (output.empty()) output = std::filesystem::path(a.scene).stem().string() + ".png";
    std::vector<NamedPath> files = checkRenderFiles(a, output, writer);

    // Under an address-space limit, no more threads than their stacks fit in: TBB aborts the
    // process when it cannot create one (engine/thread_budget.h).
    const ThreadBudget budget = applyThreadBudget(a.threads);
    if (writer && !budget.warning.empty())
        std::fprintf(stderr, "rayproc: warning: %s\n", budget.warning.c_str());
    tbb::global_control stackSize(tbb::global_control::thread_stack_size, kWorkerStackBytes);
    // --threads bounds every phase, not only the ray processor's: the BVH build, photon map
    // builds, precomputation and sorts run in TBB's global arena (and so do, under mpirun,
    // the ranks that share a machine).
    std::optional<tbb::global_control> threadLimit;
    if (budget.threads > 0)
        threadLimit.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(budget.threads));
    std::unique_ptr<Scene> scene = loadRenderScene(a, files, phases);
    const std::string mode = renderModeOf(a, *scene);
    const EngineSettings engine = engineSettingsOf(a, *scene, budget.threads, cluster);
    if (writer) warnUnreadSwitches(mode, engine);
    RenderControl control = renderControlOf(a, cluster, phases);
    const ToneMapSettings tm = toneMapOf(a);
    if (a.progressive && writer) writeProgressively(a, output, tm, control);
    Image reference;
    if (!a.reference.empty()) loadReference(a, *scene, reference, control);
    std::unique_ptr<EmbreeScene> accel = buildAccel(a, *scene, phases, writer);
    TevDisplay display;
    if (writer && !a.displayServer.empty()) display.connect(a.displayServer, output, control);

    RenderResult result = renderWithMode(a, *scene, *accel, mode, engine, control);
    if (!writer) return result.cancelled ? interruptExitStatus() : 0;
    reportOutcome(a, result);
    display.showFinal(result.image);
    // Interrupted before any pixel had a sample (gi's photon pass or cache prepass): an image
    // of nothing must not replace what the output held.
    const std::size_t pixels = std::size_t(scene->camera.width) * std::size_t(scene->camera.height);
    if (result.cancelled && result.stats.pixelsWithoutSamples >= pixels) {
        std::fprintf(stderr, "rayproc: interrupted before any pixel had a sample: nothing was "
                             "written (%s is as it was)\n", output.c_str());
        return interruptExitStatus();
    }
    return writeRenderOutputs(a, output, tm, result, phases, budget.threads, processStart);
}

// The scene, the output, the mode and its basic settings, the image size, PNG output.
void addSceneOptions(CLI::App* cmd, RenderArgs* args) {
    cmd->add_option("scene", args->scene, "Scene file: JSON (docs/scene-format.md) or pbrt-v4 (docs/pbrt-import.md)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("-o,--output", args->output,
                    "Output image: .png (8-bit sRGB, tone-mapped), .exr, .hdr or .pfm (linear "
                    "radiance). Default: <scene name>.png in the current directory");
    cmd->add_option("--mode", args->mode, modeHelp());
    cmd->add_flag("--spectral", args->spectral,
                  "Render spectrally: three hero wavelengths per path, the scene's RGB colours "
                  "upsampled as pbrt-v4 does, XYZ to linear sRGB at the film (docs/spectral.md; "
                  "every mode; default: the scene's render.spectral)");
    cmd->add_flag("--no-spectral", args->noSpectral,
                  "Render in RGB even where the scene's render.spectral asks for spectra")
        ->excludes("--spectral");
    cmd->add_option("--coat-model", args->coatModel,
                    "How every coateddiffuse material is evaluated: auto (the closed form unless "
                    "its medium scatters), analytic, or random-walk (pbrt-v4's stochastic layered "
                    "evaluation, its maxdepth and nsamples; slower and noisier, as pbrt-v4 "
                    "defines it: docs/spectral.md, \"Coffee's orange\"). Default: each "
                    "material's own (a JSON scene's \"model\", else auto)")
        ->check(CLI::IsMember({"auto", "analytic", "random-walk"}));
    cmd->add_option("--spp", args->spp, "Samples per pixel (default: the mode's, or the scene's)")
        ->check(CLI::Range(1, 1000000));
    cmd->add_option("--threads", args->threads, "Worker threads, for every phase (default: all cores; under mpirun: per rank)")
        ->check(CLI::Range(1, 1024));
    cmd->add_option("--seed", args->seed,
                    "Random seed; the same seed, scene and options give the same image whatever "
                    "the thread count (default 1)")
        ->check(CLI::Range(0LL, (1LL << 62)));
    cmd->add_option("--width", args->width, "Override the image width")->check(CLI::Range(1, 16384));
    cmd->add_option("--height", args->height, "Override the image height")->check(CLI::Range(1, 16384));
    cmd->add_option("--max-depth", args->maxDepth,
                    "Maximum bounces (raytrace default 8, preview 1, path 64)")
        ->check(CLI::Range(1, 255));
    cmd->add_option("--light-samples", args->lightSamples,
                    "Stratified light samples per shading point, and of the sky (raytrace: "
                    "default 4; gi: default 2, whose cheaper passes reach a given error "
                    "sooner): with several area lights, that many per light that matters at "
                    "the point, each choosing one (see --no-light-choice); one more per "
                    "point, spot or distant light")
        ->check(CLI::Range(1, 4096));
    cmd->add_option("--packet-width", args->packetWidth,
                    "Embree traversal: 1 = single rays (rtcIntersect1), 4/8/16 = packets "
                    "(default 16). Every width gives the same image, except where a ray meets "
                    "two surfaces at the same distance to within float rounding (coplanar or "
                    "touching geometry): which one it hits then follows the traversal order")
        ->check(CLI::IsMember({1, 4, 8, 16}));
    cmd->add_option("--exposure", args->exposure, "Exposure in stops for PNG output (default 0)")
        ->check(finiteFloat());
    cmd->add_option("--tonemap", args->tonemap, "PNG tone map: clamp (default), reinhard, aces")
        ->check(CLI::IsMember({"clamp", "reinhard", "aces"}));
}

// The profiling switches (each an ablation) and the debug views.
void addProfilingOptions(CLI::App* cmd, RenderArgs* args) {
    cmd->add_flag("--no-scene-analysis", args->noSceneAnalysis,
                  "Run every pass and stage and sample every light, even those the scene "
                  "analysis finds cannot contribute (for comparisons and profiling)");
    cmd->add_flag("--no-stratification", args->noStratification,
                  "Independent random samples instead of stratified ones: camera sub-pixel "
                  "positions, light samples, path mode's first-hit samples, final-gather rays");
    cmd->add_flag("--no-sky-compensation", args->noSkyCompensation,
                  "path: sample an image sky by its luminance for light samples, instead of by "
                  "its excess over its mean (the part BSDF samples find as well, weighed by MIS; "
                  "pbrt-v4's allowIncompletePDF)");
    cmd->add_flag("--no-glossy-mis", args->noGlossyMis,
                  "raytrace, gi: light glossy surfaces (rough metals and glass, rough coats) by "
                  "light samples alone instead of combining them with the sampled reflection "
                  "ray by multiple importance sampling (much noisier highlights of small or "
                  "near-mirror lobes)");
    cmd->add_flag("--no-diffuse-mis", args->noDiffuseMis,
                  "raytrace, gi: light diffuse surfaces from area lights by light samples alone "
                  "instead of combining them with one cosine-sampled ray per hit that collects "
                  "emission, by multiple importance sampling (fireflies on surfaces close to a "
                  "small light)");
    cmd->add_flag("--no-light-choice", args->noLightChoice,
                  "raytrace, gi: with several area lights, take --light-samples samples of "
                  "every one of them at each hit instead of --light-samples per light that "
                  "matters there, each choosing a light with path mode's light sampler (by "
                  "what its power, extent and emission cone can give the point; slower per "
                  "sample in scenes of many lights)");
    cmd->add_flag("--no-russian-roulette", args->noRoulette,
                  "raytrace, path, gi: paths (and gi's photons) end only at the maximum depth "
                  "or at zero throughput");
    cmd->add_option("--debug-view", args->debugView,
                    "gi: a diagnostic image instead of the render: photons (the global + caustic "
                    "maps' radiance estimate at first diffuse hits, nothing else), ic-records "
                    "(the render at 1/4 radiance with every cache record's projected position "
                    "marked magenta, radiance (4, 0, 4)), caustics (caustic map only), indirect "
                    "(irradiance cache / final gather only). path: noise (the render, and beside "
                    "it in the .exr output per pixel where the noise comes from: for each "
                    "strategy, direct, caustic, light-samples, light-hits, sky-samples and "
                    "sky-hits, the layer noise.<strategy> (its variance per sample over the "
                    "pixel's squared mean + 0.01, so the layers add up to about the pixel's "
                    "relMSE times its spp) and mean.<strategy> (its luminance); "
                    "docs/performance.md)")
        ->check(CLI::IsMember({"none", "photons", "ic-records", "caustics", "indirect", "noise"}));
}

// The reference and the error log, the stops (target, adaptive, time limit), the watchers and the statistics.
void addRunOptions(CLI::App* cmd, RenderArgs* args) {
    cmd->add_option("--reference", args->reference,
                    "Reference image (PNG/EXR/HDR/PFM, same size) for the convergence log")
        ->check(CLI::ExistingFile);
    cmd->add_option("--error-log", args->errorLog,
                    "With --reference: after each pass append 'spp,seconds,relmse,rmse' to this "
                    "CSV file (seconds count from the start of the mode's work, gi's photon "
                    "tracing, precomputation and cache prepass included, and exclude the time "
                    "spent measuring the error)");
    cmd->add_option("--target-relmse", args->targetRelMse,
                    "Render passes of 1 spp until the relMSE estimated from two half buffers "
                    "(alternate passes; no reference needed) is at most this, e.g. 0.01; "
                    "without --spp the samples are not capped. The variance part only, and in gi "
                    "only the noise that differs between the halves (the cache records'): the "
                    "photon map and the records' positions are common to both, so gi's error "
                    "can be several times the target (the classroom: 3.4x). Stops at "
                    "--time-limit too. Adaptive sampling is on unless --no-adaptive")
        ->check(finiteNumber())
        ->check(CLI::PositiveNumber);
    cmd->add_flag("--adaptive", args->adaptive,
                  "Adaptive sampling: after --adaptive-min-spp samples in every pixel, pairs of "
                  "passes go to the pixels whose noise (estimated from two half buffers) needs "
                  "them, as n proportional to the square root of the pixel's noise per sample "
                  "(the least image relMSE for the samples); --spp is then the mean over the "
                  "image, and no pixel takes more than 16 times it. On with --target-relmse "
                  "(where --spp caps each pixel)");
    cmd->add_flag("--no-adaptive", args->noAdaptive,
                  "Uniform sampling under --target-relmse: every pixel takes every pass")
        ->excludes("--adaptive");
    cmd->add_option("--adaptive-min-spp", args->adaptiveMinSpp,
                    "Samples every pixel takes before adaptive sampling decides (default 16)")
        ->check(CLI::Range(2, 1 << 20));
    cmd->add_option("--time-limit", args->timeLimit,
                    "Stop after the first pass that ends past SECONDS (counted like the error "
                    "log's, gi's pre-passes included); passes are then 1 spp and --spp is the "
                    "upper bound (give a large one). Progress and ETA follow the budget; the "
                    "log reports the spp done")
        ->check(finiteNumber())
        ->check(CLI::PositiveNumber);
    cmd->add_option("--display-server", args->displayServer,
                    "Show the image in the tev HDR viewer while rendering: HOST:PORT of its "
                    "display server (tev listens on 127.0.0.1:14158 by default), refreshed every "
                    "second and at the end; an unreachable viewer is a warning");
    cmd->add_flag("--quiet,-q", args->quiet, "No progress and no render log on stderr");
    cmd->add_flag("--stats", args->stats,
                  "Print per-stage statistics on stderr at the end, then each phase's wall time "
                  "(scene load, BVH build, photon passes, cache prepass, render passes, film "
                  "resolve, image write), how it ran, the workers' busy fraction and the serial "
                  "fraction; path mode adds where the "
                  "image and its noise come from: per light (and the sky) its light samples' and "
                  "its BSDF-found emission's share of the image, of the contributions' summed "
                  "squares, and the largest contribution");
    cmd->add_option("--stats-json", args->statsJson, "Write the statistics as JSON to this file");
    cmd->add_flag("--progressive-output", args->progressive,
                  "Rewrite the output image while rendering (atomically, between passes)");
    cmd->add_option("--progressive-interval", args->progressiveSeconds,
                    "Seconds between progressive writes (default 5)")
        ->check(finiteNumber())
        ->check(CLI::PositiveNumber);
    cmd->footer("Exit status: 0 done, 1 bad input or I/O error, 130 interrupted by Ctrl-C, 143 by "
                "SIGTERM, 129 by SIGHUP (each writes the partial image, or nothing before the first "
                "sample; a second signal exits at once).");
}

// Each mode's own options under a heading of its own in --help, after the options every mode
// has. A heading (Option::group through the defaults), not a CLI11 option group: those are
// nameless subcommands, and CLI11 2.1.2 took an empty argument ("") for one and looped forever
// (the CLI fuzzer's finding).
void addModeOptions(CLI::App* cmd, RenderArgs* args) {
    const std::string common = cmd->option_defaults()->get_group();
    for (const ModeEntry& mode : modeRegistry()) {
        if (!mode.options) continue;
        std::unique_ptr<ModeOptions> options = mode.options();
        cmd->option_defaults()->group(std::string(mode.name) + " options");
        options->add(*cmd);
        args->modeOptions.push_back(std::move(options));
    }
    cmd->option_defaults()->group(common);
}

} // namespace

std::function<int()> addRenderCommand(CLI::App& app) {
    auto args = std::make_shared<RenderArgs>();
    CLI::App* cmd = app.add_subcommand("render", "Render a scene to an image");
    // In this order in --help.
    addSceneOptions(cmd, args.get());
    addProfilingOptions(cmd, args.get());
    addRunOptions(cmd, args.get());
    addModeOptions(cmd, args.get());
    return [args] { return runRender(*args); };
}

} // namespace rayproc::cli
