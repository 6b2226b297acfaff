// The reference cache (keyed by scene content, resolution and spp; rendered once, then read)
// and the ablation table (every switch changes its render's settings, and the CSV row holds
// them).
#include "bench/ablation.h"
#include "bench/reference_cache.h"
#include "image/metrics.h"

#include "test_util.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <set>

using namespace rayproc;
using namespace rayproc::bench;

TEST_CASE("the reference cache renders once, then reuses, and keys by scene content",
          "[bench]") {
    test::TempDir dir;
    std::string sceneFile = dir.file("box.json");
    std::string text = test::readText(test::scenePath("cornell-box"));
    test::writeText(sceneFile, text);
    std::string refs = dir.file("refs");

    std::string path = referencePath(refs, sceneFile, 16, 12, 8);
    CHECK(std::filesystem::path(path).filename().string().rfind("box-16x12-path-8-", 0) == 0);
    CHECK(path != referencePath(refs, sceneFile, 16, 12, 16));
    CHECK(path != referencePath(refs, sceneFile, 12, 16, 8));

    auto scene = loadScene(sceneFile);
    scene->camera.width = 16;
    scene->camera.height = 12;
    EmbreeScene accel(*scene);
    Reference first = loadOrRenderReference(*scene, accel, sceneFile, refs, 8, 0);
    CHECK(first.rendered);
    CHECK(first.path == path);
    REQUIRE(std::filesystem::exists(path));
    Reference second = loadOrRenderReference(*scene, accel, sceneFile, refs, 8, 0);
    CHECK_FALSE(second.rendered);
    CHECK(compareImages(second.image, first.image).maxAbs == 0);
    // Its own seed: not the image a path render with the bench's seed 1 gives.
    RenderConfig c = RenderConfig::forMode(*scene, "path", 8);
    TimedRender same = renderTimed(*scene, accel, c);
    CHECK(compareImages(same.image, first.image).rmse > 0);

    // A changed scene file is a new key: the old reference is not reused.
    test::writeText(sceneFile, text + "\n");
    CHECK(referencePath(refs, sceneFile, 16, 12, 8) != path);
}

// What a switch does to a render is measured by `rayproc bench --ablation` (docs/performance.md);
// several change no pixel by design (packet width, lazy irradiance). This checks the table.
TEST_CASE("every ablation switch changes its mode's settings line and names its CLI option",
          "[bench]") {
    auto scene = test::loadSceneAt("cornell-box", 8, 8);
    std::set<std::string> names;
    for (const AblationSwitch& sw : ablationSwitches()) {
        INFO(sw.name << " (" << sw.mode << ")");
        RenderConfig on = RenderConfig::forMode(*scene, sw.mode, 4);
        RenderConfig off = on;
        switchOff(sw, off);
        CHECK(off.settingsString() != on.settingsString());
        CHECK(off.spp() == on.spp());
        CHECK_FALSE(sw.cliOption.empty());
        names.insert(sw.name);
    }
    for (const char* expected : {"packets (Embree width 16 vs 1)", "irradiance cache",
                                 "precomputed irradiance", "caustic map", "Russian roulette"})
        CHECK(names.count(expected) == 1);
}

TEST_CASE("ablation rows are written as CSV with every number", "[bench]") {
    AblationRow r{"cornell-box", "caustic map", "gi", "spp=4 gather=64", "spp=4 no-caustics",
                  1.5, 1.25, 100, 90, 0.002, 0.004};
    std::string line = formatAblationCsvRow(r);
    CHECK(line == "cornell-box,caustic map,gi,spp=4 gather=64,spp=4 no-caustics,1.5,1.25,100,90,"
                  "0.002,0.0040000000000000001");
    int commas = 0;
    for (char ch : std::string(kAblationCsvHeader)) commas += ch == ',';
    CHECK(commas == 10);
}
