// Bench suites: which scenes, at which resolution, each mode at which budgets, which gi settings
// are swept, and the reference each is measured against. A suite is data; the runner
// (runner.h) renders it.
#pragma once

#include <string>
#include <vector>

namespace rayproc::bench {

// One mode's budget ladder: one render per entry of `spp` (a geometric sequence), in order,
// until the ladder's time cap stops it.
struct ModeLadder {
    std::string mode; // preview, raytrace, gi, path
    std::vector<int> spp;
};

// One setting of gi mode swept over its ladder; the plot shows each as points and the best of
// them at each time (the lower envelope) as the gi curve.
struct GiVariant {
    int gatherRays = 64;
    float icAccuracy = 0.25f;
    // The global map's photons per round. The caustic map keeps gi's default (one photon per
    // pixel, 50,000 to 1,000,000 per pass), as `rayproc render` would use.
    int photons = 200000;
};

// A scene of a suite. A reference shipped with the source tree (the golden path images of
// tests/golden/, rendered at high spp with their own seed) is used when it exists and has the
// scene's render size; otherwise the reference cache renders one.
struct SuiteScene {
    std::string file;             // relative to the scenes directory
    std::string shippedReference; // relative to the scenes directory; may be empty
    int shippedReferenceSpp = 0;
    // The results' scene column and the plot's file name; empty: the file's stem (a name of
    // its own for files all called scene-v4.pbrt, one folder each).
    std::string name{};
    int width = 0, height = 0; // the render size; 0: the suite's
};

// The size a scene renders at (its reference too): its own, else the suite's.
struct RenderSize {
    int width = 0, height = 0;
};

struct BenchSuite {
    std::string name;
    std::string description;
    std::vector<SuiteScene> scenes;
    int width = 128, height = 128;   // every scene's render size unless the scene sets its own
    int referenceSpp = 4096;         // path mode, cached in <out>/refs (no shipped reference)
    // A ladder stops at its last budget, or before a render predicted (predictSeconds in
    // runner.h) to take longer than this.
    double timeCapSeconds = 30;
    std::vector<ModeLadder> ladders;
    std::vector<GiVariant> giVariants; // at least one
    // --ablation: the budget of each mode's with/without renders, and timing repeats (median).
    int ablationPathSpp = 16, ablationGiSpp = 4;
    int ablationRepeats = 3;
    // The relMSE targets of summary.md's "time to reach" table.
    std::vector<double> summaryTargets = {0.01, 0.001};
};

// The suites by name: "default" (about 10 minutes on 2 cores, references included), "quick"
// (about a minute: the CI smoke test) and "public" (Bitterli's pbrt-v4 scenes from
// ../shared beside the clone, at 1/8 of their resolution: hours).
const std::vector<BenchSuite>& benchSuites();
// The size `scene` renders at in `suite`: the scene's own if it sets one, else the suite's.
RenderSize renderSize(const BenchSuite& suite, const SuiteScene& scene);
// The suite called `name`; throws InputError listing the known ones.
const BenchSuite& findSuite(const std::string& name);

} // namespace rayproc::bench
