// Progressive caustics (gi/progressive_caustics.h): the radius sequence of Knaus & Zwicker's
// probabilistic progressive photon mapping, and the caustic of scenes/caustic-pool.json (a
// small light through a wavy water slab onto a white floor) converging to the path-mode
// reference of tests/golden/ as passes accumulate, where one k-nearest map stays biased.
#include "../analytic/analytic.h"

#include "gi/progressive_caustics.h"

using namespace rayproc;
using namespace rayproc::test;

TEST_CASE("Progressive radii: r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1), shrinking as i^((alpha-1)/2)",
          "[gi][progressive]") {
    const double alpha = 2.0 / 3.0;
    CHECK(progressiveRadiusRatio(1, alpha) == 1.0);
    CHECK(progressiveRadiusRatio(2, alpha) == Approx(std::sqrt((1 + alpha) / 2)).epsilon(1e-12));
    CHECK(progressiveRadiusRatio(3, alpha) ==
          Approx(std::sqrt((1 + alpha) / 2 * (2 + alpha) / 3)).epsilon(1e-12));
    // r_i^2 i^(1 - alpha) tends to a constant (Gamma(1) / Gamma(1 + alpha) ... ): the same at
    // i = 1000 and 4000 to 0.1%.
    auto scaled = [&](int i) {
        double r = progressiveRadiusRatio(i, alpha);
        return r * r * std::pow(double(i), 1 - alpha);
    };
    CHECK(scaled(4000) == Approx(scaled(1000)).epsilon(1e-3));
    // alpha = 1 keeps the radius; a smaller alpha shrinks faster.
    CHECK(progressiveRadiusRatio(100, 1.0) == 1.0);
    CHECK(progressiveRadiusRatio(100, 0.5) < progressiveRadiusRatio(100, alpha));
}

TEST_CASE("Progressive radii by samples: a pass of s samples takes the mean square of s indices",
          "[gi][progressive]") {
    const double alpha = 2.0 / 3.0;
    // One sample a pass is the sequence itself.
    ProgressiveRadius single(alpha);
    for (int i = 1; i <= 50; ++i) {
        double r = progressiveRadiusRatio(i, alpha);
        CHECK(single.next(1) == Approx(r * r).epsilon(1e-12));
    }
    // Passes of 1, 3 and 8 samples: the mean of (r_i / r_1)^2 over their indices 1, 2-4, 5-12.
    ProgressiveRadius grouped(alpha);
    auto meanSquare = [&](int from, int to) {
        double sum = 0;
        for (int i = from; i <= to; ++i) sum += std::pow(progressiveRadiusRatio(i, alpha), 2);
        return sum / double(to - from + 1);
    };
    CHECK(grouped.next(1) == Approx(1.0));
    CHECK(grouped.next(3) == Approx(meanSquare(2, 4)).epsilon(1e-12));
    CHECK(grouped.next(8) == Approx(meanSquare(5, 12)).epsilon(1e-12));
    // A pass's photons: the per-sample count times its samples, within the cap.
    CHECK(progressivePassPhotons(50000, 1) == 50000);
    CHECK(progressivePassPhotons(50000, 8) == 400000);
    CHECK(progressivePassPhotons(50000, 16) == 800000);
    CHECK(progressivePassPhotons(100000, 16) == kMaxPassPhotons);
    CHECK(progressivePassPhotons(2000000, 4) == 2000000);
    CHECK(progressiveMaxPassPhotons(65536) == kMaxPassPhotons);
}

namespace {

constexpr int kSize = 32;
// At 64 spp the progressive render's relMSE was 0.29 of one map's (0.0020 against 0.0069;
// 4, 16, 64 spp gave 0.0122, 0.0043, 0.0020, and one map 0.0149, 0.0089, 0.0069, stalling on
// its blur). The reference's own relMSE is ~4e-4 (scripts/make-references).
constexpr double kProgressiveGain = 0.5;

// The pool in gi with 50,000 caustic photons a pass, seed 1; progressive caustics and the
// per-pixel radius as asked (both gi's defaults).
RenderResult renderPool(const Scene& scene, const EmbreeScene& accel, int spp,
                        bool progressive = true, bool pixelRadius = true, int threads = 2) {
    EngineSettings engine;
    engine.threads = threads;
    engine.seed = 1;
    engine.quiet = true;
    GiSettings s = giSettings(scene, ModeOverrides{spp, 0, 0});
    s.progressiveCaustics = progressive;
    s.causticPixelRadius = pixelRadius;
    s.causticPhotons = 50000;
    return renderGi(scene, accel, s, engine);
}

} // namespace

TEST_CASE("Progressive caustics converge on the caustic pool, where one k-nearest map stalls",
          "[gi][progressive][golden]") {
    Image ref = readImage(goldenPath("caustic-pool-path.exr"));
    REQUIRE(ref.width == kSize);
    REQUIRE(ref.height == kSize);
    auto scene = loadSceneAt("caustic-pool", kSize, kSize);
    EmbreeScene accel(*scene);
    double previous = 1e30;
    for (int spp : {4, 16, 64}) {
        RenderResult r = renderPool(*scene, accel, spp, true);
        double e = relMse(r.image, ref);
        INFO(spp << " spp: relMSE " << e << ", " << extraStat(r, "gi/caustic_passes")
                 << " caustic maps, last radius " << extraStat(r, "gi/caustic_last_radius"));
        CHECK(e < previous);
        previous = e;
    }
    RenderResult single = renderPool(*scene, accel, 64, false);
    double eSingle = relMse(single.image, ref);
    INFO("64 spp, progressive " << previous << ", one map " << eSingle);
    CHECK(previous < kProgressiveGain * eSingle);
}

namespace {

// The mean luminance of `img` over pixels, over the reference's at the same pixels.
double ratioOver(const Image& img, const Image& ref, const std::vector<int>& pixels) {
    double a = 0, b = 0;
    for (int i : pixels) {
        int x = i % ref.width, y = i / ref.width;
        for (int c = 0; c < 3; ++c) {
            a += img.at(x, y)[c];
            b += ref.at(x, y)[c];
        }
    }
    return a / b;
}

} // namespace

TEST_CASE("Per-pixel caustic radii keep the caustic's bright lines brighter than one sequence",
          "[gi][progressive][golden][heavy]") {
    // The brightest tenth of the pool's pixels (in the 131,072-spp golden) are the caustic's
    // lines: a wide disc spreads them into the dark cells beside them. Per pixel, a line's
    // radius starts at its own k-nearest distance and shrinks with the photons it receives.
    Image ref = readImage(goldenPath("caustic-pool-path.exr"));
    auto scene = loadSceneAt("caustic-pool", kSize, kSize);
    EmbreeScene accel(*scene);
    std::vector<int> order(std::size_t(kSize * kSize));
    for (int i = 0; i < kSize * kSize; ++i) order[std::size_t(i)] = i;
    auto lum = [&](int i) {
        const auto& p = ref.at(i % kSize, i / kSize);
        return p[0] + p[1] + p[2];
    };
    std::sort(order.begin(), order.end(), [&](int a, int b) { return lum(a) < lum(b); });
    std::vector<int> brightest(order.end() - kSize * kSize / 10, order.end());
    RenderResult pixel = renderPool(*scene, accel, 64, true, true, 2);
    RenderResult global = renderPool(*scene, accel, 64, true, false, 2);
    double bp = ratioOver(pixel.image, ref, brightest);
    double bg = ratioOver(global.image, ref, brightest);
    double ep = relMse(pixel.image, ref), eg = relMse(global.image, ref);
    INFO("brightest tenth: per pixel " << bp << ", one sequence " << bg << "; relMSE " << ep
                                       << " against " << eg);
    INFO("mean pixel radius " << extraStat(pixel, "gi/caustic_mean_pixel_radius")
                              << ", the sequence's last " << extraStat(global, "gi/caustic_last_radius"));
    CHECK(std::abs(1 - bp) < std::abs(1 - bg));
    CHECK(ep < 1.1 * eg); // no noisier than the sequence where the sharpness is gained
    // And the image does not depend on the threads: the counts are integer sums.
    RenderResult one = renderPool(*scene, accel, 4, true, true, 1);
    RenderResult two = renderPool(*scene, accel, 4, true, true, 2);
    CHECK(sameBits(one.image, two.image));
}
