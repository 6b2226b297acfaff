// The suites' data (the public suite's scenes and sizes) and the per-scene render size: it
// overrides the suite's in the jobs, the reference cache's key, the prepared scene and the
// report. Nothing here renders a Bitterli scene (minutes each); the one render is a tiny box.
#include "bench/ablation.h"
#include "bench/runner.h"
#include "bench/summary.h"
#include "core/error.h"

#include "skip.h"
#include "test_util.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <regex>

using namespace rayproc;
using namespace rayproc::bench;
namespace fs = std::filesystem;

namespace {

struct Expected {
    std::string name;
    int width, height;
};

const Expected kPublic[] = {{"cornell-box", 128, 128},
                            {"veach-mis", 160, 90},
                            {"coffee", 100, 125},
                            {"classroom", 160, 90},
                            {"staircase2", 128, 128}};

// A suite of one copy of the Cornell box under <dir>/box/scene.json, at `width` x `height` of
// its own (0: the suite's 24x24).
BenchSuite boxSuite(const test::TempDir& dir, int width, int height) {
    fs::create_directories(dir.path / "box");
    test::writeText(dir.file("box/scene.json"), test::readText(test::scenePath("cornell-box")));
    BenchSuite s = findSuite("quick");
    s.width = s.height = 24;
    s.referenceSpp = 1;
    s.scenes = {{"box/scene.json", "", 0, "box", width, height}};
    return s;
}

// Options that find boxSuite's scene under dir and cache references in <dir>/refs.
BenchOptions boxOptions(const test::TempDir& dir) {
    BenchOptions options;
    options.scenesDir = dir.path.string();
    options.refsDir = dir.file("refs");
    return options;
}

// The Film's "integer <axis>resolution" [ N ] of a pbrt-v4 file; 0 if absent.
int filmResolution(const std::string& text, const std::string& axis) {
    std::smatch m;
    std::regex re("\"integer " + axis + "resolution\"\\s*\\[\\s*(\\d+)\\s*\\]");
    return std::regex_search(text, m, re) ? std::stoi(m[1]) : 0;
}

} // namespace

TEST_CASE("the public suite renders the five Bitterli scenes at their own sizes", "[bench]") {
    const BenchSuite& s = findSuite("public");
    REQUIRE(s.scenes.size() == std::size(kPublic));
    for (std::size_t i = 0; i < s.scenes.size(); ++i) {
        const SuiteScene& scene = s.scenes[i];
        INFO(scene.file);
        CHECK(scene.name == kPublic[i].name);
        CHECK(scene.file == "../../shared/scenes/bitterli/" + kPublic[i].name + "/scene-v4.pbrt");
        CHECK(scene.shippedReference.empty()); // rayproc's own path render, cached
        RenderSize size = renderSize(s, scene);
        CHECK(size.width == kPublic[i].width);
        CHECK(size.height == kPublic[i].height);
    }
    CHECK(s.referenceSpp == 16384);
    CHECK(s.timeCapSeconds == 120);
    bool hasPath = false, hasGi = false;
    for (const ModeLadder& l : s.ladders) {
        if (l.mode == "path") {
            hasPath = true;
            CHECK(l.spp.front() == 1);
            CHECK(l.spp.back() == 2048);
            for (std::size_t k = 1; k < l.spp.size(); ++k) CHECK(l.spp[k] == 2 * l.spp[k - 1]);
        }
        if (l.mode == "gi") hasGi = true;
    }
    CHECK(hasPath);
    CHECK(hasGi);
    REQUIRE(!s.giVariants.empty());
    GiVariant defaults;
    CHECK(s.giVariants.front().gatherRays == defaults.gatherRays);
    CHECK(s.giVariants.front().photons == defaults.photons);
    CHECK(s.description.find("hours") != std::string::npos);
}

TEST_CASE("the public suite's sizes are an eighth of the scene files' Film resolution", "[bench]") {
    // ../shared beside the checkout, as in CI; absent elsewhere.
    fs::path dir = test::sourceDir() / "scenes";
    const BenchSuite& s = findSuite("public");
    if (!fs::is_regular_file(dir / s.scenes.front().file))
        RAYPROC_SKIP("no " << (dir / s.scenes.front().file).lexically_normal().string());
    for (const SuiteScene& scene : s.scenes) {
        INFO(scene.file);
        std::string text = test::readText((dir / scene.file).string());
        RenderSize size = renderSize(s, scene);
        CHECK(filmResolution(text, "x") == 8 * size.width);
        CHECK(filmResolution(text, "y") == 8 * size.height);
    }
}

TEST_CASE("a scene's own render size overrides the suite's, both set or neither", "[bench]") {
    BenchSuite suite;
    suite.width = 64;
    suite.height = 48;
    SuiteScene scene;
    CHECK(renderSize(suite, scene).width == 64);
    CHECK(renderSize(suite, scene).height == 48);
    scene.width = 32;
    scene.height = 16;
    CHECK(renderSize(suite, scene).width == 32);
    CHECK(renderSize(suite, scene).height == 16);
    scene.height = 0; // half a size is none
    CHECK(renderSize(suite, scene).width == 64);
    CHECK(renderSize(suite, scene).height == 48);
}

TEST_CASE("the jobs and the cached reference's path take the scene's own size and name",
          "[bench]") {
    test::TempDir dir;
    BenchSuite suite = boxSuite(dir, 20, 12);
    BenchOptions options = boxOptions(dir);

    std::vector<SceneJob> jobs = benchSceneJobs(suite, options);
    REQUIRE(jobs.size() == 1);
    CHECK(jobs[0].width == 20);
    CHECK(jobs[0].height == 12);
    CHECK(sceneJobName(jobs[0]) == "box"); // not the file's stem, "scene"

    SceneInfo info = describeSceneJob(jobs[0], suite, options);
    CHECK(info.name == "box");
    CHECK(info.width == 20);
    CHECK(info.height == 12);
    CHECK(info.referencePath == referencePath(options.refsDir, jobs[0].file, 20, 12, 1, "box"));
    CHECK(fs::path(info.referencePath).filename().string().rfind("box-20x12-path-1-", 0) == 0);

    // --scene files have no size of their own: the suite's.
    options.sceneFiles = {dir.file("box/scene.json")};
    jobs = benchSceneJobs(suite, options);
    REQUIRE(jobs.size() == 1);
    CHECK(jobs[0].width == 24);
    CHECK(jobs[0].height == 24);
    CHECK(sceneJobName(jobs[0]) == "scene");
}

TEST_CASE("prepareForSuite renders the scene and its reference at the scene's own size",
          "[bench]") {
    test::TempDir dir;
    BenchSuite suite = boxSuite(dir, 8, 6);
    BenchOptions options = boxOptions(dir);
    options.quiet = true;
    std::vector<SceneJob> jobs = benchSceneJobs(suite, options);
    REQUIRE(jobs.size() == 1);
    std::vector<std::string> lines;
    BenchScene b =
        prepareForSuite(jobs[0], suite, options, [&](const std::string& l) { lines.push_back(l); });
    CHECK(b.name == "box");
    CHECK(b.scene->camera.width == 8);
    CHECK(b.scene->camera.height == 6);
    CHECK(b.reference.image.width == 8);
    CHECK(b.reference.image.height == 6);
    CHECK(b.reference.path == referencePath(options.refsDir, jobs[0].file, 8, 6, 1, "box"));
    CHECK(fs::exists(b.reference.path));
    REQUIRE(!lines.empty());
    CHECK(lines.front().find("8x6") != std::string::npos);
    SceneInfo info = sceneInfo(b);
    CHECK(info.width == 8);
    CHECK(info.height == 6);
    CHECK(info.nativeWidth == 512);
}

TEST_CASE("a missing suite scene file is an error naming its path", "[bench]") {
    test::TempDir dir;
    // <clone>/scenes with no ../shared beside <clone>: ../../shared from scenes/ is <dir>/shared.
    fs::create_directories(dir.path / "clone" / "scenes");
    BenchSuite suite = findSuite("public");
    BenchOptions options;
    options.scenesDir = dir.file("clone/scenes");
    std::string expected =
        (dir.path / "shared/scenes/bitterli/cornell-box/scene-v4.pbrt").lexically_normal().string();
    try {
        benchSceneJobs(suite, options);
        FAIL("no error");
    } catch (const InputError& e) {
        std::string what = e.what();
        CHECK(what.find("no such scene file") != std::string::npos);
        CHECK(what.find(expected) != std::string::npos);
        CHECK(what.find("--scenes-dir") != std::string::npos);
    }
}

TEST_CASE("the summary and ablation report give each scene's size when they differ", "[bench]") {
    const BenchSuite& suite = findSuite("public");
    SceneInfo a, b;
    a.name = "cornell-box";
    a.nativeWidth = a.nativeHeight = 1024;
    a.width = a.height = 128;
    b.name = "veach-mis";
    b.nativeWidth = 1280;
    b.nativeHeight = 720;
    b.width = 160;
    b.height = 90;
    CHECK(commonRenderSize({a, b}, suite).empty());
    CHECK(commonRenderSize({a}, suite) == "128x128");
    CHECK(commonRenderSize({}, suite) == "128x128"); // the suite's

    SummaryContext ctx;
    ctx.suite = &suite;
    ctx.scenes = {a, b};
    std::string md = renderSummary({}, ctx);
    CHECK(md.find("Every scene rendered at") == std::string::npos);
    CHECK(md.find("| scene | file's resolution | rendered at | reference |") != std::string::npos);
    CHECK(md.find("| veach-mis | 1280x720 | 160x90 |") != std::string::npos);

    ctx.scenes = {a};
    md = renderSummary({}, ctx);
    CHECK(md.find("Every scene rendered at **128x128**") != std::string::npos);
    CHECK(md.find("| cornell-box | 1024x1024 | path,") != std::string::npos);

    AblationRun run;
    run.scenes = {a, b};
    std::string ab =
        renderAblationMarkdown(run, suite, "rayproc bench public --ablation", "0", "0");
    CHECK(ab.find("cornell-box 128x128, veach-mis 160x90") != std::string::npos);
}
