// kernels/spectrum.h: the wavelength density integrates to 1 and its sampling follows it
// (chi-square), hero wavelengths estimate XYZ without bias, the sigmoid's limits, Planck's law.
#include "core/math.h"
#include "kernels/spectrum.h"
#include "spectral/spectra.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace rayproc;
using namespace rayproc::kernels::spectral;

TEST_CASE("Visible wavelength density: normalised, inverted exactly", "[kernels][spectral]") {
    // Midpoint rule over 0.01 nm steps.
    double sum = 0;
    for (double nm = 360.005; nm < 830; nm += 0.01) sum += visibleWavelengthPdf(float(nm)) * 0.01;
    CHECK(sum == Approx(1.0).epsilon(1e-4));
    CHECK(visibleWavelengthPdf(359.9f) == 0.0f);
    CHECK(visibleWavelengthPdf(830.1f) == 0.0f);
    CHECK(sampleVisibleWavelength(0.0f) == Approx(360.0f).margin(0.01));
    CHECK(sampleVisibleWavelength(1.0f) == Approx(830.0f).margin(0.01));
    // The sample at u has CDF u: integrate the density up to it.
    for (float u : {0.1f, 0.37f, 0.5f, 0.9f}) {
        float l = sampleVisibleWavelength(u);
        double cdf = 0;
        for (double nm = 360.0005; nm < l; nm += 0.001) cdf += visibleWavelengthPdf(float(nm)) * 0.001;
        CHECK(cdf == Approx(u).margin(2e-4));
    }
}

TEST_CASE("Visible wavelength sampling: chi-square against the density", "[kernels][spectral][statistical]") {
    const int bins = 47, n = 200000;
    std::vector<double> counts(bins, 0), expected(bins, 0);
    uint64_t state = 0x9E3779B97F4A7C15ull;
    for (int i = 0; i < n; ++i) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        float u = float((state >> 40) * (1.0 / 16777216.0));
        float l = sampleVisibleWavelength(u);
        int b = std::min(bins - 1, int((l - kLambdaMin) / (kLambdaMax - kLambdaMin) * bins));
        counts[b] += 1;
    }
    const double w = (kLambdaMax - kLambdaMin) / bins;
    for (int b = 0; b < bins; ++b) {
        double s = 0;
        for (int k = 0; k < 100; ++k) s += visibleWavelengthPdf(float(kLambdaMin + (b + (k + 0.5) / 100) * w));
        expected[b] = s / 100 * w * n;
    }
    double chi2 = 0;
    for (int b = 0; b < bins; ++b) chi2 += (counts[b] - expected[b]) * (counts[b] - expected[b]) / expected[b];
    // 46 degrees of freedom: the 99.9% quantile is 81.4.
    CHECK(chi2 < 81.4);
    // A density shifted by 10 nm fails the same test (the test can fail).
    double shifted = 0;
    for (int b = 1; b < bins; ++b) {
        double e = expected[b - 1];
        shifted += (counts[b] - e) * (counts[b] - e) / e;
    }
    CHECK(shifted > 81.4);
}

TEST_CASE("Hero wavelengths estimate D65's XYZ without bias", "[kernels][spectral]") {
    const spectral::DenseSpectrum& d65 = *spectral::cieIlluminant("D65");
    const float* xb = spectral::cieX().values.data();
    const float* yb = spectral::cieY().values.data();
    const float* zb = spectral::cieZ().values.data();
    const float yInt = float(spectral::cieYIntegral());
    for (bool terminate : {false, true}) {
        double X = 0, Y = 0, Z = 0;
        const int n = 20000;
        for (int i = 0; i < n; ++i) {
            SampledWavelengths w = SampledWavelengths::sampleVisible((i + 0.5f) / n);
            if (terminate) w.terminateSecondary();
            SampledSpectrum L = denseSample(d65.values.data(), w);
            Xyz c = sampledToXyz(L, w, xb, yb, zb, yInt);
            X += c.x;
            Y += c.y;
            Z += c.z;
        }
        spectral::Xyz ref = spectral::toXyz(d65);
        INFO("terminated secondaries: " << terminate);
        CHECK(Y / n == Approx(1.0).epsilon(3e-3));
        CHECK(X / n == Approx(ref.x).epsilon(3e-3));
        CHECK(Z / n == Approx(ref.z).epsilon(3e-3));
    }
    // Uniform sampling gives the same.
    double Y = 0;
    for (int i = 0; i < 20000; ++i) {
        SampledWavelengths w = SampledWavelengths::sampleUniform((i + 0.5f) / 20000);
        Y += sampledToXyz(denseSample(d65.values.data(), w), w, xb, yb, zb, yInt).y;
    }
    CHECK(Y / 20000 == Approx(1.0).epsilon(3e-3));
}

TEST_CASE("Three hero wavelengths (the render mode's) are a third apart and unbiased",
          "[kernels][spectral][spectral-mode]") {
    using W3 = SampledWavelengthsN<3>;
    // The offsets: u, u + 1/3, u + 2/3 (mod 1), so the positions of one path cover [0, 1).
    W3 w = W3::sampleUniform(0.5f);
    const float range = kLambdaMax - kLambdaMin;
    CHECK(w.lambda[0] == Approx(kLambdaMin + 0.5f * range));
    CHECK(w.lambda[1] == Approx(kLambdaMin + (0.5f + 1.0f / 3) * range));
    CHECK(w.lambda[2] == Approx(kLambdaMin + (0.5f + 2.0f / 3 - 1) * range));
    const spectral::DenseSpectrum& d65 = *spectral::cieIlluminant("D65");
    const float* xb = spectral::cieX().values.data();
    const float* yb = spectral::cieY().values.data();
    const float* zb = spectral::cieZ().values.data();
    const float yInt = float(spectral::cieYIntegral());
    double X = 0, Y = 0, Z = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        W3 v = W3::sampleVisible((i + 0.5f) / n);
        for (int k = 0; k < 3; ++k) CHECK(v.pdf[k] == visibleWavelengthPdf(v.lambda[k]));
        Xyz c = sampledToXyz(denseSample(d65.values.data(), v), v, xb, yb, zb, yInt);
        X += c.x;
        Y += c.y;
        Z += c.z;
    }
    spectral::Xyz ref = spectral::toXyz(d65);
    CHECK(Y / n == Approx(1.0).epsilon(3e-3));
    CHECK(X / n == Approx(ref.x).epsilon(3e-3));
    CHECK(Z / n == Approx(ref.z).epsilon(3e-3));
}

TEST_CASE("Sigmoid polynomial limits and Planck's law", "[kernels][spectral]") {
    CHECK(sigmoid(0) == 0.5f);
    CHECK(sigmoid(INFINITY) == 1.0f);
    CHECK(sigmoid(-INFINITY) == 0.0f);
    CHECK(sigmoid(1e30f) == Approx(1.0f));
    const float flat[3] = {0, 0, -INFINITY};
    CHECK(sigmoidPolynomial(flat, 500) == 0.0f);
    // c0 t^2 + c1 t + c2 with t = (l - 360) / 470: x = 0 at 595 nm for (0, 2, -1).
    const float ramp[3] = {0, 2, -1};
    CHECK(sigmoidPolynomial(ramp, 595) == Approx(0.5f).margin(1e-6));
    CHECK(sigmoidPolynomial(ramp, 830) == Approx(0.5f + 1 / (2 * std::sqrt(2.0f))));
    // Wien's displacement: the normalised blackbody peaks at 1 at b / T.
    double peak = 2.897771955e-3 / 5000 * 1e9;
    CHECK(blackbodyNormalized(peak, 5000) == Approx(1.0));
    CHECK(blackbodyNormalized(peak - 20, 5000) < 1.0);
    CHECK(blackbodyNormalized(peak + 20, 5000) < 1.0);
    // Stefan-Boltzmann: pi times the integral of Planck's law over wavelength is sigma T^4.
    double sum = 0;
    for (double nm = 10; nm < 100000; nm += 1) sum += planck(nm + 0.5, 5000) * 1e-9;
    CHECK(kPi * sum == Approx(5.670374419e-8 * std::pow(5000.0, 4)).epsilon(1e-3));
}
