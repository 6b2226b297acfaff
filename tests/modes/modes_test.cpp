// Analytic checks of the modes: a diffuse plane under a point light (inverse-square law and
// Lambert), and under a constant sky (the furnace-like a * L). Camera straight down.
#include "test_util.h"

#include "engine/cancel.h"
#include "image/metrics.h"

#include <atomic>
#include <functional>
#include <cmath>

using namespace rayproc;
using namespace rayproc::test;

namespace {

constexpr int kSize = 33; // odd: the centre pixel's centre is the image centre

// A 200 x 200 diffuse plane at y = 0 of albedo `albedo`, seen from straight above.
std::string planeScene(float albedo, const std::string& lights) {
    return R"({
      "camera": {"position": [0, 5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov": 10,
                 "resolution": [33, 33]},
      "materials": {"plane": {"type": "diffuse", "color": [)" +
           std::to_string(albedo) + ", " + std::to_string(albedo) + ", " + std::to_string(albedo) +
           R"(]}},
      "lights": )" +
           lights + R"(,
      "nodes": [{"type": "rectangle", "material": "plane", "center": [0, 0, 0],
                 "size": [200, 200], "normal": [0, 1, 0]}]
    })";
}

const float* centre(const Image& img) {
    return img.at(kSize / 2, kSize / 2);
}

} // namespace

TEST_CASE("Point light over a diffuse plane: radiance a / pi * I / h^2", "[modes]") {
    const float a = 0.6f, h = 2.0f;
    const Vec3 I(10.0f, 5.0f, 2.5f);
    auto scene = sceneFromJson(planeScene(a, R"([{"type": "point", "position": [0, 2, 0],
                                                  "intensity": [10, 5, 2.5]}])"));
    REQUIRE(scene->camera.width == kSize);
    EmbreeScene accel(*scene);
    const Vec3 expected = I * (a / kPi / (h * h));

    for (const std::string mode : {"raytrace", "preview"}) {
        INFO("mode " << mode);
        RenderOptions o;
        o.mode = mode;
        o.spp = mode == "raytrace" ? 4 : 1;
        RenderResult r = render(*scene, accel, o);
        const float* c = centre(r.image);
        CHECK(c[0] == Approx(expected.x).epsilon(0.01));
        CHECK(c[1] == Approx(expected.y).epsilon(0.01));
        CHECK(c[2] == Approx(expected.z).epsilon(0.01));

        // Off-centre the law is a / pi * I * cos / d^2 = a / pi * I * h / d^3 at the point a
        // pixel sees: pixel (0, 0) looks at (-r, 0, -r) with r = 5 tan(5 deg) (1 - 1/33).
        const double r0 = 5.0 * std::tan(5.0 * 3.14159265358979 / 180.0) * (1.0 - 1.0 / kSize);
        const double d = std::sqrt(h * h + 2 * r0 * r0);
        const float* corner = r.image.at(0, 0);
        CHECK(corner[0] == Approx(I.x * a / kPi * h / (d * d * d)).epsilon(0.01));
        CHECK(corner[0] < 0.9f * c[0]);
    }
}

TEST_CASE("Constant sky over a diffuse plane: radiance a * L", "[modes]") {
    const float a = 0.5f;
    const Vec3 L(0.8f, 0.6f, 0.4f);
    auto scene =
        sceneFromJson(planeScene(a, R"([{"type": "environment", "radiance": [0.8, 0.6, 0.4]}])"));
    EmbreeScene accel(*scene);
    const Vec3 expected = L * a;

    SECTION("raytrace converges to a * L") {
        RenderOptions o;
        o.spp = 4;
        o.lightSamples = 16;
        RenderResult r = render(*scene, accel, o);
        // Every pixel sees the plane, and all of the plane sees only the sky.
        Vec3 mean(0.0f);
        for (int y = 0; y < kSize; ++y) {
            for (int x = 0; x < kSize; ++x) {
                const float* p = r.image.at(x, y);
                mean += Vec3(p[0], p[1], p[2]);
                for (int ch = 0; ch < 3; ++ch) {
                    INFO("pixel " << x << ", " << y << " channel " << ch);
                    CHECK(p[ch] == Approx(expected[ch]).epsilon(0.05));
                }
            }
        }
        mean = mean / float(kSize * kSize);
        CHECK(mean.x == Approx(expected.x).epsilon(0.02));
        CHECK(mean.y == Approx(expected.y).epsilon(0.02));
        CHECK(mean.z == Approx(expected.z).epsilon(0.02));
    }
    SECTION("preview gives exactly a * L (ambient sky)") {
        RenderOptions o;
        o.mode = "preview";
        o.spp = 1;
        RenderResult r = render(*scene, accel, o);
        for (int y = 0; y < kSize; ++y) {
            for (int x = 0; x < kSize; ++x) {
                const float* p = r.image.at(x, y);
                for (int ch = 0; ch < 3; ++ch) {
                    INFO("pixel " << x << ", " << y << " channel " << ch);
                    CHECK(p[ch] == Approx(expected[ch]).epsilon(1e-6));
                }
            }
        }
    }
}

TEST_CASE("A relMSE target stops when the half-buffer estimate reaches it - the estimate is honest",
          "[modes]") {
    // The golden path image (8192 spp, 128 x 128) box-downsampled to 32 x 32 is the truth.
    Image truth = boxDownsample(readImage(goldenPath("cornell-box-path.exr")), 4);
    auto scene = loadSceneAt("cornell-box", 32, 32);
    EmbreeScene accel(*scene);
    for (double target : {0.02, 0.005}) {
        INFO("target " << target);
        EngineSettings engine;
        engine.quiet = true;
        engine.threads = 2;
        RenderControl control;
        control.targetRelMse = target;
        PathSettings s;
        s.spp = 100000; // a cap the target stops long before
        RenderResult r = renderPath(*scene, accel, s, engine, control);
        CHECK(r.targetReached);
        CHECK(r.relMseEstimate <= target);
        CHECK(r.samplesDone >= 8); // never on fewer than 4 samples per half
        CHECK(r.samplesDone < 100000);
        // The estimate is of the variance; path mode has no bias, so it should match the error
        // against the truth (whose own noise is 1/256 of a 32-spp image's).
        double actual = compareImages(r.image, truth).relmse;
        INFO("spp " << r.samplesDone << ", estimate " << r.relMseEstimate << ", actual " << actual);
        CHECK(actual < 2.0 * target);
        CHECK(actual > 0.25 * target);
    }
    // Without a target the estimate is not made (no half buffers, no cost).
    EngineSettings plain;
    plain.quiet = true;
    PathSettings s;
    s.spp = 4;
    RenderResult r = renderPath(*scene, accel, s, plain);
    CHECK(std::isnan(r.relMseEstimate));
    CHECK_FALSE(r.targetReached);
}

TEST_CASE("RenderControl::stop cancels a render without the process-wide interrupt", "[modes]") {
    auto scene = loadSceneAt("cornell-box", 128, 128); // 64 tiles of 16 x 16
    EmbreeScene accel(*scene);
    EngineSettings engine;
    engine.quiet = true;
    engine.threads = 2;
    PathSettings s;
    s.spp = 2;
    RenderControl control;

    // Polled before each emission: after a few tiles, the rest are never emitted.
    std::atomic<int> polls{0};
    control.stop = [&] { return ++polls > 4; };
    RenderResult r = renderPath(*scene, accel, s, engine, control);
    CHECK(r.cancelled);
    CHECK(r.stats.pixelsWithoutSamples > 0);
    CHECK(r.stats.pixelsWithoutSamples < std::size_t(128 * 128));
    CHECK_FALSE(interruptRequested()); // Ctrl-C's flag is untouched
    CHECK(allFinite(r.image));

    // Stopped from the start: nothing is rendered.
    control.stop = [] { return true; };
    r = renderPath(*scene, accel, s, engine, control);
    CHECK(r.cancelled);
    CHECK(r.passesDone == 0);
    CHECK(r.stats.pixelsWithoutSamples == std::size_t(128 * 128));

    // Never true: the whole render.
    control.stop = [] { return false; };
    r = renderPath(*scene, accel, s, engine, control);
    CHECK_FALSE(r.cancelled);
    CHECK(r.samplesDone == 2);
    CHECK(r.stats.pixelsWithoutSamples == 0);
}

TEST_CASE("Under a time limit the progress fraction is the share of the budget spent",
          "[modes]") {
    // A time-limited render asks for far more samples than it will take: its progress (the
    // terminal's line, rayproc serve's bar and ETA) follows the clock, not the samples.
    auto scene = loadSceneAt("cornell-box", 16, 16);
    EmbreeScene accel(*scene);
    std::function<double()> fraction;
    double atEnd = -1;
    RenderControl::Watcher watcher;
    watcher.begin = [&](std::function<Image()>, std::function<double()> f,
                        std::function<std::uint64_t()>) {
        fraction = std::move(f);
    };
    watcher.end = [&] { atEnd = fraction(); };
    EngineSettings engine;
    engine.quiet = true;
    engine.threads = 2;
    RenderControl control;
    control.timeLimitSeconds = 0.3;
    control.watcher = &watcher;
    PathSettings s;
    s.spp = 10000000;
    RenderResult r = renderPath(*scene, accel, s, engine, control);
    REQUIRE(r.timeLimitReached);
    INFO("spp done " << r.samplesDone << ", fraction at the end " << atEnd);
    CHECK(double(r.samplesDone) / s.spp < 0.01);
    CHECK(atEnd == 1.0);

    // Without a limit it is the samples' share.
    control.timeLimitSeconds = 0;
    s.spp = 4;
    r = renderPath(*scene, accel, s, engine, control);
    CHECK(atEnd == 1.0); // the last pass counted once (it was twice until stop 30)
    s.spp = 1000000;
    int passesSeen = 0;
    // Cancel early: the fraction stays small.
    control.stop = [&] { return ++passesSeen > 20; };
    r = renderPath(*scene, accel, s, engine, control);
    REQUIRE(r.cancelled);
    INFO("fraction of a cancelled 1,000,000-spp render " << atEnd);
    CHECK(atEnd < 0.01);
}
