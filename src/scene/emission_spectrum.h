// An emitter's own spectrum (docs/spectral.md, "Emission spectra"): a pbrt-v4 light or area
// light given as a blackbody, (wavelength, value) pairs or a named CIE illuminant keeps that
// spectrum beside the RGB colour RGB mode renders with. The spectral mode evaluates it at a
// path's wavelengths instead of upsampling the colour again as an RGB illuminant spectrum.
//
// The convention: `values` is the spectral counterpart of `rgb`, so an emitter whose RGB value
// is k * rgb (a light's intensity or a shape's emission, after "scale", "power" and the like)
// emits k * values. Spectra from files are normalised to luminance 1 (their y-bar sum equals
// spectral::cieYIntegral(), and rgb has luminance 1): pbrt-v4 divides every light's spectrum by
// its photometric integral before "scale" and "power" multiply it.
#pragma once

#include "core/math.h"
#include "spectral/spectra.h"

#include <memory>
#include <string>

namespace rayproc {

struct EmissionSpectrum {
    spectral::DenseSpectrum values; // every nanometre, 360..830
    Vec3 rgb{0, 0, 0};              // the colour RGB mode takes for it (linear sRGB)
    std::string label;              // what the file said, for messages ("blackbody 2700")
};
using EmissionSpectrumRef = std::shared_ptr<const EmissionSpectrum>;

// `s` scaled to luminance 1 (y-bar sum = cieYIntegral()), with its colour `rgb`; nullptr when
// `s` has no luminance.
EmissionSpectrumRef emissionAtLuminance1(const spectral::DenseSpectrum& s, const Vec3& rgb,
                                         std::string label);

// k of an emitter whose RGB value is `value` = k * e.rgb: the ratio in rgb's largest channel
// (0 when rgb is black).
float emissionScale(const EmissionSpectrum& e, const Vec3& value);

// Two emitters that add up into one (constant skies): RGB a + b, and the spectrum of both,
// where an emitter without a spectrum of its own (nullptr) counts as its RGB illuminant spectrum
// in sRGB (what the spectral mode makes of it). nullptr when neither has a spectrum.
EmissionSpectrumRef sumOfEmissions(const Vec3& a, const EmissionSpectrumRef& sa, const Vec3& b,
                                   const EmissionSpectrumRef& sb);

} // namespace rayproc
