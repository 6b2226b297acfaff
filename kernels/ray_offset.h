// Error-bounded ray origins (pbrt-v4's approach, Pharr, Jakob & Humphreys, "Physically Based
// Rendering", 4th ed., section 6.8): every computed surface point carries a conservative
// per-component bound `err` on its distance from the true surface, derived from the floating-point
// operations that produced it; a spawned ray starts at p pushed along the geometric normal by
// d = dot(|n|, err), which puts it outside the box of points p might stand for, on the side the
// ray travels to. All bounds are relative to the magnitudes involved, so the offset is scale
// invariant: it shrinks and grows with the scene and with the distance from the origin.
// docs/robustness.md derives the bounds and states the margins taken for Embree's own rounding.
#pragma once

#include "core/math.h"

#include <cmath>
#include <cstdint>
#include <cstring>

namespace rayproc::kernels {

// Higham's gamma_n = n u / (1 - n u), u = 2^-24 the unit roundoff of float: a sequence of n
// float operations has relative error at most gamma_n.
constexpr float errorGamma(int n) {
    constexpr float u = 0.5f * std::numeric_limits<float>::epsilon();
    return (float(n) * u) / (1.0f - float(n) * u);
}

// Margin for Embree's own rounding when it intersects a ray with the surface a point lies on:
// its triangle, sphere and disk tests compute the hit distance from (vertex - origin) and the
// normal of the primitive with errors of a few ulps of those magnitudes (docs/robustness.md).
constexpr int kEmbreeTestOps = 8;

// The next float above / below v (pbrt's NextFloatUp / Down), by integer arithmetic on the bit
// pattern: std::nextafter is an out-of-line libm call, and six per shadow ray showed in the
// benchmarks. Infinities stay; -0 and +0 step to the smallest denormal.
inline float nextFloatUp(float v) {
    if (std::isinf(v) && v > 0) return v;
    if (v == -0.0f) v = 0.0f;
    std::uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    bits = v >= 0 ? bits + 1 : bits - 1;
    std::memcpy(&v, &bits, sizeof bits);
    return v;
}
inline float nextFloatDown(float v) {
    if (std::isinf(v) && v < 0) return v;
    if (v == 0.0f) v = -0.0f;
    std::uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    bits = v > 0 ? bits - 1 : bits + 1;
    std::memcpy(&v, &bits, sizeof bits);
    return v;
}

inline Vec3 absVec(const Vec3& a) { return {std::abs(a.x), std::abs(a.y), std::abs(a.z)}; }

// The point p0 + u (p1 - p0) + v (p2 - p0) of a triangle and its error bound. Whatever (u, v)
// are, the exact value of this expression lies in the triangle's plane, so only the rounding
// counts: the final addition (gamma_1 |p|), the edges and their weighted sum (gamma_4 of the
// edge terms, |u|, |v| <= 1), plus the margin for Embree's test, whose error grows with the
// distance to the triangle's vertices and hence with its edges.
inline Vec3 trianglePoint(const Vec3& p0, const Vec3& p1, const Vec3& p2, float u, float v,
                          Vec3& err) {
    Vec3 e1 = p1 - p0, e2 = p2 - p0;
    Vec3 p = p0 + (e1 * u + e2 * v);
    err = absVec(p) * errorGamma(1) + (absVec(e1) + absVec(e2)) * errorGamma(4 + kEmbreeTestOps);
    return p;
}

// Error bound of a point c + r n on a sphere (n a computed unit vector) or of a point projected
// onto a disk of centre c and radius r: the final addition and Embree's test, which works with
// (origin - c), rounded to ulps of |c|, and with the radius.
inline Vec3 roundSurfaceError(const Vec3& p, const Vec3& c, float r) {
    return (absVec(p) + absVec(c)) * errorGamma(2) + Vec3(std::abs(r) * errorGamma(6 + kEmbreeTestOps));
}

// Error bound of M p + t for a point p with error bound err (pbrt-v4's Transform of a
// Point3fi): (1 + gamma_3) |M| err + gamma_3 (|M| |p| + |t|). The second term is doubled:
// Embree maps the spawned origin back into the instance's space with the inverse transform, and
// its rounding there must not undo the offset.
inline Vec3 transformedPointError(const Affine& a, const Vec3& p, const Vec3& err) {
    Vec3 out;
    for (int r = 0; r < 3; ++r) {
        float me = 0, mp = 0;
        for (int c = 0; c < 3; ++c) {
            me += std::abs(a.m[r][c]) * err[c];
            mp += std::abs(a.m[r][c]) * std::abs(p[c]);
        }
        out[r] = (1 + errorGamma(3)) * me + 2 * errorGamma(3) * (mp + std::abs(a.m[r][3]));
    }
    return out;
}

// The distance along the unit normal n that leaves the error box of a point: dot(|n|, err).
inline float offsetDistance(const Vec3& err, const Vec3& n) { return dot(absVec(n), err); }

// Moves p by the error bound along n, to the side of `dir`, then rounds each moved component one
// float further away from p, so that rounding the sum cannot pull the origin back into the box.
inline Vec3 offsetRayOrigin(const Vec3& p, const Vec3& err, const Vec3& n, const Vec3& dir) {
    float d = offsetDistance(err, n);
    Vec3 offset = n * d;
    if (dot(dir, n) < 0) offset = -offset;
    Vec3 po = p + offset;
    for (int i = 0; i < 3; ++i) {
        if (offset[i] > 0) po[i] = nextFloatUp(po[i]);
        else if (offset[i] < 0) po[i] = nextFloatDown(po[i]);
    }
    return po;
}

// A shadow ray from surface point p (error err, geometric normal n) to a light point q (error
// qErr, normal nq; nq = 0 for a light that is no surface). Both ends are offset: the origin off
// p towards q; the end off q towards the origin, by q's error bound plus Embree's rounding over
// the ray's length (its hit distance is computed from vertex - origin, so its error grows with
// the distance travelled), along nq, or along the ray for a point light, which may sit on
// geometry (preview mode puts one on each corner of a quad light). The ray then ends at t = tfar
// exactly there.
inline void shadowSegment(const Vec3& p, const Vec3& err, const Vec3& n, const Vec3& q,
                          const Vec3& qErr, const Vec3& nq, Vec3& origin, Vec3& dir, float& tfar) {
    origin = offsetRayOrigin(p, err, n, q - p);
    Vec3 back = origin - q;
    float reach = length(back);
    Vec3 endErr = qErr + absVec(q) * errorGamma(4) + Vec3(reach * errorGamma(kEmbreeTestOps));
    Vec3 end = offsetRayOrigin(q, endErr, isBlack(nq) ? back / reach : nq, back);
    Vec3 d = end - origin;
    float len = length(d);
    // The two error boxes overlap (the light touches the surface): nothing can lie between.
    if (!(reach > 0) || !(len > 0) || dot(d, back) >= 0) {
        dir = n;
        tfar = 0;
        return;
    }
    dir = d / len;
    tfar = len;
}

} // namespace rayproc::kernels
