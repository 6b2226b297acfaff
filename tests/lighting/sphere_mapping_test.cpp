// The equal-area octahedral mapping (pbrt-v4's EqualAreaSquareToSphere / SphereToSquare) and
// the lat-long mapping: round trips, known points, the octahedral pixel wrap, and the
// equal-area property (uniform points of the square give uniform directions, chi-square).
#include "lighting/sphere_mapping.h"
#include "statistical/statistical.h"

#include <catch2/catch.hpp>

using namespace rayproc;
using namespace rayproc::test;

TEST_CASE("Equal-area mapping: square -> sphere -> square round trip", "[lights]") {
    TestRng rng(1);
    float worst = 0;
    for (int i = 0; i < 200000; ++i) {
        Vec2 p = rng.uniform2();
        Vec3 d = equalAreaSquareToSphere(p);
        REQUIRE(std::abs(length(d) - 1.0f) < 1e-5f);
        Vec2 q = equalAreaSphereToSquare(d);
        worst = std::max({worst, std::abs(q.x - p.x), std::abs(q.y - p.y)});
    }
    INFO("worst coordinate error " << worst);
    CHECK(worst < 2e-4f);
    // The centre is +z, the corners -z, the edge midpoints the equator's axes.
    CHECK(equalAreaSquareToSphere({0.5f, 0.5f}).z == Approx(1.0f));
    CHECK(equalAreaSquareToSphere({0.0f, 0.0f}).z == Approx(-1.0f));
    CHECK(equalAreaSquareToSphere({1.0f, 1.0f}).z == Approx(-1.0f));
    Vec3 e = equalAreaSquareToSphere({1.0f, 0.5f});
    CHECK(e.x == Approx(1.0f));
    CHECK(e.z == Approx(0.0f).margin(1e-6));
    Vec3 n = equalAreaSquareToSphere({0.5f, 1.0f});
    CHECK(n.y == Approx(1.0f));
}

TEST_CASE("Equal-area mapping: sphere -> square -> sphere round trip", "[lights]") {
    TestRng rng(2);
    for (int i = 0; i < 100000; ++i) {
        Vec2 u = rng.uniform2();
        float z = 1 - 2 * u.x, r = std::sqrt(std::max(0.0f, 1 - z * z)), phi = 2 * kPi * u.y;
        Vec3 d{r * std::cos(phi), r * std::sin(phi), z};
        Vec3 back = equalAreaSquareToSphere(equalAreaSphereToSquare(d));
        REQUIRE(length(back - d) < 1e-3f);
    }
}

TEST_CASE("Equal-area mapping: uniform square points give uniform directions", "[lights]") {
    const int samples = 1000000;
    DirectionHistogram h({0, 0, 1}, -1.0f, 10, 20);
    TestRng rng(3);
    for (int i = 0; i < samples; ++i) h.add(equalAreaSquareToSphere(rng.uniform2()));
    auto expected = h.expected([](const Vec3&) { return 1.0 / (4 * kPi); }, samples, 2);
    ChiSquareResult r = chiSquareTest(h.counts(), expected);
    INFO("chi2 " << r.chi2 << " dof " << r.dof << " p " << r.pValue);
    CHECK(r.pValue > testSignificance());
}

TEST_CASE("Octahedral pixel wrap folds across the edges", "[lights]") {
    int x = -1, y = 2;
    wrapEqualAreaPixel(x, y, 8);
    CHECK((x == 0 && y == 5));
    x = 3, y = 8;
    wrapEqualAreaPixel(x, y, 8);
    CHECK((x == 4 && y == 7));
    x = 8, y = 8; // the corner: both folds, the same corner pixel region (-z)
    wrapEqualAreaPixel(x, y, 8);
    CHECK((x == 0 && y == 0));
    // Neighbouring pixels across an edge are neighbours on the sphere.
    Vec3 inside = equalAreaSquareToSphere({(0 + 0.5f) / 8, (5 + 0.5f) / 8});
    Vec3 outside = equalAreaSquareToSphere({0.0f, (2 + 0.5f) / 8}); // edge point next to (-1, 2)
    CHECK(length(inside - outside) < 0.4f);
}

TEST_CASE("Lat-long mapping round trip", "[lights]") {
    TestRng rng(4);
    for (int i = 0; i < 10000; ++i) {
        Vec2 p = rng.uniform2();
        p.y = 0.01f + 0.98f * p.y;
        Vec2 q = sphereToLatLong(latLongToSphere(p));
        REQUIRE(std::abs(q.x - p.x) < 1e-4f);
        REQUIRE(std::abs(q.y - p.y) < 1e-4f);
    }
    CHECK(latLongToSphere({0.0f, 0.0f}).z == Approx(1.0f));
    CHECK(latLongToSphere({0.25f, 0.5f}).y == Approx(1.0f));
}
