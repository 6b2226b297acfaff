// Sampling routines: warps of uniform numbers onto pixels, lights and hemispheres.
#pragma once

#include "core/math.h"
#include "kernels/random.h"

#include <cmath>

namespace rayproc::kernels {

// Sample `index` of `count` stratified over the unit square, one sample per stratum:
// a jittered grid when count is a perfect square, Latin hypercube (N-rooks) otherwise.
// The stratum order is permuted by `key`: a prefix of the sequence is a random subset of the
// strata, which for a large count is no better spread than independent samples (the camera and
// path mode take kernels/sobol.h's points, stratified at every power-of-two prefix).
inline Vec2 stratified2D(std::uint32_t index, std::uint32_t count, std::uint64_t key) {
    float jx = uniform(key, 2 * index), jy = uniform(key, 2 * index + 1);
    if (count <= 1) return {jx, jy};
    std::uint32_t side = std::uint32_t(std::sqrt(double(count)) + 0.5);
    if (side * side == count) {
        std::uint32_t cell = permute(index, count, key);
        return {(float(cell % side) + jx) / float(side), (float(cell / side) + jy) / float(side)};
    }
    std::uint32_t sx = permute(index, count, key);
    std::uint32_t sy = permute(index, count, mix64(key));
    return {(float(sx) + jx) / float(count), (float(sy) + jy) / float(count)};
}

// Cosine-weighted direction around +z (Malley's method on Shirley's concentric disk).
inline Vec2 concentricDisk(Vec2 u) {
    float a = 2.0f * u.x - 1.0f, b = 2.0f * u.y - 1.0f;
    if (a == 0 && b == 0) return {0, 0};
    float r, phi;
    if (std::abs(a) > std::abs(b)) {
        r = a;
        phi = (kPi / 4) * (b / a);
    } else {
        r = b;
        phi = (kPi / 2) - (kPi / 4) * (a / b);
    }
    return {r * std::cos(phi), r * std::sin(phi)};
}

inline Vec3 cosineHemisphere(Vec2 u) {
    Vec2 d = concentricDisk(u);
    float z = std::sqrt(std::max(0.0f, 1.0f - d.x * d.x - d.y * d.y));
    return {d.x, d.y, z};
}

// A cosine-weighted direction (local frame, +z up) in stratum (j, k) of M x N: sin^2(theta) in
// [j/M, (j+1)/M), phi in [2 pi k/N, 2 pi (k+1)/N), jittered by u. sin^2(theta) uniform is the
// cosine-weighted density (Malley), so every stratum has the same cosine-weighted solid angle
// pi / (M N): the final gather's layout (gi/gather_stage.h). Unstratified: u alone.
inline Vec3 cosineStratum(int j, int k, int thetaCount, int phiCount, Vec2 u, bool stratify) {
    float s2 = stratify ? (float(j) + u.x) / float(thetaCount) : u.x;
    float phi = 2.0f * kPi * (stratify ? (float(k) + u.y) / float(phiCount) : u.y);
    float sinT = std::sqrt(std::min(1.0f, s2)), cosT = std::sqrt(std::max(0.0f, 1.0f - s2));
    return {sinT * std::cos(phi), sinT * std::sin(phi), cosT};
}

// Uniform point on a triangle (Heitz's low-distortion map would do too); returns barycentrics.
inline Vec2 uniformTriangle(Vec2 u) {
    float su = std::sqrt(u.x);
    return {1.0f - su, u.y * su};
}

// Direction inside a cone of half-angle acos(cosMax) around +z, uniform in solid angle.
inline Vec3 uniformCone(Vec2 u, float cosMax) {
    float cosT = (1.0f - u.x) + u.x * cosMax;
    float sinT = std::sqrt(std::max(0.0f, 1.0f - cosT * cosT));
    float phi = u.y * 2.0f * kPi;
    return {std::cos(phi) * sinT, std::sin(phi) * sinT, cosT};
}

inline Vec3 toWorld(const Vec3& local, const Vec3& n) {
    Vec3 t, b;
    orthonormalBasis(n, t, b);
    return t * local.x + b * local.y + n * local.z;
}

} // namespace rayproc::kernels
