// Filter importance sampling (kernels/filter_sampling.h): the offsets of every filter follow |f|
// (chi-square against the filter itself, integrated by quadrature over each bin, not against the
// sampler's own table), and the weights carry f's sign with mean integral(f) / integral(|f|).
#include "statistical.h"

#include "kernels/filter_sampling.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

using namespace rayproc;
using namespace rayproc::kernels;
using namespace rayproc::test;

namespace {

constexpr int kMaxBins = 16; // per axis, over [-rx, rx] x [-ry, ry]
constexpr int kQuad = 24;    // midpoint quadrature points per bin and axis
constexpr int kFilterSamples = 1000000;

FilterShape shape(FilterType t, float rx, float ry) {
    FilterShape s;
    s.type = t;
    s.rx = rx;
    s.ry = ry;
    return s;
}

// Bins per axis: for tabulated filters, whole table cells per bin (32 cells per unit radius);
// inside a cell the sampler is uniform by design, so a bin boundary through a cell would test
// the table's resolution rather than the sampling.
int binsFor(const FilterShape& s, float r) {
    if (s.type == FilterType::Box || s.type == FilterType::Triangle) return kMaxBins;
    int cells = std::max(1, int(32 * r));
    for (int d = 1;; ++d)
        if (cells % d == 0 && cells / d <= kMaxBins) return cells / d;
}

struct NamedShape {
    std::string name;
    FilterShape s;
};

std::vector<NamedShape> shapes() {
    FilterShape lanczos2 = shape(FilterType::Lanczos, 2, 2); // with negative lobes
    FilterShape gaussian = shape(FilterType::Gaussian, 1.5f, 1.5f);
    FilterShape narrow = shape(FilterType::Gaussian, 1, 0.75f);
    narrow.sigma = 0.3f;
    return {{"box 0.5", shape(FilterType::Box, 0.5f, 0.5f)},
            {"box 1 x 0.75", shape(FilterType::Box, 1, 0.75f)},
            {"triangle 1", shape(FilterType::Triangle, 1, 1)},
            {"triangle 2 x 1", shape(FilterType::Triangle, 2, 1)},
            {"gaussian 1.5", gaussian},
            {"gaussian 1 x 0.75, sigma 0.3", narrow},
            {"mitchell 2", shape(FilterType::Mitchell, 2, 2)},
            {"lanczos 0.5", shape(FilterType::Lanczos, 0.5f, 0.5f)},
            {"lanczos 2", lanczos2}};
}

// Integral of g(f) over each bin by the midpoint rule, row-major.
template <class G>
std::vector<double> binIntegrals(const FilterShape& s, G g) {
    int bx = binsFor(s, s.rx), by = binsFor(s, s.ry);
    std::vector<double> out(std::size_t(bx) * by, 0.0);
    double bw = 2.0 * s.rx / bx, bh = 2.0 * s.ry / by;
    for (int j = 0; j < by; ++j)
        for (int i = 0; i < bx; ++i) {
            double sum = 0;
            for (int b = 0; b < kQuad; ++b)
                for (int a = 0; a < kQuad; ++a) {
                    Vec2 p{float(-s.rx + bw * (i + (a + 0.5) / kQuad)),
                           float(-s.ry + bh * (j + (b + 0.5) / kQuad))};
                    sum += g(double(evalFilter(s, p)));
                }
            out[std::size_t(j) * bx + i] = sum * bw * bh / (kQuad * kQuad);
        }
    return out;
}

int binOf(const FilterShape& s, Vec2 p) {
    int bx = binsFor(s, s.rx), by = binsFor(s, s.ry);
    if (!(std::abs(p.x) <= s.rx) || !(std::abs(p.y) <= s.ry)) return -1;
    int i = int((p.x + s.rx) / (2 * s.rx) * bx), j = int((p.y + s.ry) / (2 * s.ry) * by);
    return std::min(j, by - 1) * bx + std::min(i, bx - 1);
}

// Draws the samples, histograms them (an extra last bin for offsets outside the support) and
// tests them against `target` (per-bin integrals).
void checkFollows(const FilterSampler& sampler, const std::vector<double>& target,
                  std::uint64_t seed) {
    const FilterShape& s = sampler.shape();
    std::size_t bins = target.size();
    std::vector<double> observed(bins + 1, 0.0), expected(bins + 1, 0.0);
    double total = 0;
    for (double t : target) total += t;
    for (std::size_t k = 0; k < bins; ++k) expected[k] = kFilterSamples * target[k] / total;
    TestRng rng(seed);
    for (int n = 0; n < kFilterSamples; ++n) {
        Vec2 p = sampler.sample(rng.uniform2()).offset;
        int b = binOf(s, p);
        observed[b < 0 ? bins : std::size_t(b)] += 1;
    }
    ChiSquareResult r = chiSquareTest(observed, expected);
    INFO("chi2 " << r.chi2 << " dof " << r.dof << " p " << r.pValue);
    CHECK(r.pValue > testSignificance());
}

} // namespace

TEST_CASE("Filter samples follow |f| (chi-square, every filter)", "[filter][statistical]") {
    std::uint64_t seed = 1;
    for (const NamedShape& n : shapes()) {
        INFO(n.name);
        FilterSampler sampler(n.s);
        checkFollows(sampler, binIntegrals(n.s, [](double f) { return std::abs(f); }), seed++);
    }
}

TEST_CASE("The positive-part sampler follows max(f, 0) with weight 1", "[filter][statistical]") {
    for (FilterShape s : {shape(FilterType::Mitchell, 2, 2), shape(FilterType::Lanczos, 2, 2)}) {
        FilterSampler sampler(s, /*positivePart=*/true);
        checkFollows(sampler, binIntegrals(s, [](double f) { return std::max(f, 0.0); }),
                     100 + int(s.type));
        TestRng rng(5);
        for (int n = 0; n < 10000; ++n) CHECK(sampler.sample(rng.uniform2()).weight == 1.0f);
    }
}

TEST_CASE("Filter sample weights carry f's sign - their mean is integral f / integral |f|",
          "[filter]") {
    for (const NamedShape& n : shapes()) {
        INFO(n.name);
        FilterSampler sampler(n.s);
        std::vector<double> pos = binIntegrals(n.s, [](double f) { return f; });
        std::vector<double> abs = binIntegrals(n.s, [](double f) { return std::abs(f); });
        double sf = 0, sa = 0;
        for (std::size_t k = 0; k < pos.size(); ++k) {
            sf += pos[k];
            sa += abs[k];
        }
        double expectedMean = sf / sa;
        CHECK(sampler.meanWeight() == Approx(expectedMean).margin(2e-3));
        TestRng rng(11);
        double sum = 0;
        int mismatched = 0, negative = 0;
        const int count = 200000;
        for (int i = 0; i < count; ++i) {
            FilterSample fs = sampler.sample(rng.uniform2());
            REQUIRE(std::abs(fs.weight) == 1.0f);
            float f = evalFilter(n.s, fs.offset);
            // Only samples in a table cell that straddles a zero of f can disagree.
            if (f * fs.weight < 0) ++mismatched;
            negative += fs.weight < 0;
            sum += fs.weight;
        }
        CHECK(mismatched < count / 200);
        // Weights are +-1: the standard error of their mean is at most 1 / sqrt(count).
        CHECK(sum / count == Approx(expectedMean).margin(4.0 / std::sqrt(double(count)) + 2e-3));
        bool hasNegativeLobes = expectedMean < 0.999;
        CHECK((negative > 0) == hasNegativeLobes);
    }
    // Box, triangle and gaussian are positive: every weight is exactly 1.
    CHECK(FilterSampler(shape(FilterType::Gaussian, 1.5f, 1.5f)).meanWeight() == 1.0);
}

TEST_CASE("Filter definitions: known values", "[filter]") {
    FilterShape tri = shape(FilterType::Triangle, 1, 2);
    CHECK(evalFilter(tri, {0.5f, 1.0f}) == Approx(0.5 * 1.0));
    CHECK(evalFilter(tri, {1.5f, 0.0f}) == 0.0f);
    // Gaussian minus its value at the radius: zero at and beyond the radius.
    FilterShape g = shape(FilterType::Gaussian, 1.5f, 1.5f);
    double g0 = 1.0 / std::sqrt(2 * M_PI * 0.25), gr = g0 * std::exp(-1.5 * 1.5 / 0.5);
    CHECK(evalFilter(g, {0, 0}) == Approx((g0 - gr) * (g0 - gr)).epsilon(1e-5));
    CHECK(evalFilter(g, {1.5f, 0}) == Approx(0.0).margin(1e-7));
    // Mitchell with B = C = 1/3: m(0) = (6 - 2/3) / 6 = 8/9, m(1) = 1/18, m(2) = 0.
    FilterShape m = shape(FilterType::Mitchell, 2, 2);
    CHECK(evalFilter(m, {0, 0}) == Approx(64.0 / 81.0));
    CHECK(evalFilter(m, {1, 0}) == Approx(8.0 / 9.0 / 18.0));
    CHECK(evalFilter(m, {2, 0}) == Approx(0.0).margin(1e-6));
    // Lanczos: sinc(0) = 1; sinc(1) = 0.
    FilterShape l = shape(FilterType::Lanczos, 2, 2);
    CHECK(evalFilter(l, {0, 0}) == Approx(1.0));
    CHECK(evalFilter(l, {1, 0}) == Approx(0.0).margin(1e-6));
    CHECK(evalFilter(l, {2.5f, 0}) == 0.0f);
}

TEST_CASE("Mitchell with huge B or C keeps its shape: finite values and samples", "[filter]") {
    // B and C enter linearly, so for B -> inf the filter tends to B m_B(x) m_B(y) with
    // m_B(t) = (-9 t^3 + 12 t^2 - 2) / 6 on |t| <= 1 and (2 - t)^3 / 6 on 1 < |t| <= 2: its
    // shape is m_B(x) m_B(y) / m_B(0)^2 (B = 1e20 made 1e40, beyond float: an all-black image).
    auto mB = [](double t) {
        t = std::abs(t);
        return t <= 1 ? (-9 * t * t * t + 12 * t * t - 2) / 6 : std::pow(2 - t, 3) / 6;
    };
    for (float big : {1e20f, 1e30f, 3e38f}) {
        FilterShape m = shape(FilterType::Mitchell, 2, 2);
        m.b = big;
        m.c = 0;
        float centre = evalFilter(m, {0, 0});
        REQUIRE(std::isfinite(centre));
        REQUIRE(centre != 0);
        for (float x : {0.25f, 0.5f, 1.0f, 1.5f})
            for (float y : {0.0f, 0.75f, 1.25f}) {
                double expected = mB(x) * mB(y) / (mB(0) * mB(0));
                CHECK(evalFilter(m, {x, y}) / centre == Approx(expected).margin(1e-5));
            }
        FilterSampler sampler(m, true);
        int nonZero = 0;
        for (int i = 0; i < 64; ++i) {
            FilterSample fs = sampler.sample({(i % 8 + 0.5f) / 8, (i / 8 + 0.5f) / 8});
            CHECK(std::isfinite(fs.offset.x));
            CHECK(std::isfinite(fs.offset.y));
            nonZero += fs.weight == 1.0f;
        }
        CHECK(nonZero == 64);
    }
    // C huge too, and both, with either sign.
    for (auto [b, c] : {std::pair{0.0f, 1e30f}, std::pair{-1e30f, 1e20f}}) {
        FilterShape m = shape(FilterType::Mitchell, 2, 2);
        m.b = b;
        m.c = c;
        FilterSampler sampler(m, true);
        FilterSample fs = sampler.sample({0.3f, 0.6f});
        CHECK(std::isfinite(fs.offset.x));
        CHECK(fs.weight == 1.0f);
    }
}
