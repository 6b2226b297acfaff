// pbrt light sources as rayproc lights: point, spot, goniometric, distant -> directional,
// infinite (constant or image) -> environment; AreaLightSource "diffuse" as the emission of the
// shapes that follow. Colours follow pbrt-v4's photometric convention (pbrt_values.h): RGB
// values are taken as they are, other spectra are normalised to luminance 1 and kept whole
// beside the colour for the spectral mode (Light::spectrum, Shape::emissionSpectrum); "scale"
// multiplies, "power" (point, spot, goniometric) sets the emitted power and "illuminance"
// (distant, infinite) the illuminance, as pbrt-v4 computes them (docs/pbrt-import.md).
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
    Vec3 radiance{0, 0, 0}; // L * scale (before any "power")
    bool twoSided = false;
    double power = -1; // "power" (W); > 0: the radiance is set from the shapes' area
    EmissionSpectrumRef spectrum; // L's own spectrum (ValueReader::emission), or nullptr
};

// The radiance the shapes of one Shape directive emit: e.radiance, or, when "power" is given,
// rescaled so that the shapes emit that power in total (pbrt-v4: phi = pi A L, twice for
// two-sided). pbrt-v4 applies "power" to each triangle of a mesh separately (a triangle is a
// shape there); we apply it to the directive's whole area, which is what "power" means.
Vec3 areaRadianceForPower(const AreaEmission& e, double area);
// The world-space area of the shapes of one Shape directive placed by `toWorld`.
double shapesArea(const std::vector<Shape>& shapes, const Affine& toWorld);

// AreaLightSource; nothing for an unsupported type (with a warning).
std::optional<AreaEmission> convertAreaLight(const std::string& type, const ParamList& params,
                                             const ValueReader& values, Warnings& warnings,
                                             const SourceLoc& loc);

} // namespace rayproc::pbrt
