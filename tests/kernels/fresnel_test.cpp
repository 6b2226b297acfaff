// kernels/fresnel.h: the conductor Fresnel reflectance, written in real arithmetic, against the
// textbook complex-index formula evaluated in double precision.
#include "kernels/fresnel.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <complex>
#include <iterator>
#include <sstream>

using namespace rayproc;
using namespace rayproc::kernels;

namespace {

// Snell's law with the complex index n = eta + i k: sin^2 T = sin^2 I / n^2, and the amplitude
// reflection coefficients' squared moduli, averaged over the two polarisations.
double fresnelComplexReference(double cosI, double eta, double k) {
    using C = std::complex<double>;
    C n(eta, k);
    C cosT = std::sqrt(C(1.0) - C(1.0 - cosI * cosI) / (n * n));
    C rPar = (n * cosI - cosT) / (n * cosI + cosT);
    C rPerp = (C(cosI) - n * cosT) / (C(cosI) + n * cosT);
    return 0.5 * (std::norm(rPar) + std::norm(rPerp));
}

} // namespace

TEST_CASE("Conductor Fresnel in real arithmetic equals the complex-index formula",
          "[kernels][fresnel]") {
    // Gold, copper, aluminium and silver-like indices (pbrt-v4's RGB fits span these), a
    // dielectric (k = 0) on both sides of 1, where eta < 1 reflects totally past the critical
    // angle, and extremes of both parameters.
    const float etas[] = {0.143f, 0.2f, 0.27f, 1.1f, 1.5f, 0.67f, 3.0f, 0.05f, 10.0f};
    const float ks[] = {3.98f, 3.6f, 2.78f, 6.8f, 0.0f, 0.0f, 0.01f, 8.0f, 20.0f};
    double worst = 0;
    std::ostringstream where;
    for (int m = 0; m < int(std::size(etas)); ++m)
        for (int i = 0; i <= 1000; ++i) {
            float cosI = float(i) / 1000.0f;
            double expected = fresnelComplexReference(cosI, etas[m], ks[m]);
            double got = fresnelComplex(cosI, etas[m], ks[m]);
            REQUIRE(std::isfinite(got));
            if (std::abs(got - expected) > worst) {
                worst = std::abs(got - expected);
                where.str("");
                where << "eta " << etas[m] << " k " << ks[m] << " cosI " << cosI << ": " << got
                      << " against " << expected;
            }
        }
    INFO("largest difference " << worst << " at " << where.str());
    CHECK(worst < 2e-5);
    // The limits: grazing incidence reflects everything, also on an index of exactly 1.
    CHECK(fresnelComplex(0.0f, 0.2f, 3.6f) == 1.0f);
    CHECK(fresnelComplex(0.0f, 1.0f, 0.0f) == 1.0f);
    CHECK(fresnelComplex(1.0f, 1.0f, 0.0f) == 0.0f);
}
