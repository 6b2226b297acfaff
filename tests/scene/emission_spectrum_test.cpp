// scene/emission_spectrum.h: an emitter's own spectrum beside its RGB colour. Normalised to
// luminance 1 (pbrt-v4's photometric normalisation of a light's spectrum), the scalar of an
// emitter's RGB value over the colour, and two constant skies added into one.
#include "scene/emission_spectrum.h"
#include "spectral/color_space.h"
#include "spectral/rgb_spectrum.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace rayproc;

namespace {

double luminanceOf(const spectral::DenseSpectrum& s) {
    return spectral::toXyz(s).y;
}

spectral::DenseSpectrum ramp() {
    return spectral::DenseSpectrum::sample([](double nm) { return 0.01 * (nm - 300); });
}

} // namespace

TEST_CASE("Emission spectra: luminance 1, the scalar of an RGB value, black gives none",
          "[scene][spectral]") {
    EmissionSpectrumRef e = emissionAtLuminance1(ramp(), Vec3(1.2f, 1.0f, 0.7f), "ramp");
    REQUIRE(e);
    CHECK(luminanceOf(e->values) == Approx(1.0).epsilon(1e-6));
    // Only the scale changed: the ratio of two samples is the ramp's.
    CHECK(e->values.at(700) / e->values.at(400) == Approx(400.0 / 100.0).epsilon(1e-5));
    CHECK(e->label == "ramp");
    // An RGB value of 3 times the colour emits 3 times the spectrum; the largest channel
    // decides (red here), so a value off the colour's direction reads its red.
    CHECK(emissionScale(*e, Vec3(3.6f, 3.0f, 2.1f)) == Approx(3.0f));
    CHECK(emissionScale(*e, Vec3(0.0f)) == 0.0f);
    EmissionSpectrum black;
    CHECK(emissionScale(black, Vec3(1.0f)) == 0.0f);
    CHECK_FALSE(emissionAtLuminance1(spectral::DenseSpectrum{}, Vec3(1.0f), "zero"));
}

TEST_CASE("Emission spectra: two constant skies add up, an RGB one as its illuminant spectrum",
          "[scene][spectral]") {
    EmissionSpectrumRef own = emissionAtLuminance1(ramp(), Vec3(1.2f, 1.0f, 0.7f), "ramp");
    const Vec3 a = own->rgb * 2.0f; // 2 x the ramp
    const Vec3 b(0.5f, 0.25f, 0.125f); // RGB, no spectrum of its own
    EmissionSpectrumRef sum = sumOfEmissions(a, own, b, nullptr);
    REQUIRE(sum);
    CHECK(sum->rgb.x == Approx(a.x + b.x));
    CHECK(sum->rgb.z == Approx(a.z + b.z));
    CHECK(emissionScale(*sum, sum->rgb) == Approx(1.0f));
    const spectral::ColorSpace& srgb = spectral::colorSpace(spectral::ColorSpaceId::Srgb);
    spectral::RgbIlluminantSpectrum rgbSpectrum(srgb, b.x, b.y, b.z);
    for (float nm : {400.0f, 500.0f, 555.0f, 650.0f, 800.0f})
        CHECK(sum->values.at(nm) ==
              Approx(2 * own->values.at(nm) + rgbSpectrum(nm)).epsilon(1e-5));
    // Neither has a spectrum: none; one side black: the other's spectrum itself.
    CHECK_FALSE(sumOfEmissions(a, nullptr, b, nullptr));
    CHECK(sumOfEmissions(Vec3(0.0f), nullptr, a, own) == own);
    CHECK(sumOfEmissions(a, own, Vec3(0.0f), nullptr) == own);
}
