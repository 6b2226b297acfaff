// Chi-square goodness-of-fit machinery for the statistical tests (tests/statistical/, tag
// [statistical]), after pbrt-v4's and Mitsuba's BSDF tests: draw N directions from a sampling
// routine, histogram them on a (cos theta, phi) grid of a chosen frame, integrate the routine's
// claimed pdf over every bin numerically to get the expected counts, pool the bins expecting
// fewer than 5 samples, and compute Pearson's statistic and its p-value from the regularised
// upper incomplete gamma function. A routine whose samples do not follow its pdf is rejected at
// significance 0.01, Sidak-corrected for the number of tests in the suite.
// Random numbers come from std::mt19937_64 with fixed seeds, so every test is deterministic.
#pragma once

#include "core/math.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <vector>

namespace rayproc::test {

// Uniform floats in [0, 1) from a fixed-seed 64-bit Mersenne twister (24-bit mantissa, as the
// renderer's own streams): the same numbers on every platform.
class TestRng {
public:
    explicit TestRng(std::uint64_t seed) : m_gen(0x5eed5eed12345678ULL ^ seed) {}
    float uniform() { return float(m_gen() >> 40) * (1.0f / 16777216.0f); }
    Vec2 uniform2() {
        float a = uniform();
        return {a, uniform()};
    }

private:
    std::mt19937_64 m_gen;
};

// Regularised lower incomplete gamma P(a, x) by its series, and upper Q(a, x) = 1 - P by
// Lentz's continued fraction (Numerical Recipes, 6.2): each where it converges fast.
inline double gammaPSeries(double a, double x) {
    double sum = 1.0 / a, term = sum;
    for (int n = 1; n < 100000; ++n) {
        term *= x / (a + n);
        sum += term;
        if (std::abs(term) < std::abs(sum) * 1e-16) break;
    }
    return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}
inline double gammaQContinuedFraction(double a, double x) {
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1.0) < 1e-16) break;
    }
    return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}
// Q(a, x) = Gamma(a, x) / Gamma(a), the upper tail.
inline double regularizedGammaQ(double a, double x) {
    if (x <= 0) return 1.0;
    if (x < a + 1.0) return 1.0 - gammaPSeries(a, x);
    return gammaQContinuedFraction(a, x);
}

// P(X >= chi2) for X chi-square distributed with `dof` degrees of freedom.
inline double chiSquarePValue(double chi2, int dof) {
    if (!(chi2 < std::numeric_limits<double>::infinity())) return 0.0;
    return regularizedGammaQ(0.5 * dof, 0.5 * chi2);
}

// The per-test significance that keeps the probability of any false rejection among
// `testCount` independent tests at `overall` (Sidak's correction).
inline double sidakSignificance(double overall, int testCount) {
    return 1.0 - std::pow(1.0 - overall, 1.0 / double(testCount));
}

struct ChiSquareResult {
    double chi2 = 0;
    int dof = 0;
    double pValue = 1;
    int bins = 0;       // bins used (after pooling)
    int pooledBins = 0; // bins merged into the pool
};

// Pearson's chi-square of observed against expected counts. Bins expecting fewer than
// `minExpected` samples are pooled into one (counted as a bin if it expects any). Observed
// samples where nothing is expected make the statistic infinite: p = 0.
inline ChiSquareResult chiSquareTest(const std::vector<double>& observed,
                                     const std::vector<double>& expected,
                                     double minExpected = 5.0) {
    ChiSquareResult r;
    double poolObs = 0, poolExp = 0;
    for (std::size_t i = 0; i < observed.size(); ++i) {
        if (expected[i] < minExpected) {
            poolObs += observed[i];
            poolExp += std::max(0.0, expected[i]);
            ++r.pooledBins;
            continue;
        }
        double d = observed[i] - expected[i];
        r.chi2 += d * d / expected[i];
        ++r.bins;
    }
    if (poolExp > 0) {
        double d = poolObs - poolExp;
        r.chi2 += d * d / poolExp;
        ++r.bins;
    } else if (poolObs > 0) {
        r.chi2 = std::numeric_limits<double>::infinity();
    }
    r.dof = std::max(1, r.bins - 1);
    r.pValue = chiSquarePValue(r.chi2, r.dof);
    return r;
}

// Directions binned on a (cos theta, phi) grid of a frame with axis `axis`, over cos theta in
// [cosMin, 1]: bins of equal solid angle. Directions outside the range (and failed samples) go
// to one extra bin, the last.
class DirectionHistogram {
public:
    DirectionHistogram(const Vec3& axis, float cosMin, int thetaBins, int phiBins)
        : m_axis(normalize(axis)), m_cosMin(cosMin), m_nt(thetaBins), m_np(phiBins),
          m_counts(std::size_t(thetaBins * phiBins + 1), 0.0) {
        orthonormalBasis(m_axis, m_t, m_b);
    }
    int binCount() const { return m_nt * m_np + 1; }
    int outsideBin() const { return m_nt * m_np; }

    int binOf(const Vec3& w) const {
        double c = dot(w, m_axis);
        if (c < m_cosMin) return outsideBin();
        int it = std::min(m_nt - 1, int((1.0 - c) / (1.0 - m_cosMin) * m_nt));
        double phi = std::atan2(double(dot(w, m_b)), double(dot(w, m_t)));
        if (phi < 0) phi += 2 * kPi;
        int ip = std::min(m_np - 1, int(phi / (2 * kPi) * m_np));
        return it * m_np + ip;
    }
    void add(const Vec3& w) { m_counts[std::size_t(binOf(w))] += 1.0; }
    void addOutside() { m_counts[std::size_t(outsideBin())] += 1.0; }
    const std::vector<double>& counts() const { return m_counts; }

    // Expected counts of `samples` draws from a density `pdf` (solid angle): the integral of
    // pdf over each bin in (cos theta, phi), where d(omega) = d(cos theta) d(phi), by adaptive
    // midpoint rules. A cell splits in four (down to 1/2^maxDepth of the bin) while its 4 x 4
    // and 8 x 8 estimates differ by more than 2% of the bin's Poisson noise, or while the
    // density is zero at some of its points and not at others: peaks (narrow lobes) and
    // discontinuities (the horizon, a light's silhouette) are integrated as accurately as the
    // smooth parts. A bin where samples landed but no point of the rule saw any density is
    // integrated again on a dense 512 x 512 grid, so that a sliver of support thinner than the
    // rule's spacing is not mistaken for samples where the pdf is zero (which still makes the
    // test fail if the dense grid finds nothing either). The outside bin gets what is left of
    // `samples`, assuming the density, extended by the failure probability, integrates to one.
    std::vector<double> expected(const std::function<double(const Vec3&)>& pdf, double samples,
                                 int maxDepth = 6) const {
        std::vector<double> e(m_counts.size(), 0.0);
        double dc = (1.0 - m_cosMin) / m_nt, dp = 2.0 * kPi / m_np;
        double inside = 0;
        for (int it = 0; it < m_nt; ++it)
            for (int ip = 0; ip < m_np; ++ip) {
                double c0 = 1.0 - (it + 1) * dc, p0 = ip * dp;
                Cell first = cell(pdf, c0, c0 + dc, p0, p0 + dp, 8);
                double tol = 0.02 * std::sqrt(std::max(first.integral, 1e-7) / samples);
                double integral = adaptive(pdf, c0, c0 + dc, p0, p0 + dp, tol, maxDepth);
                std::size_t bin = std::size_t(it * m_np + ip);
                if (integral == 0 && m_counts[bin] > 0)
                    integral = cell(pdf, c0, c0 + dc, p0, p0 + dp, 512).integral;
                e[bin] = integral * samples;
                inside += integral;
            }
        e[std::size_t(outsideBin())] = std::max(0.0, 1.0 - inside) * samples;
        return e;
    }

private:
    Vec3 direction(double c, double phi) const {
        double s = std::sqrt(std::max(0.0, 1.0 - c * c));
        return normalize(m_t * float(s * std::cos(phi)) + m_b * float(s * std::sin(phi)) +
                         m_axis * float(c));
    }
    struct Cell {
        double integral = 0;
        bool mixed = false; // the density is zero at some points and not at others
    };
    // The n x n midpoint rule over [c0, c1] x [p0, p1].
    Cell cell(const std::function<double(const Vec3&)>& pdf, double c0, double c1, double p0,
              double p1, int n) const {
        double sum = 0;
        int zeros = 0;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                double v = pdf(direction(c0 + (j + 0.5) / n * (c1 - c0),
                                         p0 + (i + 0.5) / n * (p1 - p0)));
                sum += v;
                zeros += v == 0;
            }
        return {sum * (c1 - c0) * (p1 - p0) / (double(n) * n), zeros > 0 && zeros < n * n};
    }
    double adaptive(const std::function<double(const Vec3&)>& pdf, double c0, double c1,
                    double p0, double p1, double tol, int depth) const {
        Cell coarse = cell(pdf, c0, c1, p0, p1, 4);
        Cell fine = cell(pdf, c0, c1, p0, p1, 8);
        bool converged = std::abs(fine.integral - coarse.integral) <= tol && !fine.mixed &&
                         !coarse.mixed;
        if (depth == 0 || converged) return fine.integral;
        double cm = 0.5 * (c0 + c1), pm = 0.5 * (p0 + p1);
        return adaptive(pdf, c0, cm, p0, pm, 0.5 * tol, depth - 1) +
               adaptive(pdf, cm, c1, p0, pm, 0.5 * tol, depth - 1) +
               adaptive(pdf, c0, cm, pm, p1, 0.5 * tol, depth - 1) +
               adaptive(pdf, cm, c1, pm, p1, 0.5 * tol, depth - 1);
    }

    Vec3 m_axis, m_t, m_b;
    float m_cosMin;
    int m_nt, m_np;
    std::vector<double> m_counts;
};

} // namespace rayproc::test
