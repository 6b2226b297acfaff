#include "spectral/color_space.h"

#include <memory>

namespace rayproc::spectral {

Mat3 Mat3::inverse() const {
    const auto& a = m;
    double c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1];
    double c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2];
    double c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
    double det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
    double s = 1.0 / det;
    Mat3 r;
    r.m[0][0] = c00 * s;
    r.m[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) * s;
    r.m[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) * s;
    r.m[1][0] = c01 * s;
    r.m[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) * s;
    r.m[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) * s;
    r.m[2][0] = c02 * s;
    r.m[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) * s;
    r.m[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) * s;
    return r;
}

namespace {

// The columns of RGB -> XYZ are the primaries' XYZ (x/y, 1, (1-x-y)/y), each scaled so that
// RGB (1, 1, 1) lands on the white point's XYZ.
ColorSpace make(ColorSpaceId id, const char* name, const double xy[3][2],
               const DenseSpectrum* illum) {
    ColorSpace cs{};
    cs.id = id;
    cs.name = name;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 2; ++j) cs.primaries[i][j] = xy[i][j];
    cs.illuminant = illum;
    cs.white = toXyz(*cs.illuminant);
    Mat3 p;
    for (int c = 0; c < 3; ++c) {
        double x = xy[c][0], y = xy[c][1];
        p.m[0][c] = x / y;
        p.m[1][c] = 1;
        p.m[2][c] = (1 - x - y) / y;
    }
    Xyz s = p.inverse().apply(cs.white.x, cs.white.y, cs.white.z);
    double scale[3] = {s.x, s.y, s.z};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) cs.rgbToXyz.m[r][c] = p.m[r][c] * scale[c];
    cs.xyzToRgb = cs.rgbToXyz.inverse();
    return cs;
}

const ColorSpace* all() {
    // Primaries: IEC 61966-2-1 (sRGB), ITU-R BT.2020, SMPTE EG 432-1 (P3 with the D65 white, as
    // pbrt-v4's "dci-p3"), SMPTE ST 2065-1 (ACES's AP0, with the D-series white "D60").
    static const double srgb[3][2] = {{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}};
    static const double rec2020[3][2] = {{0.708, 0.292}, {0.170, 0.797}, {0.131, 0.046}};
    static const double p3[3][2] = {{0.680, 0.320}, {0.265, 0.690}, {0.150, 0.060}};
    static const double ap0[3][2] = {{0.7347, 0.2653}, {0.0, 1.0}, {0.0001, -0.0770}};
    const DenseSpectrum* d65 = cieIlluminant("D65");
    static const ColorSpace spaces[kColorSpaceCount] = {
        make(ColorSpaceId::Srgb, "srgb", srgb, d65),
        make(ColorSpaceId::Rec2020, "rec2020", rec2020, d65),
        make(ColorSpaceId::DciP3, "dci-p3", p3, d65),
        make(ColorSpaceId::Aces2065_1, "aces2065-1", ap0, &acesD60Illuminant())};
    return spaces;
}

} // namespace

const ColorSpace& colorSpace(ColorSpaceId id) { return all()[int(id)]; }

const ColorSpace* colorSpaceByName(const std::string& name) {
    for (int i = 0; i < kColorSpaceCount; ++i)
        if (name == all()[i].name) return &all()[i];
    return nullptr;
}

} // namespace rayproc::spectral
