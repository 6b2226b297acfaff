#include "scene/pbrt/pbrt_transform.h"

#include <cmath>

namespace rayproc::pbrt {

Mat4 Mat4::translate(double x, double y, double z) {
    Mat4 t;
    t.m[0][3] = x;
    t.m[1][3] = y;
    t.m[2][3] = z;
    return t;
}

Mat4 Mat4::scale(double x, double y, double z) {
    Mat4 t;
    t.m[0][0] = x;
    t.m[1][1] = y;
    t.m[2][2] = z;
    return t;
}

// Rodrigues' formula, as pbrt's Rotate: counter-clockwise looking down the axis.
Mat4 Mat4::rotate(double degrees, double x, double y, double z) {
    Vec3d a = normalize(Vec3d(x, y, z));
    double th = degrees * 3.14159265358979323846 / 180.0;
    double s = std::sin(th), c = std::cos(th);
    Mat4 r;
    r.m[0][0] = a.x * a.x + (1 - a.x * a.x) * c;
    r.m[0][1] = a.x * a.y * (1 - c) - a.z * s;
    r.m[0][2] = a.x * a.z * (1 - c) + a.y * s;
    r.m[1][0] = a.x * a.y * (1 - c) + a.z * s;
    r.m[1][1] = a.y * a.y + (1 - a.y * a.y) * c;
    r.m[1][2] = a.y * a.z * (1 - c) - a.x * s;
    r.m[2][0] = a.x * a.z * (1 - c) - a.y * s;
    r.m[2][1] = a.y * a.z * (1 - c) + a.x * s;
    r.m[2][2] = a.z * a.z + (1 - a.z * a.z) * c;
    return r;
}

Mat4 Mat4::fromPbrt(const double v[16]) {
    Mat4 t;
    for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col) t.m[row][col] = v[col * 4 + row];
    return t;
}

// pbrt's LookAt: the camera's x axis is cross(up, dir), so camera space is left-handed when the
// world is read as right-handed.
bool Mat4::lookAt(const Vec3d& eye, const Vec3d& look, const Vec3d& up, Mat4& out) {
    Vec3d dir = normalize(look - eye);
    Vec3d right = cross(normalize(up), dir);
    if (length(look - eye) == 0 || length(right) == 0) return false;
    right = normalize(right);
    Vec3d newUp = cross(dir, right);
    Mat4 worldFromCamera;
    const Vec3d cols[4] = {right, newUp, dir, eye};
    for (int c = 0; c < 4; ++c) {
        worldFromCamera.m[0][c] = cols[c].x;
        worldFromCamera.m[1][c] = cols[c].y;
        worldFromCamera.m[2][c] = cols[c].z;
    }
    return worldFromCamera.inverse(out);
}

Mat4 Mat4::mirror(const Vec3d& point, const Vec3d& n) {
    Mat4 r;
    const double nv[3] = {n.x, n.y, n.z};
    double d = 2.0 * dot(n, point);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) r.m[i][j] = (i == j ? 1.0 : 0.0) - 2.0 * nv[i] * nv[j];
        r.m[i][3] = d * nv[i];
    }
    return r;
}

Mat4 Mat4::operator*(const Mat4& b) const {
    Mat4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double s = 0;
            for (int k = 0; k < 4; ++k) s += m[i][k] * b.m[k][j];
            r.m[i][j] = s;
        }
    return r;
}

// Gauss-Jordan elimination with partial pivoting.
bool Mat4::inverse(Mat4& out) const {
    double a[4][8];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            a[i][j] = m[i][j];
            a[i][j + 4] = i == j ? 1.0 : 0.0;
        }
    for (int col = 0; col < 4; ++col) {
        int pivot = col;
        for (int r = col + 1; r < 4; ++r)
            if (std::fabs(a[r][col]) > std::fabs(a[pivot][col])) pivot = r;
        if (std::fabs(a[pivot][col]) < 1e-300) return false;
        if (pivot != col)
            for (int j = 0; j < 8; ++j) std::swap(a[col][j], a[pivot][j]);
        double inv = 1.0 / a[col][col];
        for (int j = 0; j < 8; ++j) a[col][j] *= inv;
        for (int r = 0; r < 4; ++r) {
            if (r == col || a[r][col] == 0) continue;
            double f = a[r][col];
            for (int j = 0; j < 8; ++j) a[r][j] -= f * a[col][j];
        }
    }
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) out.m[i][j] = a[i][j + 4];
    return true;
}

double Mat4::det3() const {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

bool Mat4::isIdentity() const {
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            if (m[i][j] != (i == j ? 1.0 : 0.0)) return false;
    return true;
}

bool Mat4::isAffine() const {
    return m[3][0] == 0 && m[3][1] == 0 && m[3][2] == 0 && m[3][3] == 1;
}

Vec3d Mat4::point(const Vec3d& p) const {
    return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
            m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
            m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
}

Vec3d Mat4::vector(const Vec3d& v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
            m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
}

Affine Mat4::toAffine() const {
    Affine a;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) a.m[i][j] = float(m[i][j]);
    return a;
}

} // namespace rayproc::pbrt
