// src/spectral/spectra.h and color_space.h: the colord-data tables against published CIE
// figures, the illuminants' normalisation, the colour spaces' matrices, piecewise-linear spectra.
#include "spectral/color_space.h"
#include "spectral/spectra.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace rayproc::spectral;

namespace {

void chromaticity(const Xyz& c, double& x, double& y) {
    double s = c.x + c.y + c.z;
    x = c.x / s;
    y = c.y / s;
}

} // namespace

TEST_CASE("CIE 1931 tables: published peaks, integral and white points", "[spectral]") {
    // y-bar is 1 at 555 nm; x-bar's long-wave peak is 1.0622 at 600 nm (CIE 15:2004 table).
    CHECK(cieY().at(555) == Approx(1.0f));
    CHECK(cieX().at(600) == Approx(1.0622f));
    CHECK(cieZ().at(445) == Approx(1.7826f));
    // Linear between the 5 nm samples.
    CHECK(cieY().at(557) == Approx(0.6 * 1.0 + 0.4 * 0.995).epsilon(1e-6));
    // The integral of y-bar over 360-830 nm at 1 nm: 106.857 for the CIE's 1 nm table; the 5 nm
    // table interpolated linearly comes within 0.05%.
    CHECK(cieYIntegral() == Approx(106.857).epsilon(5e-4));
    // Chromaticities of the tabulated illuminants (CIE 15:2004: D65 0.31272 0.32903, A 0.44757
    // 0.40745, D50 0.34567 0.35851).
    double x, y;
    chromaticity(toXyz(*cieIlluminant("D65")), x, y);
    CHECK(x == Approx(0.31272).margin(2e-4));
    CHECK(y == Approx(0.32903).margin(2e-4));
    chromaticity(toXyz(*cieIlluminant("A")), x, y);
    CHECK(x == Approx(0.44757).margin(2e-4));
    CHECK(y == Approx(0.40745).margin(2e-4));
    chromaticity(toXyz(*cieIlluminant("D50")), x, y);
    CHECK(x == Approx(0.34567).margin(5e-4));
    CHECK(y == Approx(0.35851).margin(5e-4));
}

TEST_CASE("Named illuminants have luminance 1, unknown names are null", "[spectral]") {
    for (const std::string& name : cieIlluminantNames()) {
        INFO(name);
        const DenseSpectrum* s = cieIlluminant(name);
        REQUIRE(s);
        CHECK(toXyz(*s).y == Approx(1.0).epsilon(1e-6));
    }
    CHECK(cieIlluminantNames().size() == 20);
    CHECK(cieIlluminant("F11"));
    CHECK_FALSE(cieIlluminant("D60"));
}

TEST_CASE("Colour spaces: white maps to (1, 1, 1), sRGB's matrix is IEC 61966-2-1's", "[spectral]") {
    for (int i = 0; i < kColorSpaceCount; ++i) {
        const ColorSpace& cs = colorSpace(ColorSpaceId(i));
        INFO(cs.name);
        ColorSpace::Rgb w = cs.fromXyz(cs.white);
        CHECK(w.r == Approx(1.0).epsilon(1e-12));
        CHECK(w.g == Approx(1.0).epsilon(1e-12));
        CHECK(w.b == Approx(1.0).epsilon(1e-12));
        // Each primary's chromaticity comes back.
        for (int p = 0; p < 3; ++p) {
            double x, y;
            chromaticity(cs.toXyz(p == 0, p == 1, p == 2), x, y);
            CHECK(x == Approx(cs.primaries[p][0]).epsilon(1e-9));
            CHECK(y == Approx(cs.primaries[p][1]).epsilon(1e-9));
        }
        CHECK(colorSpaceByName(cs.name) == &cs);
    }
    // The standard's XYZ -> sRGB matrix, from its rounded D65 white (0.3127, 0.3290); the
    // tabulated D65 is within 2e-4 of it, so the matrices agree to a few 1e-3.
    const double published[3][3] = {{3.2406, -1.5372, -0.4986},
                                    {-0.9689, 1.8758, 0.0415},
                                    {0.0557, -0.2040, 1.0570}};
    const Mat3& m = colorSpace(ColorSpaceId::Srgb).xyzToRgb;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) CHECK(m.m[r][c] == Approx(published[r][c]).margin(3e-3));
    CHECK(colorSpaceByName("aces") == nullptr);
    // ACES's white is its D-series illuminant's chromaticity, SMPTE ST 2065-1's (0.32168,
    // 0.33767), as closely as CIE 15's weights reach it (measured: y 1.0e-4 low).
    double x, y;
    chromaticity(colorSpace(ColorSpaceId::Aces2065_1).white, x, y);
    CHECK(x == Approx(0.32168).margin(2e-5));
    CHECK(y == Approx(0.33767).margin(2e-4));
}

TEST_CASE("Daylight: the CIE basis at a D illuminant's chromaticity gives its tabulated spectrum",
          "[spectral]") {
    // colord's D50, D55 and D65 are the CIE's own tables; the basis and the weights' formula
    // (CIE 15) must reproduce them from their chromaticities (computed here from the tables).
    // The CIE rounded the weights to three decimals when it tabulated them, so values agree to
    // a few parts in a thousand, not exactly; and the weights' formula, a fit, brings the
    // spectrum back to its chromaticity within about 1e-4 (measured: y 1.0e-4 low for D50 and
    // D55, within 3e-5 for D65).
    for (const char* name : {"D50", "D55", "D65"}) {
        INFO(name);
        const DenseSpectrum& table = *cieIlluminant(name);
        double x, y;
        chromaticity(toXyz(table), x, y);
        DenseSpectrum d = daylightIlluminant(x, y);
        double worst = 0;
        for (int nm = 380; nm <= 780; ++nm)
            worst = std::max(worst, std::abs(double(d.at(float(nm)) - table.at(float(nm)))) /
                                        double(table.at(float(nm))));
        CHECK(worst < 0.01);
        double dx, dy;
        chromaticity(toXyz(d), dx, dy);
        CHECK(dx == Approx(x).margin(1e-4));
        CHECK(dy == Approx(y).margin(2e-4));
        CHECK(toXyz(d).y == Approx(1.0).epsilon(1e-6));
    }
    // Another chromaticity on the locus gives another spectrum: the weights are not constants.
    DenseSpectrum warm = daylightIlluminant(0.3457, 0.3585), cool = daylightIlluminant(0.2831, 0.2971);
    CHECK(warm.at(450) < cool.at(450));
}

TEST_CASE("Piecewise-linear spectra: interpolation inside, zero outside", "[spectral]") {
    std::vector<double> pairs = {400, 1.0, 500, 3.0, 700, 0.0};
    CHECK(piecewiseLinear(pairs, 400) == 1.0);
    CHECK(piecewiseLinear(pairs, 450) == Approx(2.0));
    CHECK(piecewiseLinear(pairs, 600) == Approx(1.5));
    CHECK(piecewiseLinear(pairs, 700) == 0.0);
    CHECK(piecewiseLinear(pairs, 399.9) == 0.0);
    CHECK(piecewiseLinear(pairs, 700.1) == 0.0);
    CHECK(piecewiseLinear({}, 500) == 0.0);
}
