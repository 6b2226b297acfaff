// What a light (or a cluster of lights) can give a point, bounded from its extent, its emitted
// power and the directions it emits in: the importance a light sampler chooses lights by
// (Conty Estevez & Kulla, "Importance Sampling of Many Lights with Adaptive Tree Splitting",
// 2018; pbrt-v4's LightBounds). The same bound is evaluated for a shading point when a light is
// sampled and for a BSDF ray's origin when that ray finds the light, so the two pdfs that
// multiple importance sampling combines are exactly the ones the strategies sample with.
#pragma once

#include "core/math.h"
#include "kernels/light_importance.h"

#include <algorithm>
#include <cmath>

namespace rayproc {

struct LightBounds {
    // A sphere around every emitting point.
    Vec3 center;
    float radius = 0;
    // The emitted power's luminance (a common factor across lights does not matter).
    float phi = 0;
    // Emission leaves within thetaO of `axis` (pi: every direction), and within thetaE past that
    // around the surface's own normal (pi/2 for a Lambertian emitter, 0 for a point light's
    // spot edge). twoSided: the cone is mirrored (a two-sided quad emits along -axis too).
    // Call updateCone() after setting them.
    Vec3 axis{0, 0, 1};
    float thetaO = kPi, thetaE = 0.5f * kPi;
    bool twoSided = false;
    float cosO = -1, sinO = 0, cosE = 0; // of thetaO and thetaE (clamped to pi)

    void updateCone() {
        cosO = std::cos(std::min(thetaO, kPi));
        sinO = std::sin(std::min(thetaO, kPi));
        cosE = std::cos(std::min(thetaE, kPi));
    }

    // An upper bound on what this light can give p, up to a factor common to all lights:
    // phi cos(theta') / d^2, with d at least the radius (and d^2 at least 1e-30: with phi at most
    // 1, as LightSet scales it, no overflow) and theta' = max(0, thetaW - thetaO - thetaB) the
    // smallest angle between the emission cone and the directions from the bound to p (thetaW:
    // from the axis to p, thetaB: the bound's half-angle seen from p); 0 where theta' >= thetaE,
    // where no emitting point of the bound can face p. The angle differences by their cosines
    // and sines, without inverse trigonometry.
    float importance(const Vec3& p) const;
};

inline float LightBounds::importance(const Vec3& p) const {
    return kernels::boundsImportance(p.x, p.y, p.z, center.x, center.y, center.z, radius * radius, phi,
                            axis.x, axis.y, axis.z, cosO, sinO, cosE, twoSided ? 1.0f : 0.0f);
}

// The smallest cone found by pbrt-v4's DirectionCone::Union of two emission cones (axis and
// half-angle), for a cluster of lights.
inline void unionCone(const Vec3& axisA, float thetaA, const Vec3& axisB, float thetaB,
                      Vec3& axis, float& theta) {
    float thetaD = std::acos(std::clamp(dot(axisA, axisB), -1.0f, 1.0f));
    if (std::min(thetaD + thetaB, kPi) <= thetaA) { axis = axisA; theta = thetaA; return; }
    if (std::min(thetaD + thetaA, kPi) <= thetaB) { axis = axisB; theta = thetaB; return; }
    float thetaO = 0.5f * (thetaA + thetaD + thetaB);
    Vec3 w = cross(axisA, axisB);
    if (thetaO >= kPi || !(lengthSquared(w) > 0)) { axis = axisA; theta = kPi; return; }
    // Rotate axisA towards axisB by thetaO - thetaA about w (Rodrigues).
    float rot = thetaO - thetaA;
    Vec3 k = normalize(w);
    axis = normalize(axisA * std::cos(rot) + cross(k, axisA) * std::sin(rot) +
                     k * (dot(k, axisA) * (1 - std::cos(rot))));
    theta = thetaO;
}

} // namespace rayproc
