#include "spectral/rgb_fit.h"

#include <algorithm>
#include <cmath>

namespace rayproc::spectral {

namespace {

// CIELAB's companding function and its derivative (delta = 6/29).
constexpr double kDelta = 6.0 / 29.0;
constexpr double kCoefficientBound = 5000;
double labF(double t) {
    return t > kDelta * kDelta * kDelta ? std::cbrt(t) : t / (3 * kDelta * kDelta) + 4.0 / 29.0;
}
double labFPrime(double t) {
    if (t > kDelta * kDelta * kDelta) {
        double c = std::cbrt(t);
        return 1.0 / (3 * c * c);
    }
    return 1.0 / (3 * kDelta * kDelta);
}

// Lab of xyz relative to `white`, and d(Lab)/d(XYZ).
std::array<double, 3> toLab(const Xyz& c, const Xyz& white, double d[3][3]) {
    double tx = c.x / white.x, ty = c.y / white.y, tz = c.z / white.z;
    double fx = labF(tx), fy = labF(ty), fz = labF(tz);
    if (d) {
        double gx = labFPrime(tx) / white.x, gy = labFPrime(ty) / white.y,
               gz = labFPrime(tz) / white.z;
        d[0][0] = 0, d[0][1] = 116 * gy, d[0][2] = 0;
        d[1][0] = 500 * gx, d[1][1] = -500 * gy, d[1][2] = 0;
        d[2][0] = 0, d[2][1] = 200 * gy, d[2][2] = -200 * gz;
    }
    return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}

// Solves a x = b for 3x3 a by Gaussian elimination with partial pivoting; false if singular.
bool solve3(double a[3][3], double b[3], double x[3]) {
    int p[3] = {0, 1, 2};
    for (int col = 0; col < 3; ++col) {
        int best = col;
        for (int r = col + 1; r < 3; ++r)
            if (std::fabs(a[p[r]][col]) > std::fabs(a[p[best]][col])) best = r;
        std::swap(p[col], p[best]);
        double piv = a[p[col]][col];
        if (std::fabs(piv) < 1e-300) return false;
        for (int r = col + 1; r < 3; ++r) {
            double f = a[p[r]][col] / piv;
            for (int k = col; k < 3; ++k) a[p[r]][k] -= f * a[p[col]][k];
            b[p[r]] -= f * b[p[col]];
        }
    }
    for (int r = 2; r >= 0; --r) {
        double s = b[p[r]];
        for (int k = r + 1; k < 3; ++k) s -= a[p[r]][k] * x[k];
        x[r] = s / a[p[r]][r];
    }
    return std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]);
}

} // namespace

RgbFitter::RgbFitter(const ColorSpace& cs) : m_cs(cs) {
    double norm = 0;
    for (int i = 0; i < kDenseCount; ++i) norm += double(cs.illuminant->values[i]) * cieY().values[i];
    for (int i = 0; i < kDenseCount; ++i) {
        double e = cs.illuminant->values[i] / norm;
        m_t[i] = double(i) / (kDenseCount - 1);
        m_wx[i] = e * cieX().values[i];
        m_wy[i] = e * cieY().values[i];
        m_wz[i] = e * cieZ().values[i];
    }
}

Xyz RgbFitter::reflectedXyz(const SigmoidCoefficients& c) const {
    Xyz r;
    for (int i = 0; i < kDenseCount; ++i) {
        double t = m_t[i];
        double x = (c[0] * t + c[1]) * t + c[2];
        double s = 0.5 + x / (2 * std::sqrt(1 + x * x));
        r.x += s * m_wx[i];
        r.y += s * m_wy[i];
        r.z += s * m_wz[i];
    }
    return r;
}

Xyz RgbFitter::reflectedXyz(const SigmoidCoefficients& c, double jac[3][3]) const {
    // Four sums at a time: the colour's (x, y, z, -) and each Jacobian row's (d/dc0, d/dc1,
    // d/dc2, -). Every lane adds the same products in the same order as one scalar sum would,
    // so the result is the scalar loop's, bit for bit; the build's table fits spend most of
    // their time here.
    using V4 = double __attribute__((vector_size(32)));
    V4 colour = {0, 0, 0, 0}, row[3] = {colour, colour, colour};
    for (int i = 0; i < kDenseCount; ++i) {
        double t = m_t[i];
        double x = (c[0] * t + c[1]) * t + c[2];
        double q = 1 + x * x, sq = std::sqrt(q);
        double s = 0.5 + x / (2 * sq);
        double ds = 1 / (2 * q * sq); // S'(x)
        V4 dc = {ds * t * t, ds * t, ds, 0};
        V4 w = {m_wx[i], m_wy[i], m_wz[i], 0};
        colour += s * w;
        row[0] += m_wx[i] * dc;
        row[1] += m_wy[i] * dc;
        row[2] += m_wz[i] * dc;
    }
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j) jac[k][j] = row[k][j];
    return {colour[0], colour[1], colour[2]};
}

double RgbFitter::fit(const std::array<double, 3>& rgb, SigmoidCoefficients& c) const {
    const Xyz white = m_cs.white;
    std::array<double, 3> target = toLab(m_cs.toXyz(rgb[0], rgb[1], rgb[2]), white, nullptr);
    // The colour at c and its Jacobian. A candidate step is evaluated with the Jacobian, so an
    // accepted step's evaluation is the next iteration's (the sums are the same, in the same
    // order, as the plain reflectedXyz's: the tables do not change).
    auto evaluate = [&](const SigmoidCoefficients& k, double r[3], double j[3][3]) {
        double jx[3][3], jl[3][3];
        std::array<double, 3> lab = toLab(reflectedXyz(k, jx), white, jl);
        for (int a = 0; a < 3; ++a) r[a] = lab[a] - target[a];
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                j[a][b] = jl[a][0] * jx[0][b] + jl[a][1] * jx[1][b] + jl[a][2] * jx[2][b];
        return std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    };
    auto residualOf = [&](const SigmoidCoefficients& k) {
        std::array<double, 3> lab = toLab(reflectedXyz(k), white, nullptr);
        double r0 = lab[0] - target[0], r1 = lab[1] - target[1], r2 = lab[2] - target[2];
        return std::sqrt(r0 * r0 + r1 * r1 + r2 * r2);
    };
    double r[3], j[3][3];
    double residual = evaluate(c, r, j);
    for (int it = 0; it < 50; ++it) {
        if (residual < 1e-6) break;
        double step[3];
        if (!solve3(j, r, step)) break;
        // Backtracking: halve the Gauss-Newton step until the residual falls (far from the
        // solution the full step can overshoot into the sigmoid's flat tails).
        SigmoidCoefficients next = c;
        double nextR[3], nextJ[3][3];
        double nextResidual = residual;
        for (double scale = 1; scale > 1e-4; scale *= 0.5) {
            for (int k = 0; k < 3; ++k) next[k] = c[k] - scale * step[k];
            // Saturated colours push the coefficients towards infinity (a step spectrum);
            // bounding them keeps the iteration finite. 5000 rather than 200 brings the cells
            // of a 16^3 sRGB table that miss by more than 1e-3 in CIELAB from 10% to 2%
            // (docs/spectral.md).
            double m = std::max({std::fabs(next[0]), std::fabs(next[1]), std::fabs(next[2])});
            if (m > kCoefficientBound)
                for (double& v : next) v *= kCoefficientBound / m;
            // The full step is evaluated with its Jacobian (usually taken); a shorter one by
            // its colour alone, and with the Jacobian once taken.
            nextResidual = scale == 1 ? evaluate(next, nextR, nextJ) : residualOf(next);
            if (nextResidual < residual) {
                if (scale != 1) evaluate(next, nextR, nextJ);
                break;
            }
        }
        if (!(nextResidual < residual)) break; // no descent left: the closest the model gets
        c = next;
        residual = nextResidual;
        std::copy(nextR, nextR + 3, r);
        std::copy(&nextJ[0][0], &nextJ[0][0] + 9, &j[0][0]);
    }
    return residual;
}

} // namespace rayproc::spectral
