// Shared machinery of the pbrt-v4 BSDF tests (tests/statistical/*_bsdf_test.cpp,
// tests/kernels/bsdf_energy_test.cpp): directions by angle, the chi-square of sampleBsdf against
// evalBsdf's pdf with the per-sample consistency checks, a weighted-histogram test of the sample
// weights against evalBsdf's f |cos| (for BSDFs whose pdf is only an estimate), and the
// Monte Carlo directional albedo.
#pragma once

#include "statistical.h"

#include "kernels/bsdf_sampling.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace rayproc::test {

using kernels::BsdfParams;

inline const Vec3 kUp(0.0f, 0.0f, 1.0f);

// The direction at polar angle theta from +z (past 90: below the surface) and azimuth phi.
inline Vec3 direction(float thetaDegrees, float phiDegrees = 30.0f) {
    float t = thetaDegrees * kPi / 180.0f, p = phiDegrees * kPi / 180.0f;
    return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

// A histogram frame around `axis` wide enough for a lobe of Trowbridge-Reitz alpha: out to
// 4 atan(3 alpha) (the whole sphere for alpha >= ~0.45), as bsdf_sampling_test.cpp does.
inline float lobeCosMin(float alpha) { return std::cos(std::min(kPi, 4.0f * std::atan(3.0f * alpha))); }

struct ChiRun {
    ChiSquareResult chi;
    int invalid = 0, delta = 0;
    int pdfMismatches = 0, weightMismatches = 0;
};

// kSamples draws of sampleBsdf(b, wo) with ng = ns = +z, binned around `axis` over
// cos in [cosMin, 1] (failed samples go outside), tested against `pdf` (default: evalBsdf's).
// Every sample's pdf and weight are compared with evalBsdf's pdf and f |cos| / pdf.
inline ChiRun chiSquareRun(const BsdfParams& b, const Vec3& wo, const Vec3& axis, float cosMin,
                           std::uint64_t seed, std::function<double(const Vec3&)> pdf = {}) {
    if (!pdf)
        pdf = [&](const Vec3& wi) {
            float p;
            kernels::evalBsdf(b, wo, wi, kUp, kUp, p);
            return double(p);
        };
    DirectionHistogram hist(axis, cosMin, kThetaBins, kPhiBins);
    TestRng rng(seed);
    ChiRun run;
    for (int i = 0; i < kSamples; ++i) {
        Vec2 u = rng.uniform2();
        float uc = rng.uniform();
        kernels::BsdfSample s = kernels::sampleBsdf(b, wo, kUp, kUp, u, uc);
        if (!s.valid || s.delta) {
            run.invalid += !s.valid;
            run.delta += s.delta;
            hist.addOutside();
            continue;
        }
        hist.add(s.wi);
        float p;
        Vec3 f = kernels::evalBsdf(b, wo, s.wi, kUp, kUp, p);
        if (!(std::abs(s.pdf - p) <= 1e-4f * p)) ++run.pdfMismatches;
        Vec3 w = p > 0 ? f / p : Vec3(0.0f);
        for (int c = 0; c < 3; ++c)
            if (!(std::abs(s.weight[c] - w[c]) <= 1e-4f * std::max(1.0f, w[c]))) {
                ++run.weightMismatches;
                break;
            }
    }
    run.chi = chiSquareTest(hist.counts(), hist.expected(pdf, kSamples));
    return run;
}

inline void checkChiRun(const ChiRun& run, const std::string& label) {
    INFO(label << ": chi2 " << run.chi.chi2 << ", dof " << run.chi.dof << " (" << run.chi.bins
               << " bins, " << run.chi.pooledBins << " pooled), p-value " << run.chi.pValue
               << ", significance " << testSignificance() << ", failed samples " << run.invalid
               << ", delta samples " << run.delta);
    CHECK(run.chi.pValue > testSignificance());
    CHECK(run.delta == 0);
    CHECK(run.pdfMismatches == 0);
    CHECK(run.weightMismatches == 0);
}

// The weighted-histogram test: per bin of a (cos theta, phi) grid around `axis`, the mean of the
// sample weights falling in it, (1/N) sum w 1{wi in bin}, and the integral of evalBsdf's f |cos|
// over it (by m x m jittered points per bin), are two unbiased estimates of the same number.
// With both variances estimated, sum (A - B)^2 / (varA + varB) is chi-square with one degree of
// freedom per bin. Checks sampling and evaluation against each other without using the pdf.
// Delta samples are left out (evalBsdf has no delta part). Weights and f in `channel`.
struct WeightedRun {
    double chi2 = 0, pValue = 1;
    int bins = 0;
    double deltaFraction = 0, sampledTotal = 0, evaluatedTotal = 0;
};

inline WeightedRun weightedHistogramRun(const BsdfParams& sampled, const BsdfParams& evaluated,
                                        const Vec3& wo, const Vec3& axis, float cosMin,
                                        int samples, int perBinSide, std::uint64_t seed,
                                        int channel = 0) {
    DirectionHistogram hist(axis, cosMin, kThetaBins, kPhiBins);
    Vec3 ax = normalize(axis), tx, ty; // the histogram's frame
    orthonormalBasis(ax, tx, ty);
    int nb = hist.binCount();
    std::vector<double> sum(std::size_t(nb), 0.0), sum2(std::size_t(nb), 0.0);
    TestRng rng(seed);
    int deltas = 0;
    for (int i = 0; i < samples; ++i) {
        Vec2 u = rng.uniform2();
        float uc = rng.uniform();
        kernels::BsdfSample s = kernels::sampleBsdf(sampled, wo, kUp, kUp, u, uc);
        if (!s.valid) continue;
        if (s.delta) {
            ++deltas;
            continue;
        }
        std::size_t bin = std::size_t(hist.binOf(s.wi));
        double w = s.weight[channel];
        sum[bin] += w;
        sum2[bin] += w * w;
    }
    WeightedRun run;
    run.deltaFraction = double(deltas) / samples;
    double dc = (1.0 - cosMin) / kThetaBins, dp = 2.0 * kPi / kPhiBins;
    TestRng jitter(seed ^ 0xabcdefULL);
    BsdfParams e = evaluated;
    for (int it = 0; it < kThetaBins; ++it)
        for (int ip = 0; ip < kPhiBins; ++ip) {
            std::size_t bin = std::size_t(it * kPhiBins + ip);
            double c0 = 1.0 - (it + 1) * dc, p0 = ip * dp;
            // Evaluation side: m x m strata, one jittered point each, a fresh key each.
            double es = 0, es2 = 0;
            int m = perBinSide;
            for (int j = 0; j < m; ++j)
                for (int k = 0; k < m; ++k) {
                    double c = c0 + (j + jitter.uniform()) / m * dc;
                    double phi = p0 + (k + jitter.uniform()) / m * dp;
                    double sn = std::sqrt(std::max(0.0, 1.0 - c * c));
                    Vec3 wi = normalize(tx * float(sn * std::cos(phi)) +
                                        ty * float(sn * std::sin(phi)) + ax * float(c));
                    e.key = (std::uint64_t(bin) << 32) ^ std::uint64_t(j * m + k) ^ seed;
                    float p;
                    double v = kernels::evalBsdf(e, wo, wi, kUp, kUp, p)[channel];
                    es += v;
                    es2 += v * v;
                }
            double area = dc * dp, mm = double(m) * m;
            double b = area * es / mm;
            double varB = area * area * std::max(0.0, es2 / mm - (es / mm) * (es / mm)) / mm;
            double a = sum[bin] / samples;
            double varA = std::max(0.0, sum2[bin] / samples - a * a) / samples;
            run.sampledTotal += a;
            run.evaluatedTotal += b;
            if (varA + varB <= 0) {
                if (a != b) run.chi2 = std::numeric_limits<double>::infinity();
                continue;
            }
            run.chi2 += (a - b) * (a - b) / (varA + varB);
            ++run.bins;
        }
    run.pValue = chiSquarePValue(run.chi2, std::max(1, run.bins));
    return run;
}

// The directional albedo: the mean sample weight (failed samples count 0) per channel, with
// its standard error. `energyOf` may rescale each weight (e.g. undo radiance's 1 / eta^2).
struct Albedo {
    Vec3 mean, stdError;
};

inline Albedo directionalAlbedo(
    const BsdfParams& b, const Vec3& wo, int samples, std::uint64_t seed,
    std::function<Vec3(const kernels::BsdfSample&)> energyOf = {}) {
    TestRng rng(seed);
    double s[3] = {0, 0, 0}, s2[3] = {0, 0, 0};
    for (int i = 0; i < samples; ++i) {
        Vec2 u = rng.uniform2();
        float uc = rng.uniform();
        kernels::BsdfSample bs = kernels::sampleBsdf(b, wo, kUp, kUp, u, uc);
        if (!bs.valid) continue;
        Vec3 w = energyOf ? energyOf(bs) : bs.weight;
        for (int c = 0; c < 3; ++c) {
            s[c] += w[c];
            s2[c] += double(w[c]) * w[c];
        }
    }
    Albedo a;
    for (int c = 0; c < 3; ++c) {
        double m = s[c] / samples;
        a.mean[c] = float(m);
        a.stdError[c] = float(std::sqrt(std::max(0.0, s2[c] / samples - m * m) / samples));
    }
    return a;
}

// Whether 2000 samples of `b` from `wo` (key 3, a fixed stream) report, where not delta, the
// pdf evalBsdf gives for their direction (what MIS uses), and evalBsdf its own f and pdf again
// under the same key (a stochastic BSDF's estimate is a function of the key). Counts the
// samples that do not, and the valid non-delta ones.
inline void samplePdfConsistency(BsdfParams b, const Vec3& wo, int& valid, int& mismatches) {
    b.key = 3;
    TestRng rng(5);
    valid = mismatches = 0;
    for (int i = 0; i < 2000; ++i) {
        kernels::BsdfSample s = kernels::sampleBsdf(b, wo, kUp, kUp, rng.uniform2(), rng.uniform());
        if (!s.valid || s.delta) continue;
        ++valid;
        float p1, p2;
        Vec3 f1 = kernels::evalBsdf(b, wo, s.wi, kUp, kUp, p1);
        Vec3 f2 = kernels::evalBsdf(b, wo, s.wi, kUp, kUp, p2);
        if (p1 != s.pdf || p1 != p2 || length(f1 - f2) != 0) ++mismatches;
    }
}

} // namespace rayproc::test
