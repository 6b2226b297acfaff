// The camera's limits: one check for every way a camera arrives (the JSON and pbrt loaders,
// serve's camera message, and EmbreeScene for scenes built in code), so what serve accepts and
// saves is exactly what `rayproc render` renders. docs/robustness.md, "Embree's range".
#pragma once

#include "scene/scene.h"

#include <optional>
#include <string>

namespace rayproc {

// Embree 3 asserts, and so aborts the process, when a ray's origin or direction has a
// component beyond this in the space it traverses.
constexpr double kEmbreeRayLimit = 1.844e18;
// World coordinates rayproc handles: two orders of magnitude below Embree's limit (room for ray
// offsets and photon emission disks around the scene).
constexpr double kMaxWorldCoordinate = 1e16;
// The thin lens's focus point, position + focus distance along the widest camera ray, stays
// within this: the camera's frame squares that distance in float (beyond ~1.8e19 it is inf).
constexpr double kMaxFocusReach = 1e18;

struct CameraProblem {
    std::string field; // the JSON scene's key: position, look_at, up, fov, aperture, focus_distance
    std::string message; // what is wrong, a sentence that names the camera
};

// Why this camera cannot be rendered, or nothing: the position (and the lens around it) beyond
// kMaxWorldCoordinate, a look_at equal to the position, an up parallel to the view, a field of
// view outside (0, 180) degrees, a non-finite number, a focus point beyond kMaxFocusReach.
std::optional<CameraProblem> cameraProblem(const Camera& camera);

// "%.3g" of v, as the range messages print numbers.
std::string rangeNumber(double v);

} // namespace rayproc
