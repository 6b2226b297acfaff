// scenes/water-pool.pbrt, the pbrt-v4 stand-in for issue 39's held-back pool (water in a box,
// one area light above, the floor and walls lit through the rippled dielectric surface and
// seen through it): the importer hands gi the file's sppm settings, and gi's image carries
// path mode's energy through the importer's dielectric, area light and mesh normals.
#include "test_util.h"

using namespace rayproc;
using namespace rayproc::test;

namespace {

std::unique_ptr<Scene> loadPool(int size) {
    auto scene = loadScene((sourceDir() / "scenes" / "water-pool.pbrt").string());
    scene->camera.width = size;
    scene->camera.height = size;
    return scene;
}

EngineSettings quietEngine(std::uint64_t seed) {
    EngineSettings engine;
    engine.threads = 2;
    engine.seed = seed;
    engine.quiet = true;
    return engine;
}

} // namespace

TEST_CASE("The pbrt water pool: Integrator sppm's radius and maxdepth reach gi",
          "[pbrt][caustics]") {
    auto scene = loadPool(16);
    CHECK(scene->render.photonRadius == Approx(0.01f));
    CHECK(scene->render.maxPhotonDepth == 9);
    CHECK(scene->render.maxDepth == 8); // the camera's chain: maxdepth - 1 (docs/pbrt-import.md)
}

TEST_CASE("The pbrt water pool: gi's image mean is path's within 2% in every channel",
          "[pbrt][caustics]") {
    // Both modes at full depth (the file's maxdepth 9 truncates gi's and path's paths
    // differently: path's camera paths, gi's photon paths plus the camera chain). At 128x128
    // against a path render of 8,192 spp, gi came out 0.998-1.004 at 16 to 256 spp
    // (docs/caustics.md); here 32x32, gi 32 spp against path 2048 spp.
    auto scene = loadPool(32);
    EmbreeScene accel(*scene);
    GiSettings gi = giSettings(*scene, ModeOverrides{32, 63, 0});
    gi.maxPhotonDepth = 64;
    PathSettings path = pathSettings(scene->render, ModeOverrides{2048, 64, 0});
    Vec3 g = imageMean(renderGi(*scene, accel, gi, quietEngine(1)).image);
    Vec3 p = imageMean(renderPath(*scene, accel, path, quietEngine(7)).image);
    for (int c = 0; c < 3; ++c) {
        INFO("channel " << c << ": gi " << g[c] << ", path " << p[c]);
        CHECK(p[c] > 0.05f);
        CHECK(g[c] == Approx(p[c]).epsilon(0.02));
    }
}

TEST_CASE("pbrt sppm maxdepth D: gi takes the paths of path mode at the same D (diffuse box)",
          "[pbrt][caustics][gi]") {
    // Where every surface is diffuse, pbrt-v4's SPPM at maxdepth D (a visible point at the
    // first hit, light sampled there, photons deposited at their 2nd to D-th intersection) and
    // its path integrator at the same D sum the same paths: at most D scattering events. gi
    // reads its global map and traces its records' correction paths one bounce from the
    // visible point, so both stop one intersection short of D (photon_stage.cpp,
    // correction_stage.h). Measured at 64x64, 16 spp against path at 512 spp: gi / path
    // 1.015 at D = 2 and 3 and 1.013 at D = 50 (gi's own excess on this box, the same at every
    // depth); before, with the D-th photons kept and corrections one deeper, 1.07-1.11 at D = 2,
    // gi then had every path of D + 1 events. Path at D + 1 is 5-9% above path at D here.
    auto scene = loadScene((sourceDir() / "scenes" / "cornell-box.pbrt").string());
    scene->camera.width = scene->camera.height = 32;
    const int d = 2;
    scene->render.maxDepth = d - 1; // the importer's mapping (docs/pbrt-import.md)
    scene->render.maxPhotonDepth = d;
    EmbreeScene accel(*scene);
    auto pathMean = [&](int maxDepth) {
        PathSettings path = pathSettings(scene->render, ModeOverrides{1024, maxDepth, 0});
        return imageMean(renderPath(*scene, accel, path, quietEngine(7)).image);
    };
    Vec3 g = imageMean(
        renderGi(*scene, accel, giSettings(*scene, ModeOverrides{16, 0, 0}), quietEngine(1)).image);
    Vec3 p = pathMean(0), deeper = pathMean(d);
    for (int c = 0; c < 3; ++c) {
        INFO("channel " << c << ": gi " << g[c] << ", path " << p[c] << ", path at D + 1 "
                        << deeper[c]);
        CHECK(deeper[c] > 1.04f * p[c]); // the test separates the two depths
        CHECK(g[c] == Approx(p[c]).epsilon(0.03));
    }
}
