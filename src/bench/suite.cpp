#include "bench/suite.h"

#include "core/error.h"

namespace rayproc::bench {

namespace {

BenchSuite defaultSuite() {
    BenchSuite s;
    s.name = "default";
    s.description = "cornell-box and cornell-spheres at 128x128, every mode, gi settings swept";
    // The golden references: path, 8192 spp, seed 12345, 128x128 (tests/golden/*.args).
    s.scenes = {{"cornell-box.json", "../tests/golden/cornell-box-path.exr", 8192},
                {"cornell-spheres.json", "../tests/golden/cornell-spheres-path.exr", 8192}};
    s.width = s.height = 128;
    s.referenceSpp = 4096;
    s.timeCapSeconds = 24;
    s.ladders = {{"preview", {1, 4, 16}},
                 {"raytrace", {1, 2, 4, 8, 16, 32, 64}},
                 {"gi", {1, 2, 4, 8, 16, 32}},
                 {"path", {1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024}}};
    // One setting at a time away from gi's defaults (64 gather rays, a = 0.25, 200k photons).
    s.giVariants = {{64, 0.25f, 200000}, {16, 0.25f, 200000}, {256, 0.25f, 200000},
                    {64, 0.5f, 200000},  {64, 0.1f, 200000},  {64, 0.25f, 50000},
                    {64, 0.25f, 800000}};
    s.ablationPathSpp = 32;
    s.ablationGiSpp = 4;
    s.ablationRepeats = 3;
    return s;
}

BenchSuite quickSuite() {
    BenchSuite s;
    s.name = "quick";
    s.description = "cornell-box at 64x64, short ladders: a smoke test (CI), not a measurement";
    s.scenes = {{"cornell-box.json", "", 0}};
    s.width = s.height = 64;
    s.referenceSpp = 1024;
    s.timeCapSeconds = 4;
    s.ladders = {{"preview", {1, 4}},
                 {"raytrace", {1, 4, 16}},
                 {"gi", {1, 4, 16}},
                 {"path", {1, 4, 16, 64, 256}}};
    s.giVariants = {{32, 0.25f, 20000}, {16, 0.5f, 10000}};
    s.ablationPathSpp = 8;
    s.ablationGiSpp = 1;
    s.ablationRepeats = 1;
    return s;
}

// Bitterli's scenes in pbrt-v4 form, from the shared folder beside the clone (../shared; from
// scenes/ that is ../../shared). Each renders at 1/8 of its Film resolution, so its aspect is
// kept. The Tungsten renders beside them are not the references: for several scenes they
// disagree with the pbrt-v4 files (docs/public-scenes.md), so the references are rayproc's own
// path renders, cached in --refs.
BenchSuite publicSuite() {
    BenchSuite s;
    s.name = "public";
    // Issue 13's measure: time to relMSE 0.05 and 0.01 (0.001 is out of reach of these
    // references, whose own relMSE is about 0.0025 in the classroom by path noise's 1/N).
    s.summaryTargets = {0.05, 0.01};
    s.description = "Bitterli's pbrt-v4 scenes (cornell-box, veach-mis, coffee, classroom, "
                    "staircase2) from ../shared/scenes/bitterli at 1/8 of their resolution; "
                    "references are rayproc's own path renders at 16,384 spp, not the Tungsten "
                    "ones (docs/public-scenes.md): a few hours on 2 cores";
    const std::string dir = "../../shared/scenes/bitterli/";
    // The render size is the Film's xresolution x yresolution / 8.
    s.scenes = {{dir + "cornell-box/scene-v4.pbrt", "", 0, "cornell-box", 128, 128}, // 1024x1024
                {dir + "veach-mis/scene-v4.pbrt", "", 0, "veach-mis", 160, 90},      // 1280x720
                {dir + "coffee/scene-v4.pbrt", "", 0, "coffee", 100, 125},           // 800x1000
                {dir + "classroom/scene-v4.pbrt", "", 0, "classroom", 160, 90},      // 1280x720
                {dir + "staircase2/scene-v4.pbrt", "", 0, "staircase2", 128, 128}};  // 1024x1024
    s.width = s.height = 128; // --scene files
    // A reference's own noise adds to every error measured against it: at 2048 spp the
    // classroom's differs from a 16,384-spp one by relMSE 0.020, twice the target of 0.01.
    s.referenceSpp = 16384;
    s.timeCapSeconds = 120;
    s.ladders = {{"raytrace", {1, 2, 4, 8, 16, 32, 64}},
                 {"gi", {1, 2, 4, 8, 16, 32, 64}},
                 {"path", {1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048}}};
    // gi's defaults, then more gather rays and more photons (larger, more detailed rooms).
    s.giVariants = {{64, 0.25f, 200000}, {256, 0.25f, 200000}, {64, 0.25f, 800000}};
    s.ablationPathSpp = 32;
    s.ablationGiSpp = 4;
    s.ablationRepeats = 3;
    return s;
}

} // namespace

RenderSize renderSize(const BenchSuite& suite, const SuiteScene& scene) {
    if (scene.width > 0 && scene.height > 0) return {scene.width, scene.height};
    return {suite.width, suite.height};
}

const std::vector<BenchSuite>& benchSuites() {
    static const std::vector<BenchSuite> suites = {defaultSuite(), quickSuite(), publicSuite()};
    return suites;
}

const BenchSuite& findSuite(const std::string& name) {
    std::string known;
    for (const BenchSuite& s : benchSuites()) {
        if (s.name == name) return s;
        known += (known.empty() ? "" : ", ") + s.name;
    }
    throw InputError("unknown bench suite '" + name + "'; known suites: " + known);
}

} // namespace rayproc::bench
