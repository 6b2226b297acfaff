// Fresnel reflectances against values that do not come from rayproc's code (issue 38, item 3):
// closed forms of the dielectric Fresnel equations in their angle form (Hecht, "Optics", 5th
// ed., eqs. 4.42-4.43: R_perp = sin^2(i - t) / sin^2(i + t), R_par = tan^2(i - t) / tan^2(i + t),
// a different form from the cosine form kernels/fresnel.h evaluates), Brewster's angle, Schlick's
// formula as his paper states it, and the named metals' normal-incidence reflectance against
// published measured F0 tables (docs/testing.md, "Where the truth comes from").
#include "kernels/bsdf.h"
#include "kernels/fresnel.h"
#include "scene/metals.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>

using namespace rayproc;
using namespace rayproc::kernels;

namespace {

constexpr double kPi = 3.14159265358979323846;

double degrees(double d) { return d * kPi / 180.0; }

// Hecht's angle form, unpolarised: the mean of R_perp and R_par.
double fresnelAngleForm(double thetaI, double n) {
    double thetaT = std::asin(std::sin(thetaI) / n);
    double rPerp = std::sin(thetaI - thetaT) / std::sin(thetaI + thetaT);
    double rPar = std::tan(thetaI - thetaT) / std::tan(thetaI + thetaT);
    return 0.5 * (rPerp * rPerp + rPar * rPar);
}

} // namespace

TEST_CASE("Dielectric Fresnel matches the textbook closed forms of glass and water",
          "[kernels][fresnel]") {
    // Normal incidence: ((n - 1) / (n + 1))^2, 0.04 for n = 1.5 and 0.0204 for water (1.333).
    CHECK(fresnelDielectricSigned(1.0f, 1.5f) == Approx(0.04).margin(1e-6));
    CHECK(fresnelDielectricSigned(1.0f, 1.333f) == Approx(0.0203732).margin(1e-6));
    // Brewster's angle atan(n): R_par = 0 and R_perp = cos^2(2 theta_B) = ((1 - n^2) / (1 + n^2))^2,
    // so R = 0.0739645 for n = 1.5.
    const double brewster = std::atan(1.5);
    CHECK(fresnelDielectricSigned(float(std::cos(brewster)), 1.5f) ==
          Approx(0.5 * std::pow((1 - 2.25) / (1 + 2.25), 2)).margin(1e-5));
    // Hecht's angle form at 15..85 degrees, entering glass (45 degrees: 0.0502).
    for (int d = 15; d <= 85; d += 10) {
        INFO(d << " degrees");
        CHECK(fresnelDielectricSigned(float(std::cos(degrees(d))), 1.5f) ==
              Approx(fresnelAngleForm(degrees(d), 1.5)).margin(2e-5));
    }
    CHECK(fresnelAngleForm(degrees(45), 1.5) == Approx(0.0502).margin(1e-4));
    // Leaving glass: total internal reflection past the critical angle asin(1 / 1.5) = 41.8
    // degrees; below it the angle form with the inverted index.
    CHECK(fresnelDielectricSigned(-float(std::cos(degrees(42.0))), 1.5f) == 1.0f);
    CHECK(fresnelDielectricSigned(-float(std::cos(degrees(30.0))), 1.5f) ==
          Approx(fresnelAngleForm(degrees(30), 1 / 1.5)).margin(2e-5));
}

TEST_CASE("Schlick's Fresnel is his formula R0 + (1 - R0)(1 - cos)^5", "[kernels][fresnel]") {
    // Schlick 1994, eq. 24. At 60 degrees (1 - cos)^5 = 1/32: 0.04 + 0.96 / 32 = 0.07 exactly.
    Vec3 f = fresnelSchlick(Vec3(0.04f), 0.5f);
    CHECK(f.x == Approx(0.07).margin(1e-6));
    CHECK(fresnelSchlick(Vec3(0.04f), 1.0f).y == Approx(0.04).margin(1e-7));
    CHECK(fresnelSchlick(Vec3(0.04f), 0.0f).z == Approx(1.0).margin(1e-7));
    // It is an approximation of the exact curve: at 45 degrees for n = 1.5 it gives 0.0421
    // against 0.0502 (16% low).
    CHECK(fresnelSchlick(Vec3(0.04f), float(std::cos(degrees(45)))).x == Approx(0.0421).margin(1e-4));
}

TEST_CASE("Named metals reflect at normal incidence what published measurements give",
          "[kernels][fresnel]") {
    // Measured F0 in linear sRGB primaries (normal-incidence reflectance integrated against the
    // sRGB colour matching functions): Unreal Engine's "Physically Based Materials" table
    // (measured base colours of metals), the same figures as Real-Time Rendering, 4th ed.,
    // Table 9.2 within 0.02 (RTR4's gold is 1.000, 0.782, 0.344); brass (C260) from RTR4 only.
    // rayproc's eta, k (src/scene/metals.cpp) are RGB fits of spectral data, so the two
    // differ by how the spectrum is reduced to three numbers: measured at most 0.036 (gold's
    // green: 0.802 against 0.766). Tolerance 0.05: each metal's F0 is further than that from
    // every other metal's published F0 in some channel, so a swapped or mistyped entry fails,
    // except silver and aluminium, whose published F0 differ by at most 0.06 (aluminium's F0
    // is within 0.044 of silver's figures: a swap of those two would pass).
    struct Published {
        const char* element;
        double r, g, b;
    };
    const Published table[] = {
        {"Ag", 0.972, 0.960, 0.915}, {"Al", 0.913, 0.921, 0.925}, {"Au", 1.000, 0.766, 0.336},
        {"Cu", 0.955, 0.637, 0.538}, {"CuZn", 0.910, 0.778, 0.423},
    };
    constexpr double kTolerance = 0.05;
    for (const Published& p : table) {
        Vec3 eta, k;
        REQUIRE(namedMetal(p.element, eta, k));
        Vec3 f0 = fresnelComplex(1.0f, eta, k);
        INFO(p.element << ": F0 " << f0.x << ", " << f0.y << ", " << f0.z << " against " << p.r
                       << ", " << p.g << ", " << p.b);
        CHECK(std::abs(f0.x - p.r) < kTolerance);
        CHECK(std::abs(f0.y - p.g) < kTolerance);
        CHECK(std::abs(f0.z - p.b) < kTolerance);
        // The check can fail: every other metal's published F0 is off by more than it allows.
        for (const Published& q : table) {
            if (std::string(q.element) == p.element) continue;
            if (std::string(p.element) == "Al" && std::string(q.element) == "Ag") continue;
            double worst = std::max({std::abs(f0.x - q.r), std::abs(f0.y - q.g),
                                     std::abs(f0.z - q.b)});
            INFO("against " << q.element);
            CHECK(worst > kTolerance);
        }
    }
}
