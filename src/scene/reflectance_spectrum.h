// A material's reflectance-like constant given as a spectrum (docs/spectral.md, "Reflectance
// spectra"): a pbrt-v4 `spectrum reflectance [wavelength value ...]`, or an `rgb` reflectance
// under another ColorSpace than sRGB (that space's Jakob-Hanika spectrum), keeps its spectrum
// beside the sRGB colour RGB mode renders with (Material::color, Material::transmittance), as
// an emitter keeps its emission spectrum (scene/emission_spectrum.h). The spectral mode
// evaluates it at a path's wavelengths instead of upsampling the colour again with sRGB's table.
// Values are clamped to [0, 1], as pbrt-v4's materials clamp a reflectance they evaluate.
// A conductor's eta and k given so (pairs, an `rgb` under another colour space: that space's
// RGBUnboundedSpectrum) keep theirs in the same form, only clamped to >= 0 (Material::
// etaSpectrum, kSpectrum).
#pragma once

#include "spectral/spectra.h"

#include <memory>
#include <string>

namespace rayproc {

struct ReflectanceSpectrum {
    spectral::DenseSpectrum values; // every nanometre, 360..830, in [0, 1]
    std::string label;              // what the file said, for messages ("sampled spectrum")
};

} // namespace rayproc
