// Spectra to rayproc's linear sRGB. pbrt-v4 renders spectrally; rayproc renders in RGB, so each
// spectral parameter becomes one colour here:
// - blackbody emitters: Planck's law integrated against the CIE 1931 colour matching functions
//   (the analytic multi-lobe fit of Wyman, Sloan and Shirley, JCGT 2013), converted to linear
//   sRGB without white balancing (as pbrt's default "cie1931" sensor does), then normalised to
//   luminance 1, as pbrt-v4 normalises every non-RGB emission spectrum to 1 nit;
// - sampled (wavelength, value) spectra: the same integration; emission is normalised to
//   luminance 1, reflectances are lit by a 6504 K blackbody standing in for D65 and white
//   balanced so that a flat spectrum maps exactly to grey.
#pragma once

#include "core/math.h"

#include <string>
#include <vector>

namespace rayproc::pbrt {

// x-bar, y-bar, z-bar of CIE 1931 (2 degree observer) at `nm` nanometres.
void cieColorMatch(double nm, double& x, double& y, double& z);

// Linear sRGB (D65 white) from CIE XYZ.
Vec3 xyzToLinearSrgb(double x, double y, double z);

// Planck's spectral radiance at `nm` nanometres for temperature `kelvin` (W sr^-1 m^-3).
double planck(double nm, double kelvin);

// The colour of a blackbody at `kelvin`, luminance 1; negative sRGB components (very low or
// very high temperatures fall outside the gamut) are clamped to 0 before normalising.
Vec3 blackbodyRgb(double kelvin);

// Piecewise-linear spectra given as (wavelength nm, value) pairs, ascending wavelengths.
Vec3 sampledEmissionRgb(const std::vector<double>& pairs);    // luminance 1
Vec3 sampledReflectanceRgb(const std::vector<double>& pairs); // flat spectrum -> grey
double sampledValueAt(const std::vector<double>& pairs, double nm);

// The index of refraction (at the helium d line, 587.6 nm) of pbrt's named glass spectra
// ("glass-BK7", ...); false for other names.
bool namedGlassIor(const std::string& name, double& ior);

} // namespace rayproc::pbrt
