// White balance as pbrt-v4's "rgb" film does it with its default "cie1931" sensor
// (docs/spectral.md, "The film's sensor"): the XYZ the sensor measured is adapted from the white
// of CIE daylight at a temperature to the colour space's white by the Bradford transform (a von
// Kries scaling in Lam's cone-like space).
#pragma once

#include "spectral/color_space.h"

namespace rayproc::spectral {

struct Chromaticity {
    double x = 0, y = 0;
};
// (x, y) of a colour's XYZ.
Chromaticity chromaticityOf(const Xyz& c);

// The chromaticity of pbrt-v4's daylight illuminant for a white balance of `kelvin`: the
// temperature is first corrected to the present second radiation constant (x 1.4388 / 1.4380,
// the CIE's correlated colour temperature of the D series); below 4000 K, where the D series is
// not defined, a blackbody at that temperature, else the D-series illuminant (daylightIlluminant)
// of the chromaticity on the CIE daylight locus at it. The chromaticity of the spectrum itself
// (its XYZ), as pbrt-v4 takes it.
Chromaticity daylightWhite(double kelvin);

// The Bradford chromatic adaptation in XYZ from white `from` to white `to` (both at Y = 1):
// M^-1 diag(M to / M from) M with Lam's matrix M. It maps from's XYZ to to's exactly.
Mat3 bradfordAdaptation(Chromaticity from, Chromaticity to);

// The matrix product a b.
Mat3 operator*(const Mat3& a, const Mat3& b);

} // namespace rayproc::spectral
