// pbrt's transformation vocabulary in double precision: the current transformation matrix (CTM)
// is composed from many directives (Scale, LookAt, ConcatTransform, ...) and inverted for the
// camera, so it is kept in doubles and rounded to rayproc's float Affine only when used.
//
// Conventions follow pbrt: matrices act on column vectors; every directive post-multiplies the
// CTM (CTM = CTM * M), so the transform written last applies to the object first; Rotate is
// counter-clockwise about its axis (right-handed); Transform and ConcatTransform list the matrix
// column by column (the translation is elements 12, 13, 14); LookAt yields camera-from-world for
// pbrt's left-handed camera space (x right, y up, z forward).
#pragma once

#include "core/math.h"

#include <cmath>

namespace rayproc::pbrt {

// Double-precision 3-vectors for transform arithmetic.
struct Vec3d {
    double x = 0, y = 0, z = 0;
    Vec3d() = default;
    Vec3d(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
    explicit Vec3d(const Vec3& v) : x(v.x), y(v.y), z(v.z) {}
    Vec3 toFloat() const { return {float(x), float(y), float(z)}; }
    Vec3d operator+(const Vec3d& o) const { return {x + o.x, y + o.y, z + o.z}; }
    Vec3d operator-(const Vec3d& o) const { return {x - o.x, y - o.y, z - o.z}; }
    Vec3d operator*(double s) const { return {x * s, y * s, z * s}; }
};
inline double dot(const Vec3d& a, const Vec3d& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Vec3d cross(const Vec3d& a, const Vec3d& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(const Vec3d& a) {
    return std::sqrt(dot(a, a));
}
inline Vec3d normalize(const Vec3d& a) {
    double l = length(a);
    return l > 0 ? a * (1.0 / l) : Vec3d();
}

struct Mat4 {
    double m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};

    static Mat4 translate(double x, double y, double z);
    static Mat4 scale(double x, double y, double z);
    static Mat4 rotate(double degrees, double x, double y, double z); // axis must be non-zero
    // The 16 numbers of pbrt's Transform / ConcatTransform (column by column).
    static Mat4 fromPbrt(const double v[16]);
    // pbrt's LookAt as camera-from-world; false if eye == look or up is parallel to the view.
    static bool lookAt(const Vec3d& eye, const Vec3d& look, const Vec3d& up, Mat4& out);
    // The reflection about the plane through `point` with unit normal `n`.
    static Mat4 mirror(const Vec3d& point, const Vec3d& n);

    Mat4 operator*(const Mat4& b) const;
    bool inverse(Mat4& out) const; // false if singular
    double det3() const;           // of the linear part
    bool isIdentity() const;
    bool isAffine() const; // last row 0 0 0 1
    Vec3d point(const Vec3d& p) const;
    Vec3d vector(const Vec3d& v) const;
    Affine toAffine() const; // rounds to float, drops a projective last row
};

} // namespace rayproc::pbrt
