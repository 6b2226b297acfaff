// Spectra for set-up and conversion (docs/spectral.md): tables sampled every nanometre from
// 360 to 830 nm (the CIE matching functions, the CIE illuminants of colord-data, blackbodies,
// piecewise-linear spectra from a file's pairs) and their integrals against the matching
// functions. The per-wavelength evaluation during rendering is kernels/spectrum.h's.
#pragma once

#include "kernels/spectrum.h"

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace rayproc::spectral {

using kernels::spectral::kDenseCount;
using kernels::spectral::kLambdaMax;
using kernels::spectral::kLambdaMin;

// A spectrum sampled at every integer nanometre, 360..830.
struct DenseSpectrum {
    std::array<float, kDenseCount> values{};
    float at(float nm) const { return kernels::spectral::denseAt(values.data(), nm); }
    static DenseSpectrum sample(const std::function<double(double)>& f);
};

struct Xyz {
    double x = 0, y = 0, z = 0;
};

// The CIE 1931 2-degree matching functions, linearly interpolated between colord's 5 nm samples.
const DenseSpectrum& cieX();
const DenseSpectrum& cieY();
const DenseSpectrum& cieZ();
// The sum of y-bar over the 1 nm samples: the integral that maps a spectrum to luminance.
double cieYIntegral();

// X, Y, Z of a spectrum: the sums of f times each matching function over the 1 nm samples,
// over cieYIntegral() (pbrt-v4's SpectrumToXYZ).
Xyz toXyz(const std::function<double(double)>& f);
Xyz toXyz(const DenseSpectrum& s);

// A CIE illuminant of colord-data by name ("A", "D50", "D65", "F1".."F12", ...), scaled so
// that its luminance integral equals cieYIntegral() (Y = 1, as pbrt-v4 normalises its
// "stdillum-*" spectra); nullptr for an unknown name.
const DenseSpectrum* cieIlluminant(const std::string& name);
std::vector<std::string> cieIlluminantNames();

// The CIE D-series (daylight) illuminant of chromaticity (x, y): S0 + M1 S1 + M2 S2 of the CIE's
// daylight basis (CIE 15, the weights M1, M2 from x and y), at luminance 1 as cieIlluminant's.
// Meaningful near the daylight locus (correlated colour temperatures 4000-25000 K).
DenseSpectrum daylightIlluminant(double x, double y);
// ACES's white, the D-series illuminant at the chromaticity SMPTE ST 2065-1 gives its white
// point (0.32168, 0.33767), "D60" (pbrt-v4's "illum-acesD60"); luminance 1.
const DenseSpectrum& acesD60Illuminant();

// Piecewise-linear spectrum from (wavelength nm, value) pairs with ascending wavelengths; zero
// outside the first and last wavelength (pbrt-v4's PiecewiseLinearSpectrum).
double piecewiseLinear(const std::vector<double>& pairs, double nm);

} // namespace rayproc::spectral
