// gi's map correction (GiSettings::mapCorrection, gi/correction_stage.h): with a global map far
// too sparse for the scene, gi alone is biased; the correction takes that bias out of the image
// (its expectation is path mode's), and the image stays independent of the thread count.
#include "image/metrics.h"
#include "test_util.h"

#include <cstring>

using namespace rayproc;
using namespace rayproc::test;

namespace {

RenderResult renderStarvedGi(const Scene& scene, const EmbreeScene& accel, bool correct,
                             int threads) {
    EngineSettings engine;
    engine.threads = threads;
    engine.seed = 1;
    engine.quiet = true;
    GiSettings s = giSettings(scene, ModeOverrides{64, 0, 0});
    // 500 photons for the Cornell box: the 64-nearest discs span a good part of a wall.
    s.photons = 500;
    s.photonRounds = 1;
    s.mapCorrection = correct;
    return renderGi(scene, accel, s, engine);
}

} // namespace

TEST_CASE("gi's map correction takes a starved photon map's bias out of the image", "[gi]") {
    auto scene = loadSceneAt("cornell-box", 32, 32);
    EmbreeScene accel(*scene);
    RenderOptions o;
    o.mode = "path";
    o.spp = 2048;
    Image reference = render(*scene, accel, o).image;
    RenderResult plain = renderStarvedGi(*scene, accel, false, 2);
    RenderResult corrected = renderStarvedGi(*scene, accel, true, 2);
    ImageMetrics before = compareImages(plain.image, reference);
    ImageMetrics after = compareImages(corrected.image, reference);
    INFO("mean error " << before.meanRel << " -> " << after.meanRel << ", block error "
                       << before.blockRel << " -> " << after.blockRel);
    // Measured: mean 6.6% -> 0.4% (docs/photon-map.md, "Correcting the map").
    CHECK(before.meanRel > 0.04);
    CHECK(after.meanRel < 0.02);
    CHECK(after.meanRel < before.meanRel / 3);
    CHECK(extraStat(plain, "gi/correction_rays") == 0);
    // About one ray per first diffuse hit and pass, plus the paths they continue.
    CHECK(extraStat(corrected, "gi/correction_rays") > 32.0 * 32.0 * 64.0 * 0.5);
}

TEST_CASE("gi's map correction renders the same image on 1 and 2 threads", "[gi][determinism]") {
    auto scene = loadSceneAt("cornell-box", 24, 24);
    EmbreeScene accel(*scene);
    RenderResult one = renderStarvedGi(*scene, accel, true, 1);
    RenderResult two = renderStarvedGi(*scene, accel, true, 2);
    REQUIRE(one.image.pixels.size() == two.image.pixels.size());
    CHECK(std::memcmp(one.image.pixels.data(), two.image.pixels.data(),
                      one.image.pixels.size() * sizeof(one.image.pixels[0])) == 0);
}
