// Cache refinement (GiSettings::icRefineRays): the records keep gathering before every render
// pass, so the noise of their prepass gather leaves the image as passes accumulate. Checked on
// the Cornell box with deliberately noisy records (4 prepass rays each) against the same render
// with 256-ray records (same photon map: same seed and photons): with refinement the image's
// error against it falls to a fraction; the rays added are exactly records x rays x passes; the
// image does not depend on the thread count. (Correction rays, which take the map's own bias
// out of the records: tests/gi/map_correction_test.cpp.)
#include "test_util.h"

using namespace rayproc;
using namespace rayproc::test;

namespace {

RenderResult render(const Scene& scene, const EmbreeScene& accel, int gatherRays, int refineRays,
                    int threads) {
    EngineSettings engine;
    engine.threads = threads;
    engine.seed = 5;
    engine.quiet = true;
    GiSettings s = giSettings(scene, ModeOverrides{32, 0, 0});
    s.photons = 20000;
    s.gatherRays = gatherRays;
    s.filmGatherRays = 64; // cache misses: the same gathers in every render
    s.icRefineRays = refineRays;
    return renderGi(scene, accel, s, engine);
}

} // namespace

TEST_CASE("Cache refinement: records gather on during the render and their noise leaves the image",
          "[gi][cache]") {
    auto scene = loadSceneAt("cornell-box", 32, 32);
    EmbreeScene accel(*scene);
    RenderResult reference = render(*scene, accel, 256, 0, 2);
    RenderResult frozen = render(*scene, accel, 4, 0, 2);
    RenderResult refined = render(*scene, accel, 4, 8, 2);

    const double records = extraStat(refined, "gi/cache_records");
    const double rays = extraStat(refined, "gi/refine_rays");
    INFO(records << " records, " << rays << " refinement rays");
    CHECK(records > 20);
    CHECK(extraStat(frozen, "gi/refine_rays") == 0);
    // 8 rays per record before each of the 31 passes after the first (below-surface strata
    // count as dark rays, as in a gather).
    CHECK(rays == records * 8 * 31);

    const double errFrozen = relMse(frozen.image, reference.image);
    const double errRefined = relMse(refined.image, reference.image);
    INFO("relMSE against 256-ray records: frozen 4-ray records " << errFrozen << ", refined "
                                                                 << errRefined);
    CHECK(errRefined < 0.25 * errFrozen); // measured: 0.00042 against 0.0066

    RenderResult one = render(*scene, accel, 4, 8, 1);
    CHECK(one.image.pixels == refined.image.pixels);
}
