// Spectral gi keeps its estimates of irradiance in RGB (photon maps of XYZ, the irradiance
// cache) and takes them back to a path's wavelengths as an RGB illuminant spectrum (the
// sigmoid spectrum of the colour times the colour space's illuminant, gi/gather_stage.h's
// lightAt) before the surface's reflectance multiplies them per wavelength. That spectrum has
// the irradiance's colour but not its shape: a metamer. Here light of the illuminant (D65)
// reflected by one surface A (its spectrum D65 rho_A) lights a surface B; the colour B
// reflects is computed three ways:
//  - exact: D65 rho_A rho_B integrated;
//  - spectral gi: the metamer of D65 rho_A's RGB, times rho_B, integrated;
//  - RGB mode: RGB(D65 rho_A) x RGB(rho_B) per channel.
#include "core/math.h"
#include "spectral/rgb_spectrum.h"
#include "spectral/spectra.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace rayproc;
using namespace rayproc::spectral;

namespace {

const ColorSpace& srgb() { return colorSpace(ColorSpaceId::Srgb); }

Vec3 rgbOf(const std::function<double(double)>& f) {
    ColorSpace::Rgb v = srgb().fromXyz(toXyz(f));
    return {float(v.r), float(v.g), float(v.b)};
}

struct Bounce {
    Vec3 exact, metamer, rgb;
};

// Light of the illuminant reflected by a, then by b.
Bounce secondBounce(const Vec3& a, const Vec3& b) {
    const DenseSpectrum& d65 = *srgb().illuminant;
    RgbAlbedoSpectrum ra(srgb(), a.x, a.y, a.z), rb(srgb(), b.x, b.y, b.z);
    Bounce out;
    const Vec3 e = rgbOf([&](double nm) { return d65.at(float(nm)) * ra(float(nm)); });
    RgbIlluminantSpectrum m(srgb(), e.x, e.y, e.z);
    out.exact = rgbOf([&](double nm) { return d65.at(float(nm)) * ra(float(nm)) * rb(float(nm)); });
    out.metamer = rgbOf([&](double nm) { return m(float(nm)) * rb(float(nm)); });
    out.rgb = e * b;
    return out;
}

} // namespace

TEST_CASE("Irradiance as an illuminant spectrum: exact for white light, the colour kept",
          "[spectral]") {
    // Light of the illuminant itself (a grey first surface) is the illuminant's spectrum
    // exactly, so any second surface reflects it as the exact spectrum does.
    Bounce grey = secondBounce(Vec3(0.5f), Vec3(0.63f, 0.065f, 0.05f));
    for (int c = 0; c < 3; ++c) CHECK(grey.metamer[c] == Approx(grey.exact[c]).margin(2e-4));
    // A coloured irradiance's metamer keeps its colour: a white second surface reflects it.
    Bounce red = secondBounce(Vec3(0.63f, 0.065f, 0.05f), Vec3(1.0f));
    for (int c = 0; c < 3; ++c) CHECK(red.metamer[c] == Approx(red.exact[c]).margin(1e-3));
}

TEST_CASE("Irradiance metamers: the Cornell box's second bounces (figures)",
          "[.][spectral-measure]") {
    const Vec3 red(0.63f, 0.065f, 0.05f), green(0.14f, 0.45f, 0.091f), white(0.725f, 0.71f, 0.68f);
    const Vec3 orange(1.0f, 0.378676f, 0.013473f);
    struct Pair {
        const char* name;
        Vec3 a, b;
    } pairs[] = {{"red -> white", red, white},   {"green -> white", green, white},
                 {"white -> red", white, red},   {"red -> red", red, red},
                 {"green -> green", green, green}, {"red -> green", red, green},
                 {"green -> red", green, red},   {"orange -> orange", orange, orange}};
    // Errors per channel in percent of the exact colour's largest channel (a channel near 0,
    // or negative outside sRGB, makes a relative error meaningless).
    std::printf("pair | exact RGB | metamer - exact | RGB mode - exact\n");
    for (const Pair& p : pairs) {
        Bounce r = secondBounce(p.a, p.b);
        const float largest = std::max({r.exact.x, r.exact.y, r.exact.z});
        std::printf("%s | %.5f %.5f %.5f", p.name, r.exact.x, r.exact.y, r.exact.z);
        for (const Vec3* v : {&r.metamer, &r.rgb}) {
            std::printf(" |");
            for (int c = 0; c < 3; ++c)
                std::printf(" %+.2f%%", 100.0 * ((*v)[c] - r.exact[c]) / largest);
        }
        std::printf("\n");
    }
}
