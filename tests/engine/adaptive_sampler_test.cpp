// Adaptive sampling: the passes go to the pixels whose noise needs them, as n ~ sqrt(noise per
// sample); the image stays the same whatever the thread count; at the same mean samples per
// pixel the image's error falls where the noise is uneven.
#include "engine/adaptive_sampler.h"

#include "test_util.h"

#include <catch2/catch.hpp>

#include <random>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// Passes into alternate halves: pixel p's samples are 1 + sigma[p] * (normal noise).
void addPasses(Film& film, const std::vector<float>& sigma, int passes, int perPass,
               std::mt19937& rng, const std::vector<std::uint8_t>* mask = nullptr) {
    std::normal_distribution<float> normal;
    ThreadStats stats;
    for (int pass = 0; pass < passes; ++pass) {
        for (std::uint32_t p = 0; p < sigma.size(); ++p) {
            if (mask && !(*mask)[p]) continue;
            for (int i = 0; i < perPass; ++i) {
                film.addSample(p);
                film.add(p, Vec3(1.0f + sigma[p] * normal(rng)), stats);
            }
        }
        film.commitPass(pass % 2);
    }
}

} // namespace

TEST_CASE("Adaptive sampling samples the noisy pixels and leaves the quiet ones", "[engine]") {
    // 32x16: the left 16x16 tile's pixels are noisy (its left half four times the variance of
    // its right half), the right tile's are not noisy at all.
    const int w = 32, h = 16;
    std::vector<float> sigma(std::size_t(w) * h, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < 16; ++x) sigma[std::size_t(y) * w + x] = x < 8 ? 2.0f : 1.0f;
    Film film(w, h);
    film.enableHalfBuffers();
    std::mt19937 rng(7);
    addPasses(film, sigma, 8, 2, rng); // 16 samples each

    AdaptiveSampler::Settings s;
    s.minSpp = 16;
    s.meanSpp = 64;
    AdaptiveSampler sampler(w, h, s);
    AdaptiveSampler::Decision d = sampler.update(film, {});
    CHECK(d.pixels == std::uint64_t(w * h));
    CHECK(d.meanSpp == Approx(16.0));
    const auto& mask = sampler.activeMask();
    std::size_t quietOn = 0, noisyOn = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) (x < 16 ? noisyOn : quietOn) += mask[std::size_t(y) * w + x];
    CHECK(quietOn == 0);       // no noise: the first 16 samples were all they need
    CHECK(noisyOn == 16 * 16); // each needs more than 16 of the mean 64

    // Sample the active pixels until none is short of its need: the needs are as the square
    // roots of the noise, so the left half ends with about twice the samples of the right.
    for (int round = 0; round < 100 && d.activePixels > 0; ++round) {
        addPasses(film, sigma, 2, 2, rng, &mask);
        d = sampler.update(film, {});
        if (d.activePixels == d.pixels) break; // nothing short: the fallback samples all
    }
    double left = 0, right = 0, quiet = 0;
    for (int y = 1; y < h - 1; ++y) {
        left += double(film.samplesOf(std::uint32_t(y * w + 3)));
        right += double(film.samplesOf(std::uint32_t(y * w + 12)));
        quiet += double(film.samplesOf(std::uint32_t(y * w + 24)));
    }
    INFO("left " << left << ", right " << right << ", quiet " << quiet);
    CHECK(quiet == 16.0 * (h - 2));
    CHECK(left / right == Approx(2.0).epsilon(0.25));
    // The mean need is the asked mean: the quiet tile keeps its 16, and the rest of 64 * 512
    // goes to the noisy tile's pixels, split 2:1 between its halves (within the window's blur
    // at the boundary).
    CHECK(left / (h - 2) == Approx(2.0 / 3.0 * (64.0 * 512 - 16 * 256) / 128.0).epsilon(0.1));
}

TEST_CASE("Adaptive sampling samples every pixel when none falls short", "[engine]") {
    const int w = 16, h = 16;
    std::vector<float> sigma(std::size_t(w) * h, 0.5f);
    Film film(w, h);
    film.enableHalfBuffers();
    std::mt19937 rng(3);
    addPasses(film, sigma, 4, 4, rng);
    AdaptiveSampler::Settings s;
    s.minSpp = 16;
    s.targetRelMse = 1e6; // reached by any image: every need is the minimum, met
    AdaptiveSampler sampler(w, h, s);
    AdaptiveSampler::Decision d = sampler.update(film, {});
    CHECK(d.activePixels == d.pixels);
    for (std::uint8_t m : sampler.activeMask()) CHECK(m == 1);
}

TEST_CASE("Adaptive path renders do not depend on the thread count or the packet width",
          "[engine][modes]") {
    auto scene = loadSceneAt("cornell-box", 40, 24);
    EmbreeScene accel(*scene);
    auto run = [&](int threads, int width) {
        EngineSettings engine;
        engine.quiet = true;
        engine.threads = threads;
        engine.packetWidth = width;
        engine.adaptiveSampling = true;
        engine.adaptiveMinSpp = 4;
        PathSettings s = pathSettings(scene->render, ModeOverrides{16, 0, 0});
        return renderPath(*scene, accel, s, engine);
    };
    RenderResult one = run(1, 16);
    CHECK(meanValue(one.image) > 0.01);
    // The mean asked: 16 per pixel, and less than a pair of passes more.
    const double pixels = 40.0 * 24.0;
    CHECK(double(one.stats.totals.samples) >= 16 * pixels);
    CHECK(double(one.stats.totals.samples) < 18 * pixels);
    CHECK(one.samplesDone == 16);
    for (auto [threads, width] : {std::pair{2, 16}, std::pair{2, 4}}) {
        RenderResult r = run(threads, width);
        CHECK(r.stats.totals.samples == one.stats.totals.samples);
        CHECK(sameBits(r.image, one.image));
    }
}

TEST_CASE("Adaptive sampling lowers the error at the same mean samples per pixel", "[modes]") {
    // The Cornell box seen from afar: two thirds of the image see nothing (no noise), which
    // uniform sampling spends as much on as on the box.
    auto scene = loadSceneAt("cornell-box", 48, 48);
    scene->camera.fovY = 50;
    EmbreeScene accel(*scene);
    auto run = [&](int spp, bool adaptive, std::uint64_t seed) {
        EngineSettings engine;
        engine.quiet = true;
        engine.threads = 2;
        engine.seed = seed;
        engine.adaptiveSampling = adaptive;
        engine.adaptiveMinSpp = 8;
        return renderPath(*scene, accel, pathSettings(scene->render, ModeOverrides{spp, 0, 0}),
                          engine);
    };
    Image truth = run(1024, false, 99).image;
    double uniform = 0, adaptive = 0;
    for (std::uint64_t seed : {1, 2}) {
        RenderResult u = run(32, false, seed), a = run(32, true, seed);
        CHECK(a.stats.totals.samples < u.stats.totals.samples * 1.1);
        uniform += relMse(u.image, truth);
        adaptive += relMse(a.image, truth);
        // No bias beyond the noise: the image means agree.
        CHECK(meanValue(a.image) == Approx(meanValue(truth)).epsilon(0.02));
    }
    INFO("relMSE uniform " << uniform / 2 << ", adaptive " << adaptive / 2);
    CHECK(adaptive < 0.7 * uniform);
}
