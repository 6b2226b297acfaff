// Emission spectra in the spectral mode (scene/emission_spectrum.h, docs/spectral.md,
// "Emission spectra"): a pbrt-v4 blackbody light renders with Planck's law itself, scaled as
// pbrt-v4 scales it (over its photometric integral), not as the RGB illuminant spectrum of its
// colour. Against the test's own quadrature of Planck x reflectance x CIE functions; a directly
// seen blackbody light and sky come out in RGB mode's colour.
#include "../analytic/analytic.h"
#include "pbrt/pbrt_test_util.h"
#include "scene/pbrt/pbrt_spectrum.h"
#include "spectral/color_space.h"
#include "spectral/rgb_spectrum.h"
#include "spectral/spectra.h"

using namespace rayproc;
using namespace rayproc::test;

namespace {

Image renderIn(const std::string& mode, const Scene& scene, const EmbreeScene& accel, int spp,
               bool spectral) {
    ModeOverrides o{spp, 0, 0};
    if (mode == "gi") {
        GiSettings gi = giSettings(scene, o);
        return renderGi(scene, accel, gi, quietTwoThreads(spectral)).image;
    }
    if (mode == "raytrace")
        return renderRaytrace(scene, accel, raytraceSettings(scene.render, o),
                              quietTwoThreads(spectral))
            .image;
    return renderPath(scene, accel, pathSettings(scene.render, o), quietTwoThreads(spectral)).image;
}

// Linear sRGB of the radiance rho(l) E(l) / pi a Lambertian surface of reflectance rho sends
// back under a head-on light of irradiance spectrum E: XYZ by a sum over every nanometre of
// 360-830, over the y-bar integral (the film's normalisation), then sRGB's matrix.
Vec3 lambertianUnder(const std::function<double(double)>& rho,
                     const std::function<double(double)>& irradiance) {
    spectral::Xyz xyz = spectral::toXyz(
        [&](double nm) { return rho(nm) * irradiance(nm) / 3.14159265358979323846; });
    spectral::ColorSpace::Rgb c =
        spectral::colorSpace(spectral::ColorSpaceId::Srgb).fromXyz({xyz.x, xyz.y, xyz.z});
    return {float(c.r), float(c.g), float(c.b)};
}

} // namespace

TEST_CASE("Spectral mode: a blackbody distant light on a saturated surface is Planck's light",
          "[spectral-mode][spectral]") {
    // pbrt-v4: L = Planck / its photometric integral (luminance 1), irradiance 1 head-on, on a
    // cyan Lambertian square whose reflectance is sRGB's upsampled spectrum of the RGB.
    const Vec3 reflectance(0.1f, 0.9f, 0.9f);
    const spectral::ColorSpace& srgb = spectral::colorSpace(spectral::ColorSpaceId::Srgb);
    spectral::RgbAlbedoSpectrum rho(srgb, reflectance.x, reflectance.y, reflectance.z);
    auto rhoAt = [&](double nm) { return double(rho(float(nm))); };
    for (const double kelvin : {2700.0, 1900.0}) {
        auto r = loadWorld(R"(LightSource "distant" "blackbody L" )" + std::to_string(kelvin) + R"(
                "point3 from" [0 0 1] "point3 to" [0 0 0]
            Material "diffuse" "rgb reflectance" [0.1 0.9 0.9]
            Shape "bilinearmesh" "point3 P" [-5 -5 0 5 -5 0 -5 5 0 5 5 0])");
        REQUIRE(r.warnings.empty());
        double planckY = 0; // the photometric integral over the same samples
        for (int nm = 360; nm <= 830; ++nm)
            planckY += spectral::cieY().at(float(nm)) * kernels::spectral::planck(nm, kelvin);
        const double unit = spectral::cieYIntegral() / planckY;
        const Vec3 expected = lambertianUnder(
            rhoAt, [&](double nm) { return kernels::spectral::planck(nm, kelvin) * unit; });
        // What the mode rendered before: the RGB illuminant spectrum of the blackbody's colour.
        const Vec3 bb = pbrt::blackbodyRgb(kelvin);
        spectral::RgbIlluminantSpectrum old(srgb, bb.x, bb.y, bb.z);
        const Vec3 before =
            lambertianUnder(rhoAt, [&](double nm) { return double(old(float(nm))); });
        // Of the largest channel, besides 4 standard errors: the nearest nanometre's samples
        // against the quadrature's every nanometre.
        const double tolerance = 1e-3 * maxComponent(expected);
        double missedBefore = 0;
        for (int c = 0; c < 3; ++c)
            missedBefore = std::max(missedBefore, double(std::abs(before[c] - expected[c])));
        INFO(kelvin << " K: expected " << expected.x << " " << expected.y << " " << expected.z
                    << ", before " << before.x << " " << before.y << " " << before.z);
        CHECK(missedBefore > 10 * tolerance);

        EmbreeScene accel(*r.scene);
        for (const std::string mode : {"path", "raytrace", "gi"}) {
            Image img = renderIn(mode, *r.scene, accel, 64, true);
            for (int c = 0; c < 3; ++c) {
                PixelStats s = pixelStats(img, c);
                INFO(mode << " channel " << c << ": rendered " << s.mean << " +- " << s.stdError
                          << ", expected " << expected[c] << ", before " << before[c]);
                CHECK(std::abs(s.mean - expected[c]) <= 4 * s.stdError + tolerance);
                CHECK(s.stdError < tolerance);
            }
        }
    }
}

TEST_CASE("Spectral mode: a directly seen blackbody light and sky have RGB mode's colour",
          "[spectral-mode][spectral]") {
    auto area = loadWorld(R"(AttributeBegin
        AreaLightSource "diffuse" "blackbody L" 2700 "float scale" 2 "bool twosided" true
        Shape "bilinearmesh" "point3 P" [-5 -5 0 5 -5 0 -5 5 0 5 5 0]
        AttributeEnd)");
    auto sky = loadWorld(R"(LightSource "infinite" "blackbody L" 6000 "float scale" 1.5
        AttributeBegin Translate 0 0 10 Shape "sphere" "float radius" 0.01 AttributeEnd)");
    const std::pair<LoadedPbrt*, Vec3> cases[] = {{&area, pbrt::blackbodyRgb(2700) * 2.0f},
                                                  {&sky, pbrt::blackbodyRgb(6000) * 1.5f}};
    for (const auto& [loaded, colour] : cases) {
        REQUIRE(loaded->warnings.empty());
        EmbreeScene accel(*loaded->scene);
        for (const std::string mode : {"path", "raytrace", "gi"}) {
            Image rgb = renderIn(mode, *loaded->scene, accel, 1, false);
            Image spec = renderIn(mode, *loaded->scene, accel, 32, true);
            for (int c = 0; c < 3; ++c) {
                PixelStats a = pixelStats(rgb, c), b = pixelStats(spec, c);
                INFO(mode << " channel " << c << ": RGB " << a.mean << ", spectral " << b.mean
                          << " +- " << b.stdError);
                CHECK(a.mean == Approx(colour[c]).epsilon(1e-5));
                CHECK(std::abs(b.mean - a.mean) <= 4 * b.stdError + 2e-3 * maxComponent(colour));
                CHECK(b.stdError < 2e-3 * maxComponent(colour));
            }
        }
    }
}
