// pbrt-v4 materials as rayproc materials (docs/pbrt-import.md, "Materials", has the table):
// diffuse, coateddiffuse, conductor, dielectric, thindielectric, diffusetransmission and mix
// keep pbrt-v4's meaning and parameters (scene/material.h); coatedconductor becomes its
// conductor with a warning (no coat); interface is no surface; anything else is diffuse 0.5
// with a warning. Parameters may be textures; named metal spectra become RGB.
#pragma once

#include "scene/pbrt/pbrt_values.h"
#include "scene/scene.h"

#include <string>

namespace rayproc::pbrt {

struct MaterialResult {
    Material material;
    bool interface = false;  // pbrt's "interface": a medium boundary, no surface
    std::string mixNames[2]; // mix: the named materials, resolved by the builder
};

MaterialResult convertMaterial(const std::string& type, const ParamList& params,
                               const ValueReader& values, Warnings& warnings, const SourceLoc& loc);

} // namespace rayproc::pbrt
