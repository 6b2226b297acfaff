#include "lighting/sphere_mapping.h"

#include <algorithm>
#include <cmath>

namespace rayproc {

// The square [-1,1]^2 is split by |u| + |v| = 1 into an inner diamond (upper hemisphere) and
// four corner triangles (lower hemisphere). r = 1 - |1 - |u| - |v|| is the distance from the
// pole in the octahedral sense; equal area demands z = 1 - r^2, and the angle around the pole
// grows linearly along each diamond edge: phi = pi/4 ((|v| - |u|) / r + 1) in each quadrant.
Vec3 equalAreaSquareToSphere(Vec2 p) {
    float u = 2 * p.x - 1, v = 2 * p.y - 1;
    float au = std::abs(u), av = std::abs(v);
    float signedDistance = 1 - (au + av);
    float d = std::abs(signedDistance);
    float r = 1 - d;
    float phi = (r == 0 ? 1.0f : (av - au) / r + 1) * (kPi / 4);
    float z = std::copysign(1 - r * r, signedDistance);
    float s = r * std::sqrt(std::max(0.0f, 2 - r * r)); // sin theta, since 1 - z^2 = r^2 (2 - r^2)
    return {std::copysign(std::cos(phi) * s, u), std::copysign(std::sin(phi) * s, v), z};
}

// The inverse: r = sqrt(1 - |z|), the quadrant's angle fraction t = atan(min/max) * 2/pi
// measured from the axis of the larger component, then v = t r, u = r - v on the diamond, and
// the lower hemisphere reflects the point across the diamond edge.
Vec2 equalAreaSphereToSquare(const Vec3& d) {
    float x = std::abs(d.x), y = std::abs(d.y), z = std::abs(d.z);
    float r = std::sqrt(std::max(0.0f, 1 - z));
    float a = std::max(x, y), b = std::min(x, y);
    float t = a == 0 ? 0.0f : std::atan(b / a) * (2 / kPi);
    if (x < y) t = 1 - t;
    float v = t * r, u = r - v;
    if (d.z < 0) {
        std::swap(u, v);
        u = 1 - u;
        v = 1 - v;
    }
    u = std::copysign(u, d.x);
    v = std::copysign(v, d.y);
    return {std::clamp(0.5f * (u + 1), 0.0f, 1.0f), std::clamp(0.5f * (v + 1), 0.0f, 1.0f)};
}

void wrapEqualAreaPixel(int& x, int& y, int res) {
    if (x < 0) {
        x = -x - 1;
        y = res - 1 - y;
    } else if (x >= res) {
        x = 2 * res - 1 - x;
        y = res - 1 - y;
    }
    if (y < 0) {
        x = res - 1 - x;
        y = -y - 1;
    } else if (y >= res) {
        x = res - 1 - x;
        y = 2 * res - 1 - y;
    }
    x = std::clamp(x, 0, res - 1);
    y = std::clamp(y, 0, res - 1);
}

Vec3 latLongToSphere(Vec2 uv) {
    float theta = uv.y * kPi, phi = uv.x * 2 * kPi;
    float s = std::sin(theta);
    return {s * std::cos(phi), s * std::sin(phi), std::cos(theta)};
}

Vec2 sphereToLatLong(const Vec3& d) {
    float theta = std::acos(std::clamp(d.z, -1.0f, 1.0f));
    float phi = std::atan2(d.y, d.x);
    if (phi < 0) phi += 2 * kPi;
    return {std::clamp(phi / (2 * kPi), 0.0f, 1.0f), theta / kPi};
}

} // namespace rayproc
