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
          "[pbrt][caustics][heavy]") {
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
    // visible point, so both stop one intersection short of D (photon_pass.cpp,
    // correction_stage.h); with the D-th photons kept and corrections one deeper, gi had every
    // path of D + 1 events too (docs/caustics.md, "One bounce fewer behind the gather").
    // Means over the pixels that do not see the lamp: its edge pixels' coverage noise moves a
    // low-spp image's whole mean by 1-4% from seed to seed. Measured so: gi / path 1.018-1.021
    // here (gi's own excess at 32x32 on this box, 1.004-1.010 at 64x64, the same at D = 50);
    // path at D + 1 is 11-17% above path at D, where gi was before.
    auto scene = loadScene((sourceDir() / "scenes" / "cornell-box.pbrt").string());
    scene->camera.width = scene->camera.height = 32;
    const int d = 2;
    scene->render.maxDepth = d - 1; // the importer's mapping (docs/pbrt-import.md)
    scene->render.maxPhotonDepth = d;
    EmbreeScene accel(*scene);
    auto pathImage = [&](int maxDepth) {
        PathSettings path = pathSettings(scene->render, ModeOverrides{1024, maxDepth, 0});
        return renderPath(*scene, accel, path, quietEngine(7)).image;
    };
    const Image p = pathImage(0), deeper = pathImage(d);
    const Image g =
        renderGi(*scene, accel, giSettings(*scene, ModeOverrides{16, 0, 0}), quietEngine(1)).image;
    auto unlitMean = [&](const Image& img) {
        Vec3 sum(0.0f);
        int n = 0;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                const float* r = p.at(x, y);
                if (std::max({r[0], r[1], r[2]}) >= 1.0f) continue; // the lamp and its edges
                sum += Vec3(img.at(x, y)[0], img.at(x, y)[1], img.at(x, y)[2]);
                ++n;
            }
        REQUIRE(n > img.width * img.height / 2);
        return sum / float(n);
    };
    const Vec3 gm = unlitMean(g), pm = unlitMean(p), dm = unlitMean(deeper);
    for (int c = 0; c < 3; ++c) {
        INFO("channel " << c << ": gi " << gm[c] << ", path " << pm[c] << ", path at D + 1 "
                        << dm[c]);
        CHECK(dm[c] > 1.08f * pm[c]); // the test separates the two depths
        CHECK(gm[c] == Approx(pm[c]).epsilon(0.03));
    }
}
