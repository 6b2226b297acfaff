// Small vector / matrix vocabulary shared by the scene, the engine and the kernels.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace rayproc {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 1.0f / kPi;
constexpr float kInfinity = std::numeric_limits<float>::infinity();

struct Vec2 {
    float x = 0, y = 0;
};

struct Vec3 {
    float x = 0, y = 0, z = 0;
    constexpr Vec3() = default;
    constexpr Vec3(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
    constexpr explicit Vec3(float v) : x(v), y(v), z(v) {}
    float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    Vec3 operator-() const { return {-x, -y, -z}; }
    Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
    Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
    Vec3& operator*=(const Vec3& o) { x *= o.x; y *= o.y; z *= o.z; return *this; }
    Vec3& operator*=(float s) { x *= s; y *= s; z *= s; return *this; }
    bool operator==(const Vec3& o) const { return x == o.x && y == o.y && z == o.z; }
};

inline Vec3 operator+(Vec3 a, const Vec3& b) { return a += b; }
inline Vec3 operator-(Vec3 a, const Vec3& b) { return a -= b; }
inline Vec3 operator*(Vec3 a, const Vec3& b) { return a *= b; }
inline Vec3 operator*(Vec3 a, float s) { return a *= s; }
inline Vec3 operator*(float s, Vec3 a) { return a *= s; }
inline Vec3 operator/(const Vec3& a, float s) { return a * (1.0f / s); }
inline Vec3 operator/(const Vec3& a, const Vec3& b) { return {a.x / b.x, a.y / b.y, a.z / b.z}; }
inline float dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline float lengthSquared(const Vec3& a) { return dot(a, a); }
// Unit vector along a, for any finite a: the squared length of a vector longer than ~1e19 (a
// cross product of 1e10-long edges) overflows a float and of one shorter than ~1e-19
// underflows, so those take normalizeScaled (scaled by the largest component first). Zero stays
// zero.
Vec3 normalizeScaled(const Vec3& a);
inline Vec3 normalize(const Vec3& a) {
    float l2 = dot(a, a);
    if (l2 > 1e-36f && l2 < 1e36f) return a / std::sqrt(l2);
    return normalizeScaled(a);
}
// Area of the triangle abc; the cross product is formed in double, since its squared length
// overflows a float for edges longer than ~1e9 (a light in a scene scaled by 1e11).
inline float triangleArea(const Vec3& a, const Vec3& b, const Vec3& c) {
    double ux = double(b.x) - a.x, uy = double(b.y) - a.y, uz = double(b.z) - a.z;
    double vx = double(c.x) - a.x, vy = double(c.y) - a.y, vz = double(c.z) - a.z;
    double x = uy * vz - uz * vy, y = uz * vx - ux * vz, z = ux * vy - uy * vx;
    return float(0.5 * std::sqrt(x * x + y * y + z * z));
}
inline Vec3 vmin(const Vec3& a, const Vec3& b) {
    return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
inline Vec3 vmax(const Vec3& a, const Vec3& b) {
    return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
inline float maxComponent(const Vec3& a) { return std::max(a.x, std::max(a.y, a.z)); }
// The index of a's largest component (the first of equal ones).
inline int largestComponent(const Vec3& a) {
    return a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2);
}
inline float luminance(const Vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
inline bool isFinite(const Vec3& a) {
    return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}
inline bool isBlack(const Vec3& c) { return c.x == 0 && c.y == 0 && c.z == 0; }

// Builds an orthonormal basis (t, b, n) around a unit normal n (Duff et al. 2017).
inline void orthonormalBasis(const Vec3& n, Vec3& t, Vec3& b) {
    float sign = std::copysign(1.0f, n.z);
    float a = -1.0f / (sign + n.z);
    float bb = n.x * n.y * a;
    t = {1.0f + sign * n.x * n.x * a, sign * bb, -sign * n.x};
    b = {bb, sign + n.y * n.y * a, -n.y};
}

struct Bounds3 {
    Vec3 lo{kInfinity, kInfinity, kInfinity};
    Vec3 hi{-kInfinity, -kInfinity, -kInfinity};
    bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    void extend(const Vec3& p) { lo = vmin(lo, p); hi = vmax(hi, p); }
    void extend(const Bounds3& b) {
        if (!b.empty()) { lo = vmin(lo, b.lo); hi = vmax(hi, b.hi); }
    }
    Vec3 diagonal() const { return hi - lo; }
    Vec3 center() const { return (lo + hi) * 0.5f; }
    // p inside or on the box (an empty box contains nothing).
    bool contains(const Vec3& p) const {
        return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z &&
               p.z <= hi.z;
    }
};

// Row-major 3x4 affine transform (the last row of the 4x4 matrix is implied 0 0 0 1).
struct Affine {
    float m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};

    static Affine identity() { return {}; }
    static Affine translate(const Vec3& t);
    static Affine scale(const Vec3& s);
    static Affine rotate(float degrees, const Vec3& axis);
    static Affine lookAt(const Vec3& eye, const Vec3& target, const Vec3& up); // camera-to-world

    Vec3 point(const Vec3& p) const {
        return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
                m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
                m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
    }
    Vec3 vector(const Vec3& v) const {
        return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
                m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
    }
    // Transforms a normal with the inverse transpose of the linear part; `this` must be the
    // inverse of the transform that moved the points.
    Vec3 normalByInverse(const Vec3& n) const {
        return {m[0][0] * n.x + m[1][0] * n.y + m[2][0] * n.z,
                m[0][1] * n.x + m[1][1] * n.y + m[2][1] * n.z,
                m[0][2] * n.x + m[1][2] * n.y + m[2][2] * n.z};
    }
    float determinant() const;
    Affine inverse() const;
    bool isIdentity() const;
    Bounds3 bounds(const Bounds3& b) const;
    // Column-major 3x4 layout as Embree's RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR expects.
    void toColumnMajor(float out[12]) const;
};

Affine operator*(const Affine& a, const Affine& b);

} // namespace rayproc
