// Spectra to rayproc's linear sRGB. pbrt-v4 renders spectrally; rayproc's RGB mode takes one
// colour per spectral parameter, integrated against the CIE 1931 matching functions tabulated
// by colord-data (src/spectral/, docs/spectral.md) and converted with pbrt-v4's sRGB (primaries
// and the tabulated D65, so a flat spectrum maps exactly to grey):
// - emission (blackbody, sampled pairs, named "stdillum-*"): the spectrum's XYZ to sRGB without
//   white balancing (pbrt's default "cie1931" sensor), negative components clamped to 0, then
//   luminance 1, as pbrt-v4 divides every light's spectrum by its luminance;
// - sampled reflectances: the colour of the spectrum under D65, sRGB's illuminant (pbrt-v4's
//   colour of a reflectance).
// Sampled pairs are zero outside their first and last wavelength, as pbrt-v4's
// PiecewiseLinearSpectrum.
#pragma once

#include "core/math.h"
#include "scene/emission_spectrum.h"
#include "scene/reflectance_spectrum.h"
#include "scene/material.h"

#include <string>
#include <vector>

namespace rayproc::spectral {
struct ColorSpace;
}

namespace rayproc::pbrt {

// x-bar, y-bar, z-bar of CIE 1931 (2 degree observer) at `nm` nanometres (the tables, linear
// between their 5 nm samples).
void cieColorMatch(double nm, double& x, double& y, double& z);

// Linear sRGB (pbrt-v4's: the tabulated D65 white) from CIE XYZ.
Vec3 xyzToLinearSrgb(double x, double y, double z);

// The colour of a blackbody at `kelvin`, luminance 1; negative sRGB components (very low or
// very high temperatures fall outside the gamut) are clamped to 0 before normalising.
Vec3 blackbodyRgb(double kelvin);

// Piecewise-linear spectra given as (wavelength nm, value) pairs, ascending wavelengths.
Vec3 sampledEmissionRgb(const std::vector<double>& pairs);    // luminance 1
Vec3 sampledReflectanceRgb(const std::vector<double>& pairs); // flat spectrum -> grey
// Linear interpolation that holds the end values beyond the ends (for scalar uses: an index of
// refraction at one wavelength).
double sampledValueAt(const std::vector<double>& pairs, double nm);

// The colour of pbrt-v4's named illuminant "stdillum-A", "-D50", "-D65", "-F1".."-F12" or
// "illum-acesD60", luminance 1; false for other names.
bool namedIlluminantRgb(const std::string& name, Vec3& rgb);

// The same emission spectra kept whole for the spectral mode (scene/emission_spectrum.h): the
// spectrum at every nanometre at luminance 1 with the colour above (a blackbody: Planck's law,
// whose peak normalisation pbrt-v4's BlackbodySpectrum applies cancels in the luminance's);
// nullptr where the colour functions above give none (an unknown name, no luminance).
EmissionSpectrumRef blackbodyEmission(double kelvin);
EmissionSpectrumRef sampledEmission(const std::vector<double>& pairs);
EmissionSpectrumRef namedIlluminantEmission(const std::string& name);
// An emission "rgb" under another colour space than sRGB: its RGB illuminant spectrum in that
// space (pbrt-v4's RGBIlluminantSpectrum, whose photometric scale counts the illuminant alone,
// so it is not renormalised) with its sRGB colour rgbIlluminantToSrgb; nullptr under sRGB.
EmissionSpectrumRef rgbIlluminantEmission(const Vec3& rgb, const spectral::ColorSpace& cs);

// Reflectance-like spectra kept whole for the spectral mode (scene/reflectance_spectrum.h):
// (wavelength, value) pairs, zero outside their range; an "rgb" reflectance under another
// colour space than sRGB, that space's RGBAlbedoSpectrum (nullptr under sRGB, whose colour the
// spectral mode upsamples itself). Both clamped to [0, 1].
ReflectanceSpectrumRef sampledReflectance(const std::vector<double>& pairs);
ReflectanceSpectrumRef rgbAlbedoReflectance(const Vec3& rgb, const spectral::ColorSpace& cs);
// The same for an unbounded value (a conductor's eta or k): pairs, or an "rgb" under another
// colour space than sRGB as that space's RGBUnboundedSpectrum; clamped to >= 0 only.
ReflectanceSpectrumRef sampledUnbounded(const std::vector<double>& pairs);
ReflectanceSpectrumRef rgbUnboundedValues(const Vec3& rgb, const spectral::ColorSpace& cs);

// An "rgb" value written under another ColorSpace than sRGB, as sRGB (docs/pbrt-import.md,
// "Colour spaces"): pbrt-v4 upsamples it with that colour space's table (Jakob & Hanika), so
// rayproc does too and takes the spectrum's colour as the sRGB colour of the same kind: a
// reflectance's colour under D65 (clamped to [0, 1]), an unbounded value's likewise (clamped
// to >= 0), an illuminant's XYZ (the colour space's illuminant times the upsampled value,
// pbrt-v4's RGBIlluminantSpectrum) in sRGB. Under sRGB itself each returns `rgb` unchanged.
Vec3 rgbAlbedoToSrgb(const Vec3& rgb, const spectral::ColorSpace& cs);
Vec3 rgbUnboundedToSrgb(const Vec3& rgb, const spectral::ColorSpace& cs);
Vec3 rgbIlluminantToSrgb(const Vec3& rgb, const spectral::ColorSpace& cs);

} // namespace rayproc::pbrt
