// RGB values as spectra, as pbrt-v4 defines them (docs/spectral.md, "RGB upsampling"), from the
// coefficient tables tools/rgb2spec_gen.cpp computes at build time:
// - a reflectance (RGB in [0, 1]): the sigmoid polynomial whose colour under the colour space's
//   illuminant is that RGB (RGBAlbedoSpectrum);
// - an unbounded value: m = max(r, g, b), the reflectance of rgb / 2m scaled by 2m
//   (RGBUnboundedSpectrum);
// - an illuminant: the unbounded spectrum times the colour space's illuminant
//   (RGBIlluminantSpectrum), so RGB (1, 1, 1) is that illuminant itself.
// These set-up objects use the refined coefficients.
#pragma once

#include "kernels/spectrum.h"
#include "spectral/color_space.h"

namespace rayproc::spectral {

struct SigmoidPolynomial {
    float c[3] = {0, 0, 0};
    float operator()(float nm) const { return kernels::spectral::sigmoidPolynomial(c, nm); }
};

// The table's coefficients for a reflectance RGB (each clamped to [0, 1]), trilinear between its
// cells: fast enough per texel, within 1e-3 of the RGB for 99.8% of the cube (docs/spectral.md);
// grey (r = g = b) is exact: a flat spectrum of that value.
SigmoidPolynomial rgbToCoefficients(const ColorSpace& cs, float r, float g, float b);
// The same polished by Gauss-Newton steps from the table's value (spectral::RgbFitter, a few
// microseconds): for values set up once, such as a material's constant colour.
SigmoidPolynomial rgbToCoefficientsRefined(const ColorSpace& cs, float r, float g, float b);
// The table's resolution (RES of tools/rgb2spec_gen.cpp).
int rgbTableResolution();

struct RgbAlbedoSpectrum {
    SigmoidPolynomial p;
    RgbAlbedoSpectrum(const ColorSpace& cs, float r, float g, float b);
    float operator()(float nm) const { return p(nm); }
};

struct RgbUnboundedSpectrum {
    float scale = 0;
    SigmoidPolynomial p;
    RgbUnboundedSpectrum(const ColorSpace& cs, float r, float g, float b);
    float operator()(float nm) const { return scale * p(nm); }
};

struct RgbIlluminantSpectrum {
    RgbUnboundedSpectrum rgb;
    const DenseSpectrum* illuminant;
    RgbIlluminantSpectrum(const ColorSpace& cs, float r, float g, float b)
        : rgb(cs, r, g, b), illuminant(cs.illuminant) {}
    float operator()(float nm) const { return rgb(nm) * illuminant->at(nm); }
};

} // namespace rayproc::spectral
