// RGB colour spaces as pbrt-v4 defines them: three primaries' chromaticities and an illuminant
// spectrum whose chromaticity is the white point (so its XYZ maps to RGB (1, 1, 1) exactly up
// to rounding). The matrices follow from those (SMPTE RP 177's derivation).
#pragma once

#include "spectral/spectra.h"

#include <string>

namespace rayproc::spectral {

struct Mat3 {
    double m[3][3] = {};
    Xyz apply(double a, double b, double c) const {
        return {m[0][0] * a + m[0][1] * b + m[0][2] * c, m[1][0] * a + m[1][1] * b + m[1][2] * c,
                m[2][0] * a + m[2][1] * b + m[2][2] * c};
    }
    Mat3 inverse() const;
};

enum class ColorSpaceId { Srgb, Rec2020, DciP3, Aces2065_1 };
constexpr int kColorSpaceCount = 4;

struct ColorSpace {
    ColorSpaceId id;
    const char* name; // pbrt-v4's name: "srgb", "rec2020", "dci-p3", "aces2065-1"
    double primaries[3][2]; // xy of red, green, blue
    const DenseSpectrum* illuminant; // luminance 1 (cieIlluminant)
    Xyz white;                       // the illuminant's XYZ, Y = 1
    Mat3 rgbToXyz, xyzToRgb;

    struct Rgb {
        double r, g, b;
    };
    Rgb fromXyz(const Xyz& c) const {
        Xyz v = xyzToRgb.apply(c.x, c.y, c.z);
        return {v.x, v.y, v.z};
    }
    Xyz toXyz(double r, double g, double b) const { return rgbToXyz.apply(r, g, b); }
};

const ColorSpace& colorSpace(ColorSpaceId id);
// By pbrt-v4's name; nullptr for any other.
const ColorSpace* colorSpaceByName(const std::string& name);

} // namespace rayproc::spectral
