// gi's film gathers (GiSettings::filmGatherRays): where a render pass finds no usable cache record
// it gathers straight into the film with its own ray count, by default a record's rays shared
// out over the render's samples; fewer rays per gather change the noise, not the expectation.
#include "test_util.h"

using namespace rayproc;
using namespace rayproc::test;

TEST_CASE("Film gathers take gatherRays / spp rays unless set, at least one", "[gi]") {
    GiSettings s;
    s.gatherRays = 64;
    s.spp = 16;
    CHECK(filmGatherRays(s) == 4);
    s.spp = 1;
    CHECK(filmGatherRays(s) == 64);
    s.spp = 100000; // a time-limited render's bound
    CHECK(filmGatherRays(s) == 1);
    s.filmGatherRays = 8;
    CHECK(filmGatherRays(s) == 8);
}

TEST_CASE("A one-ray film gather costs a 64th of the rays and keeps the image's mean", "[gi]") {
    auto scene = loadSceneAt("cornell-box", 24, 24);
    EmbreeScene accel(*scene);
    EngineSettings engine;
    engine.threads = 2;
    engine.seed = 3;
    engine.quiet = true;
    GiSettings s = giSettings(*scene, ModeOverrides{16, 0, 0});
    s.photons = 20000;
    s.irradianceCache = false; // every first diffuse hit gathers for the film
    s.filmGatherRays = 64;
    RenderResult full = renderGi(*scene, accel, s, engine);
    s.filmGatherRays = 1;
    RenderResult one = renderGi(*scene, accel, s, engine);
    const double raysFull = extraStat(full, "gi/gather_rays"), raysOne = extraStat(one, "gi/gather_rays");
    INFO(raysFull << " gather rays with 64 per gather, " << raysOne << " with 1");
    // Every pixel's 16 samples see a diffuse wall; strata below a surface send no ray.
    CHECK(raysOne > 0.9 * 24 * 24 * 16);
    CHECK(raysOne <= 24 * 24 * 16);
    CHECK(raysFull / raysOne == Approx(64).epsilon(0.1));
    Vec3 a = imageMean(full.image), b = imageMean(one.image);
    for (int c = 0; c < 3; ++c) {
        INFO("channel " << c << ": 64 rays " << a[c] << ", 1 ray " << b[c]);
        CHECK(b[c] == Approx(a[c]).epsilon(0.02));
    }
}
