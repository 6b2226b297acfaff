#include "core/math.h"

#include <algorithm>
#include <cmath>

namespace rayproc {

Vec3 normalizeScaled(const Vec3& a) {
    float m = std::max({std::abs(a.x), std::abs(a.y), std::abs(a.z)});
    if (!(m > 0) || !std::isfinite(m)) return Vec3(0, 0, 0); // zero, NaN or infinite input
    Vec3 s = a / m; // largest component +-1: the squared length is in [1, 3]
    return s / std::sqrt(dot(s, s));
}

Affine Affine::translate(const Vec3& t) {
    Affine a;
    a.m[0][3] = t.x; a.m[1][3] = t.y; a.m[2][3] = t.z;
    return a;
}

Affine Affine::scale(const Vec3& s) {
    Affine a;
    a.m[0][0] = s.x; a.m[1][1] = s.y; a.m[2][2] = s.z;
    return a;
}

// Rodrigues' rotation about a unit axis, right-handed (counter-clockwise looking down the axis).
Affine Affine::rotate(float degrees, const Vec3& axisIn) {
    Vec3 k = normalize(axisIn);
    double th = double(degrees) * 3.14159265358979323846 / 180.0;
    double c = std::cos(th), s = std::sin(th), t = 1.0 - c;
    Affine a;
    a.m[0][0] = float(t * k.x * k.x + c);
    a.m[0][1] = float(t * k.x * k.y - s * k.z);
    a.m[0][2] = float(t * k.x * k.z + s * k.y);
    a.m[1][0] = float(t * k.x * k.y + s * k.z);
    a.m[1][1] = float(t * k.y * k.y + c);
    a.m[1][2] = float(t * k.y * k.z - s * k.x);
    a.m[2][0] = float(t * k.x * k.z - s * k.y);
    a.m[2][1] = float(t * k.y * k.z + s * k.x);
    a.m[2][2] = float(t * k.z * k.z + c);
    return a;
}

// Camera-to-world for a right-handed camera looking down its -z axis with +y up, +x right.
Affine Affine::lookAt(const Vec3& eye, const Vec3& target, const Vec3& up) {
    Vec3 w = normalize(eye - target); // camera +z points backwards
    Vec3 u = normalize(cross(up, w));
    Vec3 v = cross(w, u);
    Affine a;
    for (int r = 0; r < 3; ++r) {
        a.m[r][0] = u[r];
        a.m[r][1] = v[r];
        a.m[r][2] = w[r];
        a.m[r][3] = eye[r];
    }
    return a;
}

Affine operator*(const Affine& a, const Affine& b) {
    Affine r;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 4; ++j) {
            double s = (j == 3) ? a.m[i][3] : 0.0;
            for (int k = 0; k < 3; ++k) s += double(a.m[i][k]) * b.m[k][j];
            r.m[i][j] = float(s);
        }
    }
    return r;
}

float Affine::determinant() const {
    double a = m[0][0], b = m[0][1], c = m[0][2];
    double d = m[1][0], e = m[1][1], f = m[1][2];
    double g = m[2][0], h = m[2][1], i = m[2][2];
    return float(a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g));
}

Affine Affine::inverse() const {
    double a = m[0][0], b = m[0][1], c = m[0][2];
    double d = m[1][0], e = m[1][1], f = m[1][2];
    double g = m[2][0], h = m[2][1], i = m[2][2];
    double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
    double inv = 1.0 / det;
    double r[3][3] = {{(e * i - f * h) * inv, (c * h - b * i) * inv, (b * f - c * e) * inv},
                      {(f * g - d * i) * inv, (a * i - c * g) * inv, (c * d - a * f) * inv},
                      {(d * h - e * g) * inv, (b * g - a * h) * inv, (a * e - b * d) * inv}};
    Affine out;
    for (int row = 0; row < 3; ++row) {
        double t = 0;
        for (int k = 0; k < 3; ++k) {
            out.m[row][k] = float(r[row][k]);
            t -= r[row][k] * m[k][3];
        }
        out.m[row][3] = float(t);
    }
    return out;
}

bool Affine::isIdentity() const {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j)
            if (m[i][j] != (i == j ? 1.0f : 0.0f)) return false;
    return true;
}

Bounds3 Affine::bounds(const Bounds3& b) const {
    Bounds3 out;
    if (b.empty()) return out;
    for (int c = 0; c < 8; ++c) {
        Vec3 p{(c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y, (c & 4) ? b.hi.z : b.lo.z};
        out.extend(point(p));
    }
    return out;
}

void Affine::toColumnMajor(float out[12]) const {
    for (int col = 0; col < 4; ++col)
        for (int row = 0; row < 3; ++row) out[col * 3 + row] = m[row][col];
}

} // namespace rayproc
