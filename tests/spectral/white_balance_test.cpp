// spectral/white_balance.h: pbrt-v4's daylight white for a white balance temperature and the
// Bradford adaptation between two whites.
#include "spectral/color_space.h"
#include "spectral/white_balance.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace rayproc::spectral;

namespace {

Xyz atY1(Chromaticity c) { return {c.x / c.y, 1.0, (1 - c.x - c.y) / c.y}; }

Chromaticity whiteOf(const ColorSpace& cs) {
    double s = cs.white.x + cs.white.y + cs.white.z;
    return {cs.white.x / s, cs.white.y / s};
}

} // namespace

TEST_CASE("Daylight whites: the D series from 4000 K, a blackbody below", "[spectral]") {
    // 6504 K is D65 (the CIE's 6500 K before the radiation constant's correction), 5003 K D50:
    // their tabulated chromaticities (0.31272, 0.32903) and (0.34567, 0.35851) within the
    // daylight locus formula's fit.
    Chromaticity d65 = daylightWhite(6504), d50 = daylightWhite(5003);
    CHECK(d65.x == Approx(0.31272).margin(3e-4));
    CHECK(d65.y == Approx(0.32903).margin(3e-4));
    CHECK(d50.x == Approx(0.34567).margin(3e-4));
    CHECK(d50.y == Approx(0.35851).margin(3e-4));
    // Below 4000 K a blackbody at the corrected temperature: 2856 K (x 1.4380 / 1.4388) is
    // illuminant A's (0.44757, 0.40745), a blackbody by definition.
    Chromaticity a = daylightWhite(2856 * 1.4380 / 1.4388);
    CHECK(a.x == Approx(0.44757).margin(3e-4));
    CHECK(a.y == Approx(0.40745).margin(3e-4));
    // Warmer is redder, on both sides of 7000 K (the locus's two ranges).
    CHECK(daylightWhite(4500).x > daylightWhite(5500).x);
    CHECK(daylightWhite(6900).x > daylightWhite(7100).x);
    CHECK(daylightWhite(7100).x > daylightWhite(12000).x);
}

TEST_CASE("Bradford adaptation maps one white onto the other", "[spectral]") {
    const Chromaticity to = whiteOf(colorSpace(ColorSpaceId::Srgb));
    for (double kelvin : {2700.0, 4000.0, 6504.0, 9000.0}) {
        const Chromaticity from = daylightWhite(kelvin);
        Mat3 m = bradfordAdaptation(from, to);
        Xyz f = atY1(from), t = atY1(to);
        Xyz mapped = m.apply(f.x, f.y, f.z);
        INFO(kelvin << " K");
        CHECK(mapped.x == Approx(t.x).epsilon(1e-12));
        CHECK(mapped.y == Approx(t.y).epsilon(1e-12));
        CHECK(mapped.z == Approx(t.z).epsilon(1e-12));
    }
    Mat3 same = bradfordAdaptation(to, to);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) CHECK(same.m[i][j] == Approx(i == j ? 1.0 : 0.0).margin(1e-12));
}
