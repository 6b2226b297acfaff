// gi's map corrections, with a global map far too sparse for the scene, where gi alone is
// biased: per pixel (GiSettings::mapCorrection, gi/correction_stage.h) the correction takes that
// bias out of the image (its expectation is path mode's); per cache record
// (GiSettings::icCorrectionRays, gi/cache_refinement.h) it takes it out of the records, which
// then converge to the exact gather. Both leave the image independent of the thread count.
#include "image/metrics.h"
#include "test_util.h"

#include <cstring>

using namespace rayproc;
using namespace rayproc::test;

namespace {

struct Correction {
    bool perPixel = false;
    int recordRays = 0;
};

// 64 spp in 32 passes; with `onePerPass`, `spp` passes of 1 spp (as under a time limit).
RenderResult renderStarvedGi(const Scene& scene, const EmbreeScene& accel, Correction correct,
                             int threads, int spp = 64, bool onePerPass = false) {
    EngineSettings engine;
    engine.threads = threads;
    engine.seed = 1;
    engine.quiet = true;
    RenderControl control;
    if (onePerPass) control.timeLimitSeconds = 1e6;
    GiSettings s = giSettings(scene, ModeOverrides{spp, 0, 0});
    // 500 photons for the Cornell box: the 64-nearest discs span a good part of a wall.
    s.photons = 500;
    s.photonRounds = 1;
    s.mapCorrection = correct.perPixel;
    s.icCorrectionRays = correct.recordRays;
    return renderGi(scene, accel, s, engine, control);
}

Image pathReference(const Scene& scene, const EmbreeScene& accel) {
    RenderOptions o;
    o.mode = "path";
    o.spp = 2048;
    return render(scene, accel, o).image;
}

} // namespace

// The path reference and the uncorrected render are made once for both corrections.
TEST_CASE("gi's map corrections take a starved photon map's bias out, per pixel and per record",
          "[gi][cache][heavy]") {
    auto scene = loadSceneAt("cornell-box", 32, 32);
    EmbreeScene accel(*scene);
    Image reference = pathReference(*scene, accel);
    RenderResult plain = renderStarvedGi(*scene, accel, {}, 2);
    ImageMetrics before = compareImages(plain.image, reference);
    CHECK(before.meanRel > 0.04);
    CHECK(extraStat(plain, "gi/correction_rays") == 0);
    CHECK(extraStat(plain, "gi/ic_correction_rays") == 0);

    // Per pixel: the image converges to path mode's.
    RenderResult corrected = renderStarvedGi(*scene, accel, {true, 0}, 2);
    ImageMetrics after = compareImages(corrected.image, reference);
    INFO("per pixel: mean error " << before.meanRel << " -> " << after.meanRel
                                  << ", block error " << before.blockRel << " -> "
                                  << after.blockRel);
    // Measured: mean 6.6% -> 0.4% (docs/photon-map.md, "Correcting the map").
    CHECK(after.meanRel < 0.02);
    CHECK(after.meanRel < before.meanRel / 3);
    // About one ray per first diffuse hit and pass, plus the paths they continue.
    CHECK(extraStat(corrected, "gi/correction_rays") > 32.0 * 32.0 * 64.0 * 0.5);

    // Per cache record: the records converge to the exact gather, not to the map's.
    RenderResult records = renderStarvedGi(*scene, accel, {false, 8}, 2);
    ImageMetrics recordsAfter = compareImages(records.image, reference);
    INFO("per record: mean error " << before.meanRel << " -> " << recordsAfter.meanRel
                                   << ", block error " << before.blockRel << " -> "
                                   << recordsAfter.blockRel);
    // The corrections go in with a weight that grows as they prove larger than their noise, and
    // the film keeps the early passes' smaller weights: 32 passes leave part of the bias,
    // 256 passes of 1 spp far less. Measured: weight 0.89 after 32 passes, mean error 6.7% ->
    // 3.1%, block 5.7% -> 2.7%; after 256 passes weight 0.99, mean 1.3%, block 1.1%.
    const double weight = extraStat(records, "gi/ic_correction_weight");
    INFO("weight after 32 passes " << weight);
    CHECK(weight > 0.5);
    CHECK(weight <= 1.0);
    CHECK(recordsAfter.meanRel < before.meanRel / 1.6);
    CHECK(recordsAfter.blockRel < before.blockRel / 1.6);
    RenderResult longer = renderStarvedGi(*scene, accel, {false, 8}, 2, 256, true);
    ImageMetrics longerAfter = compareImages(longer.image, reference);
    INFO("256 passes: weight " << extraStat(longer, "gi/ic_correction_weight") << ", mean error "
                               << longerAfter.meanRel << ", block error " << longerAfter.blockRel);
    CHECK(extraStat(longer, "gi/ic_correction_weight") > weight);
    CHECK(longerAfter.meanRel < before.meanRel / 3);
    CHECK(longerAfter.blockRel < before.blockRel / 2);
    // 8 correction rays per record wherever refinement adds its one gather ray (every record,
    // before each pass after the first).
    const double refineRays = extraStat(records, "gi/refine_rays");
    CHECK(refineRays > 0);
    CHECK(extraStat(records, "gi/ic_correction_rays") == 8 * refineRays);
    RenderResult one = renderStarvedGi(*scene, accel, {false, 8}, 1);
    CHECK(one.image.pixels == records.image.pixels);
}

TEST_CASE("gi's map correction renders the same image on 1 and 2 threads", "[gi][determinism]") {
    auto scene = loadSceneAt("cornell-box", 24, 24);
    EmbreeScene accel(*scene);
    RenderResult one = renderStarvedGi(*scene, accel, {true, 0}, 1);
    RenderResult two = renderStarvedGi(*scene, accel, {true, 0}, 2);
    REQUIRE(one.image.pixels.size() == two.image.pixels.size());
    CHECK(std::memcmp(one.image.pixels.data(), two.image.pixels.data(),
                      one.image.pixels.size() * sizeof(one.image.pixels[0])) == 0);
}
