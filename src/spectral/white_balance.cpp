#include "spectral/white_balance.h"

#include "kernels/spectrum.h"

namespace rayproc::spectral {

namespace {

Xyz whiteXyz(Chromaticity c) { return {c.x / c.y, 1.0, (1 - c.x - c.y) / c.y}; }

// Lam's (Bradford) cone-response matrix, XYZ to "LMS".
constexpr Mat3 kBradford = {{{0.8951, 0.2664, -0.1614},
                             {-0.7502, 1.7135, 0.0367},
                             {0.0389, -0.0685, 1.0296}}};

} // namespace

Chromaticity chromaticityOf(const Xyz& c) {
    double s = c.x + c.y + c.z;
    return {c.x / s, c.y / s};
}

Chromaticity daylightWhite(double kelvin) {
    const double cct = kelvin * 1.4388 / 1.4380;
    if (cct < 4000)
        return chromaticityOf(
            toXyz([cct](double nm) { return kernels::spectral::planck(nm, cct); }));
    // CIE 15: the daylight locus, x from the temperature (two ranges), y from x.
    const double t = 1.0 / cct;
    const double x = cct <= 7000
                         ? ((-4.6070e9 * t + 2.9678e6) * t + 0.09911e3) * t + 0.244063
                         : ((-2.0064e9 * t + 1.9018e6) * t + 0.24748e3) * t + 0.237040;
    const double y = (-3.0 * x + 2.870) * x - 0.275;
    return chromaticityOf(toXyz(daylightIlluminant(x, y)));
}

Mat3 operator*(const Mat3& a, const Mat3& b) {
    Mat3 r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) r.m[i][j] += a.m[i][k] * b.m[k][j];
    return r;
}

Mat3 bradfordAdaptation(Chromaticity from, Chromaticity to) {
    Xyz f = whiteXyz(from), t = whiteXyz(to);
    Xyz lf = kBradford.apply(f.x, f.y, f.z), lt = kBradford.apply(t.x, t.y, t.z);
    Mat3 scale;
    scale.m[0][0] = lt.x / lf.x;
    scale.m[1][1] = lt.y / lf.y;
    scale.m[2][2] = lt.z / lf.z;
    return kBradford.inverse() * (scale * kBradford);
}

} // namespace rayproc::spectral
