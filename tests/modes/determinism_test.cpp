// Reproducibility: the same scene, seed and settings give the same image bit for bit whatever
// the thread count and the packet width; a different seed gives a different image.
#include "furnace_scene.h"
#include "test_util.h"

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// Pixels whose bits differ, for the failure message.
std::size_t differingValues(const Image& a, const Image& b) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < std::min(a.pixels.size(), b.pixels.size()); ++i)
        n += std::memcmp(&a.pixels[i], &b.pixels[i], sizeof(float)) != 0;
    return n;
}

} // namespace

// Bit-identical across thread counts (1, 2) and packet widths (16, 8, 4, 1). Embree 3.13
// rounds a sphere's t differently in rtcIntersect1 and in its packet kernels (by about an ulp;
// see intersect_test.cpp); EmbreeScene::surface() solves the sphere again in double precision,
// so the images must still agree to the bit.
TEST_CASE("Images do not depend on the thread count or the packet width", "[modes]") {
    for (const std::string name : {"cornell-box", "cornell-spheres"}) {
        auto scene = loadSceneAt(name, 64, 64);
        EmbreeScene accel(*scene);
        for (const std::string mode : {"raytrace", "preview"}) {
            INFO("scene " << name << ", mode " << mode);
            RenderOptions o;
            o.mode = mode;
            o.spp = mode == "raytrace" ? 4 : 1;
            o.threads = 1;
            o.packetWidth = 16;
            RenderResult reference = render(*scene, accel, o);
            REQUIRE(reference.image.width == 64);
            REQUIRE(reference.image.height == 64);
            REQUIRE_FALSE(reference.cancelled);
            CHECK(meanValue(reference.image) > 0.01); // not a black image
            CHECK(reference.stats.totals.invalidSamples == 0);
            CHECK(reference.stats.pixelsWithoutSamples == 0);

            for (auto [threads, width] : {std::pair{2, 16}, std::pair{2, 8}, std::pair{1, 4},
                                          std::pair{1, 1}, std::pair{2, 1}}) {
                INFO("threads " << threads << ", packet width " << width);
                o.threads = threads;
                o.packetWidth = width;
                RenderResult r = render(*scene, accel, o);
                INFO("values that differ: " << differingValues(r.image, reference.image));
                CHECK(r.stats.totals.samples == reference.stats.totals.samples);
                CHECK(sameBits(r.image, reference.image));
                CHECK(r.stats.totals.raysTraced == reference.stats.totals.raysTraced);
            }
        }
    }
}

TEST_CASE("Different seeds give different images", "[modes]") {
    auto scene = loadSceneAt("cornell-box", 64, 64);
    EmbreeScene accel(*scene);
    RenderOptions o;
    o.spp = 4;
    o.seed = 1;
    Image a = render(*scene, accel, o).image;
    o.seed = 2;
    Image b = render(*scene, accel, o).image;
    o.seed = 1;
    Image again = render(*scene, accel, o).image;
    CHECK_FALSE(sameBits(a, b));
    CHECK(differingValues(a, b) > a.pixels.size() / 4); // noise everywhere, not one pixel
    CHECK(sameBits(a, again));
    // Different noise, the same picture.
    CHECK(meanValue(b) == Approx(meanValue(a)).epsilon(0.05));
}

// The same for the two global-illumination modes: path's bounces, and gi's photon maps,
// precomputed irradiance and irradiance cache (filled in passes merged in a fixed order).
// cornell-spheres: spheres are where rtcIntersect1 and the packet kernels round t differently.
TEST_CASE("Path and gi images do not depend on the thread count or the packet width", "[modes]") {
    auto scene = loadSceneAt("cornell-spheres", 32, 32);
    EmbreeScene accel(*scene);
    ModeOverrides overrides{2, 0, 0};
    GiSettings gi = giSettings(*scene, overrides);
    gi.photons = gi.causticPhotons = 20000;
    PathSettings path = pathSettings(scene->render, overrides);
    for (const std::string mode : {"path", "gi"}) {
        INFO("mode " << mode);
        auto run = [&](int threads, int width) {
            EngineSettings engine;
            engine.threads = threads;
            engine.packetWidth = width;
            engine.quiet = true;
            return mode == "gi" ? renderGi(*scene, accel, gi, engine)
                                : renderPath(*scene, accel, path, engine);
        };
        RenderResult reference = run(1, 16);
        CHECK(meanValue(reference.image) > 0.01);
        CHECK(reference.stats.totals.invalidSamples == 0);
        for (auto [threads, width] : {std::pair{2, 16}, std::pair{2, 1}, std::pair{1, 4}}) {
            INFO("threads " << threads << ", packet width " << width);
            RenderResult r = run(threads, width);
            INFO("values that differ: " << differingValues(r.image, reference.image));
            CHECK(sameBits(r.image, reference.image));
        }
    }
}

// Smooth glass splits a camera path into a visible point per lobe and bounce, more than the
// cache prepass's two slots a pixel: a level that wants more is traced again with room for
// all (gi/cache_prepass.cpp), where which visible points got a slot used to depend on the
// threads' timing. A glass sphere filling the view inside a furnace: every pixel past two.
TEST_CASE("gi's cache prepass makes the same records when glass splits the camera's paths",
          "[modes][gi][determinism]") {
    auto loaded = loadPbrt(furnaceAround("\"dielectric\" \"float eta\" 1.5"), "glass-furnace.pbrt");
    REQUIRE(loaded.warnings.empty());
    const Scene* scene = loaded.scene.get();
    EmbreeScene accel(*scene);
    GiSettings gi = giSettings(*scene, ModeOverrides{2, 0, 0});
    // The prepass's slots do not depend on the photon maps: small ones keep the test quick.
    gi.photons = 20000;
    gi.photonRounds = 1;
    gi.causticPhotons = 5000;
    auto run = [&](int threads) {
        EngineSettings engine;
        engine.threads = threads;
        engine.quiet = true;
        return renderGi(*scene, accel, gi, engine);
    };
    RenderResult reference = run(1);
    CHECK(meanValue(reference.image) > 1);
    // The scene takes the path that makes the records whole: without it the runs below agree
    // only when the machine happens to run the threads one after the other.
    CHECK(extraStat(reference, "gi/cache_prepass_levels_retraced") > 0);
    for (int k = 0; k < 3; ++k) {
        RenderResult r = run(2);
        INFO("run " << k << ", values that differ: " << differingValues(r.image, reference.image));
        CHECK(sameBits(r.image, reference.image));
    }
}
