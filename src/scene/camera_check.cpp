#include "scene/camera_check.h"

#include "scene/pbrt/pbrt_transform.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rayproc {

namespace {

double maxAbs(const Vec3& v) {
    double m = std::max({std::abs(double(v.x)), std::abs(double(v.y)), std::abs(double(v.z))});
    return std::isfinite(double(v.x) + double(v.y) + double(v.z)) ? m : INFINITY;
}

using pbrt::Vec3d;

std::string beyondRange(const std::string& what, double reach) {
    // 1e16 rounds up to 1.0000000272564224e16 in float: shown in full, it is seen to be beyond.
    std::string shown = rangeNumber(reach);
    if (shown == rangeNumber(kMaxWorldCoordinate)) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.17g (as a 32-bit float)", reach);
        shown = buf;
    }
    return what + " a coordinate of " + shown + "; rayproc handles coordinates up to " +
           rangeNumber(kMaxWorldCoordinate) + " (Embree's rays must stay within " +
           rangeNumber(kEmbreeRayLimit) + ")";
}

// The lens: its rays start up to the aperture radius around the position and aim at the focus
// point, position + focus distance along a pinhole ray whose components reach `slope`.
std::optional<CameraProblem> lensProblem(const Camera& c, double viewLength) {
    double r = double(c.apertureRadius), at = maxAbs(c.position);
    if (!std::isfinite(r) || r < 0)
        return CameraProblem{"aperture", "the camera's aperture must be a finite radius >= 0"};
    if (r == 0) return std::nullopt; // a pinhole: the focus distance is not used
    if (!(at + r <= kMaxWorldCoordinate))
        return CameraProblem{"aperture", beyondRange("the camera's aperture (lens radius) of " +
                                                         rangeNumber(r) + " puts rays at",
                                                     at + r)};
    double f = c.focusDistance > 0 ? double(c.focusDistance) : viewLength;
    double tanHalf = std::tan(0.5 * double(c.fovY) * 3.14159265358979323846 / 180.0);
    double slope = tanHalf * (double(c.width) / double(c.height) + 1.0) + 1.0;
    double reach = at + f * slope;
    if (std::isfinite(double(c.focusDistance)) && c.focusDistance >= 0 && reach <= kMaxFocusReach)
        return std::nullopt;
    std::string what = "the camera's focus distance (the distance to look_at when it is not "
                       "given) of " +
                       rangeNumber(f);
    return CameraProblem{"focus_distance", what + " puts the lens's focus point at up to " +
                                               rangeNumber(reach) + "; at most " +
                                               rangeNumber(kMaxFocusReach)};
}

} // namespace

std::string rangeNumber(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

std::optional<CameraProblem> cameraProblem(const Camera& c) {
    double at = maxAbs(c.position);
    if (!(at <= kMaxWorldCoordinate))
        return CameraProblem{"position", beyondRange("the camera is at", at)};
    if (!std::isfinite(maxAbs(c.lookAt)))
        return CameraProblem{"look_at", "the camera's look_at must be finite"};
    if (!(c.fovY > 0 && c.fovY < 180))
        return CameraProblem{"fov", "the camera's field of view must lie strictly between 0 and "
                                    "180 degrees"};
    // In double: a view of 1e30 squares beyond float.
    Vec3d view = Vec3d(c.lookAt) - Vec3d(c.position), up(c.up);
    double viewLength = length(view);
    if (!(viewLength > 0))
        return CameraProblem{"look_at", "look_at coincides with the camera position: they must "
                                        "differ (a zero-length view)"};
    if (!std::isfinite(length(up)) || !(length(up) > 0))
        return CameraProblem{"up", "the camera's up must be a finite, non-zero vector"};
    if (!(length(cross(normalize(view), normalize(up))) >= 1e-6))
        return CameraProblem{"up", "up is parallel to the view direction"};
    return lensProblem(c, viewLength);
}

} // namespace rayproc
