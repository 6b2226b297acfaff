// The film: fixed-point accumulation that does not depend on the order of contributions (so
// images do not depend on the thread count), and the bookkeeping of invalid, clamped and
// missing samples.
#include "engine/film.h"

#include "test_util.h"

#include <catch2/catch.hpp>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

using namespace rayproc;
using namespace rayproc::test;

namespace {

struct Contribution {
    std::uint32_t pixel;
    Vec3 radiance;
};

// Radiance over many orders of magnitude (1e-4 .. 1e3), the case where float sums depend on
// the order of addition.
std::vector<Contribution> randomContributions(int count, std::uint32_t pixels, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::uint32_t> pixel(0, pixels - 1);
    std::uniform_real_distribution<float> exponent(-4.0f, 3.0f);
    std::vector<Contribution> v;
    for (int i = 0; i < count; ++i) {
        Vec3 r(std::pow(10.0f, exponent(rng)), std::pow(10.0f, exponent(rng)),
               std::pow(10.0f, exponent(rng)));
        v.push_back({pixel(rng), r});
    }
    return v;
}

void addAll(Film& film, const std::vector<Contribution>& cs, ThreadStats& stats) {
    for (const Contribution& c : cs) {
        film.addSample(c.pixel);
        film.add(c.pixel, c.radiance, stats);
    }
}

} // namespace

TEST_CASE("Film accumulation does not depend on the order of contributions", "[engine]") {
    constexpr int kW = 8, kH = 4;
    auto cs = randomContributions(20000, kW * kH, 12345);
    auto shuffled = cs;
    std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(99));
    auto reversed = cs;
    std::reverse(reversed.begin(), reversed.end());

    ThreadStats s1, s2, s3;
    Film a(kW, kH), b(kW, kH), c(kW, kH);
    addAll(a, cs, s1);
    addAll(b, shuffled, s2);
    addAll(c, reversed, s3);
    a.commitPass();
    b.commitPass();
    c.commitPass();
    Image ia = a.resolve(), ib = b.resolve(), ic = c.resolve();
    CHECK(sameBits(ia, ib));
    CHECK(sameBits(ia, ic));
    CHECK(s1.invalidSamples == 0);
    CHECK(s1.clampedSamples == 0);

    // The test has teeth: plain float sums of the same data do depend on the order.
    std::vector<float> sumA(kW * kH * 3, 0.0f), sumB(kW * kH * 3, 0.0f);
    for (auto& x : cs)
        for (int ch = 0; ch < 3; ++ch) sumA[x.pixel * 3 + ch] += x.radiance[ch];
    for (auto& x : shuffled)
        for (int ch = 0; ch < 3; ++ch) sumB[x.pixel * 3 + ch] += x.radiance[ch];
    CHECK(std::memcmp(sumA.data(), sumB.data(), sumA.size() * sizeof(float)) != 0);

    // And the film's value is the sum to within the fixed-point resolution.
    std::vector<double> exact(kW * kH * 3, 0.0);
    std::vector<int> samples(kW * kH, 0);
    for (auto& x : cs) {
        ++samples[x.pixel];
        for (int ch = 0; ch < 3; ++ch) exact[x.pixel * 3 + ch] += double(x.radiance[ch]);
    }
    for (int p = 0; p < kW * kH; ++p) {
        REQUIRE(samples[p] > 0);
        for (int ch = 0; ch < 3; ++ch) {
            double expected = exact[p * 3 + ch] / samples[p];
            CHECK(ia.pixels[p * 3 + ch] == Approx(expected).epsilon(1e-6));
        }
    }
}

TEST_CASE("Film accumulation from two threads equals the sequential one, over passes", "[engine]") {
    constexpr int kW = 4, kH = 4;
    auto pass1 = randomContributions(5000, kW * kH, 1);
    auto pass2 = randomContributions(5000, kW * kH, 2);

    Film seq(kW, kH);
    ThreadStats st;
    addAll(seq, pass1, st);
    seq.commitPass();
    addAll(seq, pass2, st);
    seq.commitPass();

    Film par(kW, kH);
    tbb::enumerable_thread_specific<ThreadStats> local;
    tbb::task_arena arena(2);
    for (const auto* pass : {&pass2, &pass1}) { // the passes in the other order, too
        arena.execute([&] {
            tbb::parallel_for(std::size_t(0), pass->size(), [&](std::size_t i) {
                par.addSample((*pass)[i].pixel);
                par.add((*pass)[i].pixel, (*pass)[i].radiance, local.local());
            });
        });
        par.commitPass();
    }
    // Passes fold into doubles in pass order, so only the same pass order promises the same
    // bits; the two-thread film in that order matches the sequential one exactly.
    Film par2(kW, kH);
    for (const auto* pass : {&pass1, &pass2}) {
        arena.execute([&] {
            tbb::parallel_for(std::size_t(0), pass->size(), [&](std::size_t i) {
                par2.addSample((*pass)[i].pixel);
                par2.add((*pass)[i].pixel, (*pass)[i].radiance, local.local());
            });
        });
        par2.commitPass();
    }
    Image a = seq.resolve(), b = par.resolve(), c = par2.resolve();
    CHECK(sameBits(a, c));
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
        CHECK(b.pixels[i] == Approx(a.pixels[i]).epsilon(1e-6));
    for (std::uint32_t p = 0; p < kW * kH; ++p) CHECK(seq.samplesOf(p) == par2.samplesOf(p));
}

TEST_CASE("Film discards and counts NaN and Inf contributions", "[engine]") {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    Film film(2, 1);
    ThreadStats stats;
    film.addSample(0);
    film.addSample(0);
    film.add(0, Vec3(0.5f, 0.25f, 1.0f), stats);
    film.add(0, Vec3(nan, 1.0f, 1.0f), stats);
    film.add(0, Vec3(1.0f, inf, 1.0f), stats);
    film.add(0, Vec3(1.0f, 1.0f, -inf), stats);
    film.add(0, Vec3(0.5f, 0.25f, 1.0f), stats);
    film.addSample(1);
    film.add(1, Vec3(nan), stats);
    film.commitPass();
    CHECK(stats.invalidSamples == 4);
    CHECK(stats.clampedSamples == 0);

    Image img = film.resolve();
    // Pixel 0: two valid contributions over two samples; the invalid ones left no trace.
    CHECK(img.at(0, 0)[0] == 0.5f);
    CHECK(img.at(0, 0)[1] == 0.25f);
    CHECK(img.at(0, 0)[2] == 1.0f);
    // Pixel 1: its only contribution was discarded; the sample still counts, so it is black.
    CHECK(img.at(1, 0)[0] == 0.0f);
    CHECK(img.at(1, 0)[1] == 0.0f);
    CHECK(img.at(1, 0)[2] == 0.0f);
    for (float v : img.pixels) CHECK(std::isfinite(v));
}

TEST_CASE("Film pixels without samples stay black and are counted", "[engine]") {
    Film film(4, 3);
    ThreadStats stats;
    CHECK(film.pixelsWithoutSamples() == 12);
    film.addSample(0);
    film.add(0, Vec3(1.0f), stats);
    film.addSample(5);
    film.addSample(5);
    film.add(5, Vec3(2.0f), stats);
    // Radiance for a pixel whose sample was never recorded is not shown.
    film.add(7, Vec3(3.0f), stats);
    film.commitPass();
    CHECK(film.pixelsWithoutSamples() == 10);
    CHECK(film.samplesOf(0) == 1);
    CHECK(film.samplesOf(5) == 2);
    CHECK(film.samplesOf(7) == 0);

    Image img = film.resolve();
    REQUIRE(img.width == 4);
    REQUIRE(img.height == 3);
    for (int p = 0; p < 12; ++p) {
        float expected = p == 0 ? 1.0f : p == 5 ? 1.0f : 0.0f;
        for (int c = 0; c < 3; ++c) {
            INFO("pixel " << p << " channel " << c);
            CHECK(img.pixels[p * 3 + c] == expected);
        }
    }

    // A later pass that samples pixel 7 shows the radiance of both passes over its samples.
    film.addSample(7);
    film.commitPass();
    CHECK(film.pixelsWithoutSamples() == 9);
    CHECK(film.resolve().at(3, 1)[0] == 3.0f);
}

TEST_CASE("Film clamps contributions beyond its fixed-point range and counts them", "[engine]") {
    const float limit = float(Film::kFixedLimit);
    Film film(3, 1);
    ThreadStats stats;
    for (std::uint32_t p = 0; p < 3; ++p) film.addSample(p);
    film.add(0, Vec3(4.0f * limit, 1.0f, 0.0f), stats);  // positive, beyond the range
    film.add(1, Vec3(0.0f, -4.0f * limit, 1.0f), stats); // negative, beyond the range
    film.add(2, Vec3(0.5f * limit, 0.0f, 0.0f), stats);  // large but within
    film.commitPass();
    CHECK(stats.clampedSamples == 2);
    CHECK(stats.invalidSamples == 0);

    Image img = film.resolve();
    // Clamped to the limit with its sign, and nothing else touched.
    CHECK(img.at(0, 0)[0] == Approx(Film::kFixedLimit).epsilon(1e-6));
    CHECK(img.at(0, 0)[1] == 1.0f);
    CHECK(img.at(1, 0)[1] == Approx(-Film::kFixedLimit).epsilon(1e-6));
    CHECK(img.at(1, 0)[2] == 1.0f);
    CHECK(img.at(2, 0)[0] == 0.5f * limit);
}

TEST_CASE("Film sums of bright contributions do not wrap, whatever their order", "[engine]") {
    // The sun's luminance, 1.6e9, seen by 64 samples of one pass: 1e11 in all, far beyond the
    // 2^31 radiance a 64-bit fixed-point sum holds at 2^32 units per radiance unit.
    const float sun = 1.6e9f;
    Film film(2, 1);
    ThreadStats stats;
    for (int i = 0; i < 64; ++i) {
        film.addSample(0);
        film.add(0, Vec3(sun, 0.25f * sun, 1e-3f), stats);
    }
    // Pixel 1 mixes signs around the low word's wrap: the carries must cancel exactly.
    std::vector<float> values;
    for (int i = 0; i < 40; ++i) values.push_back(i % 2 ? -3.0e9f : 5.0e9f);
    for (float v : values) {
        film.addSample(1);
        film.add(1, Vec3(v, -v, 0.5f), stats);
    }
    film.commitPass();
    CHECK(stats.clampedSamples == 0);
    Image img = film.resolve();
    CHECK(img.at(0, 0)[0] == Approx(double(sun)).epsilon(1e-9));
    CHECK(img.at(0, 0)[1] == Approx(0.25 * double(sun)).epsilon(1e-9));
    CHECK(img.at(0, 0)[2] == Approx(1e-3).epsilon(1e-6));
    CHECK(img.at(1, 0)[0] == Approx(1.0e9).epsilon(1e-9)); // (20 * 5e9 - 20 * 3e9) / 40
    CHECK(img.at(1, 0)[1] == Approx(-1.0e9).epsilon(1e-9));
    CHECK(img.at(1, 0)[2] == 0.5f);

    // The same contributions in another order and from two threads give the same bits.
    Film other(2, 1);
    tbb::task_arena arena(2);
    tbb::enumerable_thread_specific<ThreadStats> local;
    arena.execute([&] {
        tbb::parallel_for(0, 104, [&](int k) {
            int i = 103 - k;
            if (i < 64) {
                other.addSample(0);
                other.add(0, Vec3(sun, 0.25f * sun, 1e-3f), local.local());
            } else {
                float v = values[std::size_t(i - 64)];
                other.addSample(1);
                other.add(1, Vec3(v, -v, 0.5f), local.local());
            }
        });
    });
    other.commitPass();
    CHECK(sameBits(img, other.resolve()));
}

// rayproc serve shows a render's tiles as they finish: the pass so far is visible in
// resolveInProgress, not in resolve, and after the commit both agree.
TEST_CASE("Film shows the current pass while it runs, for display only", "[engine]") {
    Film film(4, 1);
    ThreadStats stats;
    film.addSample(0);
    film.add(0, Vec3(2.0f, 1.0f, 0.5f), stats);
    film.addSample(0);
    film.add(0, Vec3(4.0f, 1.0f, 0.5f), stats);
    Image committed = film.resolve();
    Image running = film.resolveInProgress();
    CHECK(committed.pixels[0] == 0.0f);
    CHECK(running.pixels[0] == 3.0f);
    CHECK(running.pixels[1] == 1.0f);
    CHECK(running.pixels[3] == 0.0f); // pixel 1: no sample yet
    film.commitPass();
    CHECK(film.resolve().pixels == film.resolveInProgress().pixels);
    // A second pass in flight averages with the first.
    film.addSample(0);
    film.add(0, Vec3(6.0f, 1.0f, 0.5f), stats);
    CHECK(film.resolveInProgress().pixels[0] == 4.0f);
    CHECK(film.resolve().pixels[0] == 3.0f);
}

TEST_CASE("Film's unit follows the scene's brightness: its brightest light is 2^36 units",
          "[engine][film]") {
    CHECK(Film::exponentFor(17.0) == Film::kDefaultExponent);        // the Cornell box
    CHECK(Film::exponentFor(16.0) == 32);
    CHECK(Film::exponentFor(31.99) == 32);
    CHECK(Film::exponentFor(32.0) == 31);
    CHECK(Film::exponentFor(15.99) == 33);
    CHECK(Film::exponentFor(1.0) == 36);
    CHECK(Film::exponentFor(1e-30) == 36 + 100);                     // 1e-30 ~ 2^-99.7
    CHECK(Film::exponentFor(1e30) == 36 - 99);                       // 1e30 ~ 2^99.7
    CHECK(Film::exponentFor(0.0) == Film::kDefaultExponent);         // no light
    CHECK(Film::exponentFor(std::numeric_limits<double>::quiet_NaN()) == Film::kDefaultExponent);
    CHECK(Film::exponentFor(std::numeric_limits<double>::infinity()) == Film::kDefaultExponent);
    Film film(1, 1, 40);
    CHECK(film.exponent() == 40);
    CHECK(film.fixedLimit() == std::ldexp(1.0, 56));
    CHECK(Film(1, 1).fixedLimit() == Film::kFixedLimit);
}

TEST_CASE("Film sums dim and bright scenes' contributions exactly and in any order",
          "[engine][film]") {
    // The random contributions of the first test (1e-4 .. 1e3) times 1e-25 and 1e25, on films
    // whose unit follows that brightness: the same relative precision, the same determinism.
    constexpr int kW = 4, kH = 4;
    auto cs = randomContributions(5000, kW * kH, 777);
    for (double scale : {1e-25, 1e25}) {
        INFO("contributions times " << scale);
        auto scaled = cs;
        for (Contribution& c : scaled) c.radiance = c.radiance * float(scale);
        auto reversed = scaled;
        std::reverse(reversed.begin(), reversed.end());
        int e = Film::exponentFor(1e3 * scale);
        Film a(kW, kH, e), b(kW, kH, e), fixed32(kW, kH);
        ThreadStats sa, sb, s32;
        addAll(a, scaled, sa);
        addAll(b, reversed, sb);
        addAll(fixed32, scaled, s32);
        a.commitPass();
        b.commitPass();
        fixed32.commitPass();
        Image ia = a.resolve(), ib = b.resolve(), i32 = fixed32.resolve();
        CHECK(sameBits(ia, ib));
        CHECK(sa.clampedSamples == 0);
        std::vector<double> exact(kW * kH * 3, 0.0);
        std::vector<int> samples(kW * kH, 0);
        for (const Contribution& c : scaled) {
            ++samples[c.pixel];
            for (int ch = 0; ch < 3; ++ch) exact[c.pixel * 3 + ch] += double(c.radiance[ch]);
        }
        int wrong32 = 0;
        for (int p = 0; p < kW * kH; ++p)
            for (int ch = 0; ch < 3; ++ch) {
                double expected = exact[p * 3 + ch] / samples[p];
                CHECK(ia.pixels[p * 3 + ch] == Approx(expected).epsilon(1e-6));
                wrong32 += !(std::abs(i32.pixels[p * 3 + ch] / expected - 1) < 1e-6);
            }
        // The test has teeth: a fixed unit of 2^-32 radiance reads 1e-25 as 0 and clamps 1e25.
        CHECK(wrong32 == kW * kH * 3);
    }
}

TEST_CASE("Film pixels whose mean passes float's range are the largest float, not Inf",
          "[engine][film]") {
    Film film(2, 1, Film::exponentFor(3e38)); // a light at float's limit: no clamped sample
    ThreadStats stats;
    film.addSample(0);
    film.addSample(1);
    film.add(0, Vec3(3e38f, 3e38f, 1e30f), stats); // one sample of 6e38 in all
    film.add(0, Vec3(3e38f, -3e38f, 0.0f), stats);
    film.add(1, Vec3(-3e38f, 0.0f, 0.0f), stats);
    film.add(1, Vec3(-3e38f, 0.0f, 0.0f), stats);
    film.commitPass();
    CHECK(stats.clampedSamples == 0);
    Image img = film.resolve();
    const float largest = std::numeric_limits<float>::max();
    CHECK(img.at(0, 0)[0] == largest);
    CHECK(img.at(0, 0)[1] == 0.0f);
    CHECK(img.at(0, 0)[2] == Approx(1e30).epsilon(0.01)); // 2^-36 of 3e38 is 4e27
    CHECK(img.at(1, 0)[0] == -largest);
    CHECK(sameBits(film.resolveInProgress(), img));
}
