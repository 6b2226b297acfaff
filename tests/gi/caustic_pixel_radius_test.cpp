// The caustic radius per pixel (gi/caustic_pixel_radius.h): SPPM's statistics (Hachisuka &
// Jensen 2009) kept per pixel for progressive caustics. The update in closed form, pixels that
// receive no photon keeping their radius, the k-nearest seed (radius and photon count: the
// global sequence's first step under a constant density), and sums that do not depend on
// the order in which the visible points report (the image must not depend on the threads).
#include "test_util.h"

#include "gi/caustic_pixel_radius.h"

#include <cmath>

using namespace rayproc;

TEST_CASE("Pixel caustic radii: seeded from the first pass's k-nearest distances",
          "[gi][progressive]") {
    CausticPixelRadius r(4, 2.0f, 2.0 / 3.0);
    REQUIRE(r.seeding());
    for (std::uint32_t j = 0; j < 4; ++j) CHECK(r.radius(j) == 2.0f);
    CHECK(r.radius(99) == 2.0f); // outside the film: the largest radius
    r.seed(0, 0.25f, 64);
    r.seed(0, 0.49f, 32); // pixel 0: the mean of the squares, 0.37, and 48 photons
    r.seed(1, 100.0f, 3); // beyond the largest radius: kept at it
    r.seed(2, 0.0f, 64);  // k photons on the point: a smallest radius, never 0
    r.endPass(1);
    CHECK_FALSE(r.seeding());
    CHECK(r.radius(0) == Approx(std::sqrt(0.37)).epsilon(1e-4));
    CHECK(r.radius(1) == 2.0f);
    CHECK(r.radius(2) > 0.0f);
    CHECK(r.radius(2) <= 2.0f / 256.0f);
    CHECK(r.radius(3) == 2.0f); // no visible point: untouched
    // N_0 = the 48 seed photons: the same density again (48 within R_0) shrinks R^2 by
    // (1 + alpha) / 2, the global sequence's first step, not SPPM's alpha.
    r.found(0, 48);
    r.endPass(1);
    CHECK(r.radius(0) == Approx(std::sqrt(0.37 * (1 + 2.0 / 3.0) / 2)).epsilon(1e-4));
}

TEST_CASE("Pixel caustic radii: R^2 <- R^2 (N + alpha M) / (N + M), N <- N + alpha M per sample",
          "[gi][progressive]") {
    const double alpha = 2.0 / 3.0;
    CausticPixelRadius r(3, 1.0f, alpha);
    r.endPass(1); // a first pass without caustic lookups: nothing seeded
    // Pass 2, one sample: pixel 0 finds 30 photons at each of two visible points (M = 30 per
    // lookup), pixel 1 finds none, pixel 2 is not looked up.
    r.found(0, 30);
    r.found(0, 30);
    r.found(1, 0);
    r.endPass(1);
    double r2 = alpha, n = alpha * 30; // N = 0: the first reduction is alpha
    CHECK(r.radius(0) == Approx(std::sqrt(r2)).epsilon(1e-6));
    CHECK(r.radius(1) == 1.0f); // no photon: the radius stays (SPPM)
    CHECK(r.radius(2) == 1.0f);
    // Pass 3, one sample: 10 photons.
    r.found(0, 10);
    r.endPass(1);
    r2 *= (n + alpha * 10) / (n + 10);
    n += alpha * 10;
    CHECK(r.radius(0) == Approx(std::sqrt(r2)).epsilon(1e-6));
    // Pass 4, four samples (a map of four samples' photons): 40 photons at one visible point
    // are 10 per sample, and the update runs four times.
    r.found(0, 40);
    r.endPass(4);
    for (int k = 0; k < 4; ++k) {
        r2 *= (n + alpha * 10) / (n + 10);
        n += alpha * 10;
    }
    CHECK(r.radius(0) == Approx(std::sqrt(r2)).epsilon(1e-6));
    CHECK(r.meanRadius() == Approx(std::sqrt(r2)).epsilon(1e-6)); // the one pixel with photons
}

TEST_CASE("Pixel caustic radii: under a constant photon density R^2 falls as i^(alpha - 1)",
          "[gi][progressive]") {
    // M_i = d pi R_i^2 at each pass (the expected count): the radius shrinks like the global
    // sequence, so bias (R^2) and noise (1 / (N_i R_i^2)...) both vanish.
    const double alpha = 2.0 / 3.0;
    CausticPixelRadius r(1, 1.0f, alpha);
    r.endPass(1);
    auto scaled = [&](int passes) {
        for (int i = 0; i < passes; ++i) {
            double rr = r.radius(0);
            r.found(0, std::uint32_t(std::lround(100000.0 * rr * rr)));
            r.endPass(1);
        }
        double rr = r.radius(0);
        return rr * rr;
    };
    double at1000 = scaled(1000);
    double at4000 = scaled(3000);
    CHECK(at1000 < 0.1); // 0.074 (the first pass: alpha)
    CHECK(at4000 / at1000 == Approx(std::pow(4.0, alpha - 1)).epsilon(0.03));
}

TEST_CASE("Pixel caustic radii: the same however the visible points' reports are ordered",
          "[gi][progressive]") {
    CausticPixelRadius a(2, 1.0f, 0.7), b(2, 1.0f, 0.7);
    const float seeds[] = {0.3f, 0.011f, 0.52f, 0.9f, 0.0001f};
    for (int k = 0; k < 5; ++k) a.seed(0, seeds[k], std::uint32_t(10 * k));
    for (int k = 4; k >= 0; --k) b.seed(0, seeds[k], std::uint32_t(10 * k));
    a.endPass(2);
    b.endPass(2);
    const std::uint32_t counts[] = {7, 0, 1234, 5, 99};
    for (std::uint32_t c : counts) a.found(0, c);
    for (int k = 4; k >= 0; --k) b.found(0, counts[k]);
    a.endPass(2);
    b.endPass(2);
    CHECK(a.radius(0) == b.radius(0));
    CHECK(a.radius(0) < 1.0f);
}
