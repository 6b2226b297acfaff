// Ray-triangle intersection in double precision, for triangles whose single-precision test
// (Embree's) would be off by more than the scene can tolerate: a ground plane 1e9 wide seen from
// near the origin (src/accel/huge_triangles.h decides which, docs/robustness.md has the figures).
// Moeller-Trumbore (Moeller & Trumbore, "Fast, minimum storage ray-triangle intersection", 1997)
// with the vertices taken relative to the ray's origin: the float vertices and the float ray are
// exact in double, so the only errors are a few roundings of 2^-53 relative to the magnitudes
// |vertex - origin| and the edges, instead of Embree's 2^-24.
#pragma once

#include "core/math.h"

#include <algorithm>
#include <cmath>

namespace rayproc::kernels {

// Where the ray o + t d meets the plane of the triangle p0 p1 p2, with its barycentrics: the
// point is p0 + u (p1 - p0) + v (p2 - p0), Embree's convention. `inside` says whether (u, v)
// lies in the triangle, edges included (two triangles sharing an edge both accept a ray along
// it, so no ray slips between them). `valid` is false for a ray parallel to the plane or a
// triangle without area.
struct ExactTriangleHit {
    bool valid = false;
    bool inside = false;
    double t = 0, u = 0, v = 0;
};

inline ExactTriangleHit intersectTriangleExact(const Vec3& o, const Vec3& d, const Vec3& p0,
                                               const Vec3& p1, const Vec3& p2) {
    ExactTriangleHit h;
    const double dx = d.x, dy = d.y, dz = d.z;
    const double ex = double(p1.x) - p0.x, ey = double(p1.y) - p0.y, ez = double(p1.z) - p0.z;
    const double fx = double(p2.x) - p0.x, fy = double(p2.y) - p0.y, fz = double(p2.z) - p0.z;
    // pvec = d x e2; det = e1 . pvec (the triple product d . (e1 x e2) up to sign).
    const double px = dy * fz - dz * fy, py = dz * fx - dx * fz, pz = dx * fy - dy * fx;
    const double det = ex * px + ey * py + ez * pz;
    if (det == 0 || !std::isfinite(det)) return h;
    const double inv = 1.0 / det;
    // tvec = o - p0: the vertex relative to the origin, where the float test loses its digits.
    const double tx = double(o.x) - p0.x, ty = double(o.y) - p0.y, tz = double(o.z) - p0.z;
    const double qx = ty * ez - tz * ey, qy = tz * ex - tx * ez, qz = tx * ey - ty * ex;
    h.u = (tx * px + ty * py + tz * pz) * inv;
    h.v = (dx * qx + dy * qy + dz * qz) * inv;
    h.t = (fx * qx + fy * qy + fz * qz) * inv;
    h.valid = std::isfinite(h.t) && std::isfinite(h.u) && std::isfinite(h.v);
    h.inside = h.valid && h.u >= 0 && h.v >= 0 && h.u + h.v <= 1;
    return h;
}

// A bound on the distance, along the triangle's normal, between the computed hit point and the
// triangle's plane, for a ray from o hitting it at p, and for any ray leaving p (whose test
// rounds |vertex - p| the same way): Moeller-Trumbore's t and its numerator are ~10 roundings
// of products of |vertex - origin| and the edges, divided by the triple product, which turns
// them into kappa = |e1| |e2| / |e1 x e2| (1 / sine of the triangle's angle at p0) times the
// distances involved; the division by d . n moves the point along the ray, by the same relative
// error of the distance travelled. 24 roundings of 2^-53 leave a margin of two over that count.
inline double exactTriangleError(const Vec3& p, const Vec3& o, const Vec3& p0, const Vec3& p1,
                                 const Vec3& p2) {
    auto norm1 = [](double x, double y, double z) {
        return std::abs(x) + std::abs(y) + std::abs(z);
    };
    const double ex = double(p1.x) - p0.x, ey = double(p1.y) - p0.y, ez = double(p1.z) - p0.z;
    const double fx = double(p2.x) - p0.x, fy = double(p2.y) - p0.y, fz = double(p2.z) - p0.z;
    const double nx = ey * fz - ez * fy, ny = ez * fx - ex * fz, nz = ex * fy - ey * fx;
    const double area2 = std::sqrt(nx * nx + ny * ny + nz * nz);
    const double edges =
        std::sqrt(ex * ex + ey * ey + ez * ez) * std::sqrt(fx * fx + fy * fy + fz * fz);
    const double kappa = area2 > 0 ? edges / area2 : 1.0;
    double reach = 0;
    for (const Vec3* q : {&p0, &p1, &p2})
        reach = std::max(reach, norm1(double(q->x) - p.x, double(q->y) - p.y, double(q->z) - p.z));
    reach += 2 * norm1(double(p.x) - o.x, double(p.y) - o.y, double(p.z) - o.z);
    return 24 * 0x1p-53 * kappa * reach;
}

} // namespace rayproc::kernels
