// pbrt-v4 materials as rayproc's four (docs/pbrt-import.md has the table):
// - diffuse -> Diffuse (reflectance);
// - conductor -> Mirror when smooth, Glossy when rough; the colour is "reflectance" if given,
//   else the normal-incidence Fresnel reflectance of RGB or constant eta / k, else (named or
//   sampled spectra, pbrt's copper default) a neutral 0.9;
// - dielectric -> Dielectric (eta -> ior; roughness ignored with a warning);
// - coateddiffuse -> Diffuse with its base reflectance (the clear coat's highlight is lost;
//   rayproc's Glossy is a bare metal-like lobe that would turn the base colour specular);
// - interface -> no surface (shapes skipped) where known at the shape;
// - anything else -> Diffuse 0.5 with a warning.
#pragma once

#include "scene/pbrt/pbrt_values.h"
#include "scene/scene.h"

namespace rayproc::pbrt {

struct MaterialResult {
    Material material;
    bool interface = false; // pbrt's "interface": a medium boundary, no surface
};

// pbrt's roughness parameter as a GGX alpha (pbrt's RoughnessToAlpha is sqrt when
// "remaproughness" is on); rayproc's Material::roughness is sqrt(alpha).
double roughnessToAlpha(double roughness, bool remap);

MaterialResult convertMaterial(const std::string& type, const ParamList& params,
                               const ValueReader& values, Warnings& warnings, const SourceLoc& loc);

} // namespace rayproc::pbrt
