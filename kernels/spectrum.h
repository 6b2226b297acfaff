// Per-wavelength evaluation for spectral rendering (docs/spectral.md): the few wavelengths a path
// carries (hero-wavelength sampling, Wilkie et al. 2014: four per path as pbrt-v4, three in
// rayproc's render mode; the count is a template parameter), their importance density over the
// visible range, and the spectra evaluated at them: tables sampled every nanometre, Jakob &
// Hanika's sigmoid polynomials (RGB upsampling), Planck's law.
// Pure functions of their arguments; the tables themselves are set up in src/spectral/.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

namespace rayproc::kernels::spectral {

constexpr int kWavelengths = 4;
constexpr float kLambdaMin = 360.0f, kLambdaMax = 830.0f;

// Values at a path's N wavelengths (kWavelengths by default; rayproc's spectral render mode
// carries 3, one in each float of the engine's colour triples, docs/spectral.md).
template <int N>
struct SampledSpectrumN {
    std::array<float, N> v{};
    SampledSpectrumN() = default;
    explicit SampledSpectrumN(float c) { v.fill(c); }
    float operator[](int i) const { return v[i]; }
    float& operator[](int i) { return v[i]; }
    SampledSpectrumN& operator*=(const SampledSpectrumN& o) {
        for (int i = 0; i < N; ++i) v[i] *= o.v[i];
        return *this;
    }
    SampledSpectrumN& operator*=(float s) {
        for (float& x : v) x *= s;
        return *this;
    }
    SampledSpectrumN& operator+=(const SampledSpectrumN& o) {
        for (int i = 0; i < N; ++i) v[i] += o.v[i];
        return *this;
    }
    float average() const {
        float s = 0;
        for (float x : v) s += x;
        return s / N;
    }
};
template <int N>
inline SampledSpectrumN<N> operator*(SampledSpectrumN<N> a, const SampledSpectrumN<N>& b) {
    return a *= b;
}
template <int N>
inline SampledSpectrumN<N> operator*(SampledSpectrumN<N> a, float s) { return a *= s; }
template <int N>
inline SampledSpectrumN<N> operator+(SampledSpectrumN<N> a, const SampledSpectrumN<N>& b) {
    return a += b;
}
using SampledSpectrum = SampledSpectrumN<kWavelengths>;

// The importance density over wavelength: p(l) proportional to sech^2(a (l - mu)) on
// [360, 830] nm, a = 0.0072 / nm, mu = 538 nm (the visible-importance shape pbrt-v4 uses; it
// follows the sum of the matching functions). Its normalisation and inverse CDF are derived
// here from a and mu: with T(l) = tanh(a (l - mu)), the CDF is (T(l) - T(360)) / (T(830) -
// T(360)), so l = mu + atanh(T(360) + u (T(830) - T(360))) / a.
struct VisibleDensity {
    static constexpr double a = 0.0072, mu = 538.0;
    static double tLow() { return std::tanh(a * (double(kLambdaMin) - mu)); }
    static double tHigh() { return std::tanh(a * (double(kLambdaMax) - mu)); }
};

inline float visibleWavelengthPdf(float nm) {
    if (nm < kLambdaMin || nm > kLambdaMax) return 0;
    static const float norm =
        float(VisibleDensity::a / (VisibleDensity::tHigh() - VisibleDensity::tLow()));
    float c = std::cosh(float(VisibleDensity::a) * (nm - float(VisibleDensity::mu)));
    return norm / (c * c);
}

inline float sampleVisibleWavelength(float u) {
    static const float t0 = float(VisibleDensity::tLow()), t1 = float(VisibleDensity::tHigh());
    float nm = float(VisibleDensity::mu) + std::atanh(t0 + u * (t1 - t0)) / float(VisibleDensity::a);
    return std::clamp(nm, kLambdaMin, kLambdaMax);
}

// A path's N wavelengths: the hero from u, the others at u + i/N (mod 1), each with its own
// density. Averaging f(l_i) / p(l_i) over them estimates the integral of f (each term alone
// does; their average is a one-sample estimator with the stratified offsets).
template <int N>
struct SampledWavelengthsN {
    std::array<float, N> lambda{}, pdf{};

    // The i-th wavelength's position in [0, 1): u + i/N (mod 1).
    static float offset(float u, int i) {
        float up = u + float(i) / N;
        return up >= 1 ? up - 1 : up;
    }
    static SampledWavelengthsN sampleVisible(float u) {
        SampledWavelengthsN w;
        for (int i = 0; i < N; ++i) {
            w.lambda[i] = sampleVisibleWavelength(offset(u, i));
            w.pdf[i] = visibleWavelengthPdf(w.lambda[i]);
        }
        return w;
    }
    static SampledWavelengthsN sampleUniform(float u) {
        SampledWavelengthsN w;
        const float range = kLambdaMax - kLambdaMin;
        for (int i = 0; i < N; ++i) {
            w.lambda[i] = kLambdaMin + offset(u, i) * range;
            w.pdf[i] = 1.0f / range;
        }
        return w;
    }
    // A wavelength-dependent event (dispersion) keeps only the hero: the others' densities
    // become 0 and the hero's carries the whole estimate.
    void terminateSecondary() {
        if (N < 2 || pdf[1] == 0) return;
        for (int i = 1; i < N; ++i) pdf[i] = 0;
        pdf[0] /= N;
    }
};
using SampledWavelengths = SampledWavelengthsN<kWavelengths>;

// A table sampled at every integer nanometre from 360 to 830 (471 values), evaluated at the
// nearest sample; zero outside.
constexpr int kDenseCount = int(kLambdaMax - kLambdaMin) + 1;
inline float denseAt(const float* table, float nm) {
    int i = int(std::lround(nm)) - int(kLambdaMin);
    return (i < 0 || i >= kDenseCount) ? 0.0f : table[i];
}
template <int N>
inline SampledSpectrumN<N> denseSample(const float* table, const SampledWavelengthsN<N>& w) {
    SampledSpectrumN<N> s;
    for (int i = 0; i < N; ++i) s[i] = denseAt(table, w.lambda[i]);
    return s;
}

// Jakob & Hanika 2019: s(l) = S(c0 t^2 + c1 t + c2), S(x) = 1/2 + x / (2 sqrt(1 + x^2)), with
// t = (l - 360) / 470 (rayproc keeps the normalised wavelength: the polynomial in nanometres
// loses digits to cancellation in float). Infinite x (a flat 0 or 1) gives 0 or 1.
inline float sigmoid(float x) {
    // Beyond 1e8 (and at infinity) S differs from 0 or 1 by less than 1 / (4 x^2), far below
    // float's resolution; x^2 would overflow before that.
    if (std::abs(x) > 1e8f) return x > 0 ? 1.0f : 0.0f;
    return 0.5f + x / (2.0f * std::sqrt(1.0f + x * x));
}
inline float sigmoidPolynomial(const float c[3], float nm) {
    float t = (nm - kLambdaMin) * (1.0f / (kLambdaMax - kLambdaMin));
    return sigmoid((c[0] * t + c[1]) * t + c[2]);
}

// Planck's law: spectral radiance of a blackbody at `kelvin`, W / (sr m^2 m), at `nm`.
inline double planck(double nm, double kelvin) {
    if (kelvin <= 0) return 0;
    const double c = 299792458.0, h = 6.62607015e-34, kb = 1.380649e-23;
    double l = nm * 1e-9;
    return (2 * h * c * c) / (std::pow(l, 5) * std::expm1((h * c) / (l * kb * kelvin)));
}

// pbrt-v4's normalised blackbody: Planck's law over its value at the peak (Wien's displacement
// law, b = 2.897771955e-3 m K), so its maximum is 1.
inline double blackbodyNormalized(double nm, double kelvin) {
    if (kelvin <= 0) return 0;
    double peakNm = 2.897771955e-3 / kelvin * 1e9;
    return planck(nm, kelvin) / planck(peakNm, kelvin);
}

// CIE XYZ of a sampled radiance: each of the matching functions times L over the density,
// averaged over the wavelengths, over the integral of y-bar (so a spectrum of luminance 1 gives
// Y = 1). Wavelengths whose density is 0 (terminated) add nothing.
struct Xyz {
    float x = 0, y = 0, z = 0;
};
template <int N>
inline Xyz sampledToXyz(const SampledSpectrumN<N>& L, const SampledWavelengthsN<N>& w,
                        const float* xBar, const float* yBar, const float* zBar, float yIntegral) {
    Xyz r;
    for (int i = 0; i < N; ++i) {
        if (w.pdf[i] == 0) continue;
        float l = L[i] / w.pdf[i];
        r.x += denseAt(xBar, w.lambda[i]) * l;
        r.y += denseAt(yBar, w.lambda[i]) * l;
        r.z += denseAt(zBar, w.lambda[i]) * l;
    }
    float s = 1.0f / (N * yIntegral);
    r.x *= s;
    r.y *= s;
    r.z *= s;
    return r;
}

} // namespace rayproc::kernels::spectral
