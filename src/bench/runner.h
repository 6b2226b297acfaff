// The bench runner: for each scene of a suite, each mode (and for gi each swept setting) renders
// its budget ladder, measures each image against the scene's reference, and appends one row
// per render to results.csv as it finishes.
#pragma once

#include "bench/bench_scene.h"
#include "bench/results_csv.h"
#include "bench/suite.h"

#include <functional>
#include <string>
#include <vector>

namespace rayproc::bench {

struct BenchOptions {
    std::string outDir = "bench-results";
    std::string refsDir;                 // empty: <outDir>/refs
    std::string scenesDir;               // where the suite's scene files are
    std::vector<std::string> sceneFiles; // --scene: instead of the suite's scenes
    // --reference: FILE for a run of one scene, or NAME=FILE for the scene of that name; a
    // given reference sets the size its scene renders at.
    std::vector<std::string> referenceImages;
    std::vector<std::string> modes;      // --modes: a subset of the suite's, empty = all
    bool progressive = false;            // --progressive: runProgressive instead of the ladders
    std::vector<std::string> peerCsvs;   // --peer-csv
    int threads = 0;                     // engine threads, 0 = all cores
    double timeCapSeconds = 0;           // > 0: instead of the suite's
    // --spectral: every render spectral, every mode's (docs/spectral.md), the cached
    // references too (the shipped golden images, RGB renders, are passed over).
    bool spectral = false;
    bool quiet = false;
};

// One prepared scene's facts the report needs (the scene and BVH themselves are released).
struct SceneInfo {
    std::string name, file;
    int nativeWidth = 0, nativeHeight = 0;
    int width = 0, height = 0; // the render size (and the reference's)
    std::string referencePath;
    ReferenceSource referenceSource = ReferenceSource::Cache;
    int referenceSpp = 0; // 0: unknown (given with --reference)
    bool referenceSpectral = false;
    bool referenceRendered = false;
    double referenceSeconds = 0;
};

struct LadderRun {
    std::vector<SceneInfo> scenes;
    std::vector<BenchRow> rows;
    bool interrupted = false;
};

// Progress lines ("cornell-box path spp=16: 0.52 s, relMSE 0.0123") for the command to print.
using BenchLog = std::function<void(const std::string&)>;

// The scenes to bench: the --scene files (at the suite's size), or the suite's under
// scenesDir (each at renderSize), each with its reference (--reference, a shipped one that
// exists, else the cache). Throws InputError naming the path of a missing scene file.
std::vector<SceneJob> benchSceneJobs(const BenchSuite& suite, const BenchOptions& options);

// Prepares a scene for the suite (reference included), logging a reference render.
BenchScene prepareForSuite(const SceneJob& job, const BenchSuite& suite,
                           const BenchOptions& options, const BenchLog& log);
SceneInfo sceneInfo(const BenchScene& scene);
// The same without rendering anything (for --report-only): the scene file is read for its
// resolution, the reference is named as the run would find it.
SceneInfo describeSceneJob(const SceneJob& job, const BenchSuite& suite,
                           const BenchOptions& options);

// "WxH" when every scene renders at that size (the suite's when there are none), else empty:
// the report then gives each scene's size.
std::string commonRenderSize(const std::vector<SceneInfo>& scenes, const BenchSuite& suite);

// The time a render at `nextSpp` is expected to take, from the last two renders of its ladder:
// a fixed cost plus a cost per sample (gi's photon pass and cache prepass are the fixed part).
// With no earlier render (prevSpp 0), time in proportion to the samples.
double predictSeconds(int prevSpp, double prevSeconds, int spp, double seconds, int nextSpp);

// Each scene of `jobs` (benchSceneJobs) in turn: prepared (prepareForSuite), its SceneInfo
// appended to `scenes`, then body(scene). Returns false, skipping the rest, when a reference
// render was interrupted or body returns false (it was interrupted).
bool forEachBenchScene(const std::vector<SceneJob>& jobs, const BenchSuite& suite,
                       const BenchOptions& options, const BenchLog& log,
                       std::vector<SceneInfo>& scenes,
                       const std::function<bool(const BenchScene&)>& body);

// The suite's ladders, only those of options.modes when it names some. Throws InputError
// naming a mode the suite does not have.
std::vector<ModeLadder> selectedLadders(const BenchSuite& suite, const BenchOptions& options);

// Renders every ladder of the suite; stops early (interrupted = true) on Ctrl-C, keeping the
// rows of the renders that completed.
LadderRun runLadders(const std::vector<SceneJob>& jobs, const BenchSuite& suite,
                     const BenchOptions& options, ResultsCsvWriter& results, const BenchLog& log);

// --progressive: each mode renders once with its defaults (gi: the suite's first setting),
// passes of 1 spp under a time limit of the time cap, and its error against the reference is
// measured after every pass (the clock stopped meanwhile, as for `render --error-log`): one row
// per pass, settings "spp=N ... time-limit=T", seconds from the start of the mode's work, rays
// those of the render passes so far. One render gives the whole curve, so the time to an error
// is read at pass resolution, and gi pays its photon pass and cache prepass once, as a user's
// render does.
LadderRun runProgressive(const std::vector<SceneJob>& jobs, const BenchSuite& suite,
                         const BenchOptions& options, ResultsCsvWriter& results,
                         const BenchLog& log);

} // namespace rayproc::bench
