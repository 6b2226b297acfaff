// pbrt light sources as rayproc lights: point, spot, distant -> directional, infinite (constant)
// -> environment; AreaLightSource "diffuse" as the emission of the shapes that follow. Colours
// follow pbrt-v4's photometric convention (pbrt_values.h): RGB values are taken as they are,
// other spectra are normalised to luminance 1, then "scale" multiplies and "power" (point and
// spot lights) sets the emitted power as pbrt computes it.
#pragma once

#include "scene/pbrt/pbrt_transform.h"
#include "scene/pbrt/pbrt_values.h"
#include "scene/scene.h"

#include <optional>

namespace rayproc::pbrt {

// Adds the light to `scene` (an unsupported type warns and adds nothing). `toWorld` is the
// light's CTM in rayproc's world.
void convertLight(const std::string& type, const ParamList& params, const Mat4& toWorld,
                  const ValueReader& values, Warnings& warnings, const SourceLoc& loc,
                  Scene& scene);

struct AreaEmission {
    Vec3 radiance{0, 0, 0};
    bool twoSided = false;
};

// AreaLightSource; nothing for an unsupported type (with a warning).
std::optional<AreaEmission> convertAreaLight(const std::string& type, const ParamList& params,
                                             const ValueReader& values, Warnings& warnings,
                                             const SourceLoc& loc);

} // namespace rayproc::pbrt
