// pbrt-v4's named metal spectra ("metal-Cu-eta", "metal-Au-k", ...) as RGB: rayproc renders in
// RGB, so each measured spectrum of a metal's complex index of refraction is represented by
// its values averaged over the sRGB primaries' bands (the fits Tungsten and Mitsuba use for
// RGB rendering; docs/pbrt-import.md, "Materials").
#pragma once

#include "core/math.h"

#include <string>

namespace rayproc {

// The complex index of a metal by its element name ("Ag", "Al", "Au", "Cu", "CuZn", "MgO",
// "TiO2"); false for other names.
bool namedMetal(const std::string& element, Vec3& eta, Vec3& k);

// The RGB value of pbrt-v4's named spectrum "metal-<element>-eta" or "metal-<element>-k";
// false if `name` is not one.
bool namedMetalSpectrum(const std::string& name, Vec3& out);

} // namespace rayproc
