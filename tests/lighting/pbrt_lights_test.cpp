// The pbrt importer's lights against hand-computed figures: point and spot "power", distant
// "illuminance", goniometric images and power, image infinite lights (equal-area, lat-long
// fallback, illuminance, portal, L with filename), area light "power" and "blackbody" colours;
// and the Bitterli classroom's skydome loading without warnings.
#include "image/image.h"
#include "lighting/environment.h"
#include "lighting/light_set.h"
#include "lighting/sphere_mapping.h"
#include "pbrt/pbrt_test_util.h"
#include "scene/pbrt/pbrt_lights.h"
#include "scene/pbrt/pbrt_spectrum.h"
#include "skip.h"
#include "spectral/color_space.h"
#include "spectral/rgb_spectrum.h"

#include <filesystem>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// A world snippet with a small sphere, since a scene must have geometry.
LoadedPbrt loadLights(const std::string& lights) {
    return loadWorld(lights + "\nShape \"sphere\" \"float radius\" 0.01\n");
}

const Light& onlyLight(const LoadedPbrt& r) {
    REQUIRE(r.scene->lights.size() == 1);
    return r.scene->lights[0];
}

void writeImageFile(const std::string& name, int w, int h, float value) {
    Image img(w, h);
    for (float& v : img.pixels) v = value;
    writeImage((pbrtTestDir() / name).string(), img);
}

} // namespace

TEST_CASE("pbrt point light: I * scale, power / (4 pi)", "[lights]") {
    auto r = loadLights(R"(LightSource "point" "rgb I" [1 0.5 0.25] "float scale" 2)");
    CHECK(onlyLight(r).intensity.y == Approx(1.0f));
    auto p = loadLights(R"(LightSource "point" "float power" 100)");
    CHECK(onlyLight(p).intensity.x == Approx(7.957747f)); // 100 / (4 pi)
}

TEST_CASE("pbrt spot light: smoothstep falloff and power over its cone", "[lights]") {
    auto r = loadLights(R"(LightSource "spot" "float coneangle" 30 "float conedeltaangle" 10
                          "float power" 50 "point3 from" [0 0 0] "point3 to" [0 0 -1])");
    const Light& l = onlyLight(r);
    // k_e = 2 pi ((1 - cos 20) + (cos 20 - cos 30) / 2) = 0.6103548
    CHECK(l.intensity.x == Approx(81.91956f).epsilon(1e-5));
    CHECK(l.coneAngle == Approx(20.0f));
    CHECK(l.falloffAngle == Approx(10.0f));
    // Full intensity inside 20 degrees, half way (smoothstep 0.5) at cos = mid, 0 beyond 30.
    LightSet set;
    Scene& s = *r.scene;
    EmbreeScene accel(s);
    set = LightSet::build(s, accel);
    const LightSource& spot = set.lights[0];
    auto at = [&](float deg) {
        float t = deg * kPi / 180;
        return spot.directionalFactor(normalize(l.direction * std::cos(t) +
                                                normalize(cross(l.direction, {0, 1, 0})) * std::sin(t)));
    };
    CHECK(at(10) == Approx(1.0f));
    CHECK(at(31) == Approx(0.0f));
    float c20 = std::cos(20 * kPi / 180), c30 = std::cos(30 * kPi / 180);
    float mid = std::acos(0.5f * (c20 + c30)) * 180 / kPi;
    CHECK(at(mid) == Approx(0.5f).margin(1e-3));
}

TEST_CASE("pbrt distant light: L * scale * illuminance", "[lights]") {
    auto r = loadLights(R"(LightSource "distant" "rgb L" [2 2 2] "float scale" 0.5
                          "float illuminance" 3 "point3 from" [0 1 0] "point3 to" [0 0 0])");
    const Light& l = onlyLight(r);
    CHECK(l.type == LightType::Directional);
    CHECK(l.intensity.x == Approx(3.0f));
    CHECK(l.direction.y == Approx(-1.0f));
}

TEST_CASE("pbrt blackbody light colour: luminance 1 times scale", "[lights]") {
    auto r = loadLights(R"(LightSource "point" "blackbody I" 3000 "float scale" 4)");
    Vec3 I = onlyLight(r).intensity;
    CHECK(luminance(I) == Approx(4.0f).epsilon(1e-3));
    CHECK(I.x > I.z); // a 3000 K blackbody is orange
    Vec3 d65 = pbrt::blackbodyRgb(6504);
    CHECK(d65.x == Approx(1.0f).epsilon(0.06)); // near white, not white balanced
    CHECK(d65.z == Approx(1.0f).epsilon(0.1));
}

TEST_CASE("pbrt goniometric light: image in equal-area light space, power", "[lights]") {
    writeImageFile("gonio.pfm", 8, 8, 0.5f);
    writeImageFile("wide.pfm", 16, 8, 1.0f);
    auto r = loadLights(R"(LightSource "goniometric" "string filename" "gonio.pfm"
                          "rgb I" [1 1 1] "float power" 20)");
    const Light& l = onlyLight(r);
    CHECK(l.type == LightType::Goniometric);
    REQUIRE(l.image);
    // k_e = 4 pi * mean = 2 pi: I = 20 / (2 pi)
    CHECK(l.intensity.x == Approx(20.0f / (2 * kPi)));
    EmbreeScene accel(*r.scene);
    LightSet set = LightSet::build(*r.scene, accel);
    CHECK(luminance(set.lights[0].power()) == Approx(20.0f).epsilon(1e-4));
    // pbrt-v4 swaps y and z: the image's centre (+z) is the light's +y.
    Vec3 centre = l.toWorld.vector({0, 0, 1});
    CHECK(std::abs(centre.y) == Approx(1.0f));
    // One bright pixel: the intensity towards its direction (y and z swapped) is I * 7.
    Image one(8, 8);
    float* px = one.at(2, 5);
    px[0] = px[1] = px[2] = 7.0f;
    writeImage((pbrtTestDir() / "gonio-one.pfm").string(), one);
    auto g = loadLights(R"(LightSource "goniometric" "string filename" "gonio-one.pfm"
                           "rgb I" [2 2 2])");
    EmbreeScene gAccel(*g.scene);
    LightSet gSet = LightSet::build(*g.scene, gAccel);
    Vec3 d = equalAreaSquareToSphere({2.5f / 8, 5.5f / 8});
    const LightSource& gl = gSet.lights[0];
    CHECK(gl.directionalFactor({d.x, d.z, d.y}) == Approx(7.0f));
    CHECK(gl.directionalFactor(d) == Approx(0.0f)); // unswapped: another pixel
    LightSample ls = gl.sample(Vec3{d.x, d.z, d.y} * 2.0f, {0.5f, 0.5f});
    REQUIRE(ls.valid);
    CHECK(ls.weight.x == Approx(2.0f * 7.0f / 4.0f)); // I * image / r^2
    CHECK(pbrtErrorOf(std::string(kPbrtHeader) +
                      R"(LightSource "goniometric" "string filename" "wide.pfm")")
              .find("square") != std::string::npos);
}

TEST_CASE("pbrt image infinite light: equal-area, illuminance, portal, lat-long", "[lights]") {
    writeImageFile("sky.pfm", 64, 64, 2.0f);
    writeImageFile("wide.pfm", 16, 8, 1.0f);
    auto r = loadLights(R"(LightSource "infinite" "string filename" "sky.pfm" "float scale" 3)");
    const Light& l = onlyLight(r);
    CHECK(l.type == LightType::Environment);
    REQUIRE(l.image);
    CHECK(l.mapping == EnvironmentMapping::EqualArea);
    CHECK(l.intensity.x == Approx(3.0f));
    CHECK(r.warnings.empty());
    // pbrt-v4's illuminance estimate of a uniform map of radiance 2 is 2 pi / N * sum of
    // 2 cos over the upper half: about 2 * pi / 2 = pi, so "illuminance" 10 scales by ~10 / pi.
    auto e = loadLights(R"(LightSource "infinite" "string filename" "sky.pfm" "float illuminance" 10)");
    CHECK(onlyLight(e).intensity.x == Approx(10.0f / kPi).epsilon(0.01));
    auto p = loadLights(R"(LightSource "infinite" "string filename" "sky.pfm"
                          "point3 portal" [0 0 0 1 0 0 1 1 0 0 1 0])");
    CHECK(p.warned("portal"));
    auto w = loadLights(R"(LightSource "infinite" "string filename" "wide.pfm")");
    CHECK(w.warned("lat-long"));
    CHECK(onlyLight(w).mapping == EnvironmentMapping::LatLong);
    CHECK(pbrtErrorOf(std::string(kPbrtHeader) +
                      R"(LightSource "infinite" "string filename" "sky.pfm" "rgb L" [1 1 1])")
              .find("not both") != std::string::npos);
    // Constant skies: illuminance / pi.
    auto c = loadLights(R"(LightSource "infinite" "rgb L" [1 1 1] "float illuminance" 3.14159265)");
    CHECK(onlyLight(c).intensity.x == Approx(1.0f));
    CHECK_FALSE(onlyLight(c).image);
}

TEST_CASE("pbrt area light power: radiance = power / (pi A sides)", "[lights]") {
    pbrt::AreaEmission e;
    e.radiance = {1, 1, 1};
    e.power = 10;
    CHECK(pbrt::areaRadianceForPower(e, 2.0).x == Approx(10.0 / (kPi * 2)));
    e.twoSided = true;
    CHECK(pbrt::areaRadianceForPower(e, 2.0).x == Approx(10.0 / (kPi * 4)));
    Shape disk;
    disk.type = ShapeType::Disk;
    disk.radius = 2;
    CHECK(pbrt::shapesArea({disk}, Affine::scale({0.5f, 0.5f, 0.5f})) == Approx(kPi));
}

TEST_CASE("The classroom's skydome loads as an equal-area image sky without warnings",
          "[lights]") {
    // ../shared beside the checkout, as in CI (scripts/public-scenes); absent elsewhere.
    const std::string path =
        (std::filesystem::path(RAYPROC_SOURCE_DIR) / "../shared/scenes/bitterli/classroom/scene-v4.pbrt")
            .lexically_normal()
            .string();
    if (!std::filesystem::is_regular_file(path)) RAYPROC_SKIP("no " << path);
    std::vector<std::string> warnings;
    auto scene = loadPbrtScene(path, &warnings);
    for (const std::string& w : warnings) {
        INFO(w);
        CHECK(w.find("infinite") == std::string::npos);
        CHECK(w.find("LightSource") == std::string::npos);
        CHECK(w.find("Skydome") == std::string::npos);
    }
    int skies = 0;
    for (const Light& l : scene->lights) {
        if (l.type != LightType::Environment) continue;
        ++skies;
        REQUIRE(l.image);
        CHECK(l.image->width == 512);
        CHECK(l.mapping == EnvironmentMapping::EqualArea);
    }
    CHECK(skies == 1);
}

namespace {

// The light's own spectrum: present, luminance 1, its colour the light's RGB colour over k.
const EmissionSpectrum& keptSpectrum(const EmissionSpectrumRef& s, const Vec3& rgbValue) {
    REQUIRE(s);
    CHECK(spectral::toXyz(s->values).y == Approx(1.0).epsilon(1e-5));
    const float k = emissionScale(*s, rgbValue);
    CHECK(rgbValue.x == Approx(s->rgb.x * k).epsilon(1e-5));
    CHECK(rgbValue.y == Approx(s->rgb.y * k).epsilon(1e-5));
    CHECK(rgbValue.z == Approx(s->rgb.z * k).epsilon(1e-5));
    return *s;
}

// A blackbody's spectrum has Planck's law's shape.
void checkPlanckShape(const EmissionSpectrum& s, double kelvin) {
    for (double nm : {400.0, 500.0, 700.0, 800.0})
        CHECK(s.values.at(float(nm)) / s.values.at(555) ==
              Approx(kernels::spectral::planck(nm, kelvin) / kernels::spectral::planck(555, kelvin))
                  .epsilon(1e-5));
}

} // namespace

TEST_CASE("pbrt lights keep a blackbody's spectrum beside its colour", "[lights][spectral]") {
    for (const char* light :
         {R"(LightSource "point" "blackbody I" 2700 "float scale" 3)",
          R"(LightSource "spot" "blackbody I" 2700 "float power" 40)",
          R"(LightSource "distant" "blackbody L" 2700 "float illuminance" 5)",
          R"(LightSource "goniometric" "blackbody I" 2700 "float scale" 2)",
          R"(LightSource "infinite" "blackbody L" 2700 "float scale" 0.5)"}) {
        INFO(light);
        auto r = loadLights(light);
        const Light& l = onlyLight(r);
        const EmissionSpectrum& s = keptSpectrum(l.spectrum, l.intensity);
        CHECK(s.label == "blackbody 2700");
        checkPlanckShape(s, 2700);
        // RGB mode's colour is unchanged: the blackbody's at luminance 1, times the scalar.
        Vec3 bb = pbrt::blackbodyRgb(2700);
        CHECK(s.rgb.x == bb.x);
        CHECK(s.rgb.z == bb.z);
    }
    // The scalar is the one pbrt-v4 applies after dividing by the photometric integral.
    auto p = loadLights(R"(LightSource "point" "blackbody I" 2700 "float scale" 3)");
    CHECK(emissionScale(*onlyLight(p).spectrum, onlyLight(p).intensity) == Approx(3.0f));
}

TEST_CASE("pbrt area lights keep their spectrum through power", "[lights][spectral]") {
    auto r = loadWorld(R"(AttributeBegin
        AreaLightSource "diffuse" "blackbody L" 4000 "float power" 10
        Shape "bilinearmesh" "point3 P" [0 0 0 1 0 0 0 1 0 1 1 0]
        AttributeEnd)");
    std::vector<PlacedShape> shapes = rootShapes(*r.scene);
    REQUIRE(shapes.size() == 1);
    const Shape& sh = *shapes[0].shape;
    const EmissionSpectrum& s = keptSpectrum(sh.emissionSpectrum, sh.emission);
    checkPlanckShape(s, 4000);
    // power = pi A L_v: luminance 10 / pi over the unit square.
    CHECK(emissionScale(s, sh.emission) == Approx(10.0 / kPi).epsilon(1e-5));
}

TEST_CASE("pbrt lights keep sampled and named illuminant spectra, not RGB ones",
          "[lights][spectral]") {
    auto sampled = loadLights(R"(LightSource "point" "spectrum I" [450 1 500 3 600 2])");
    const EmissionSpectrum& s = keptSpectrum(onlyLight(sampled).spectrum, onlyLight(sampled).intensity);
    CHECK(s.values.at(440) == 0.0f); // zero outside the pairs, as pbrt-v4's
    CHECK(s.values.at(610) == 0.0f);
    CHECK(s.values.at(500) / s.values.at(450) == Approx(3.0).epsilon(1e-5));
    CHECK(s.values.at(550) / s.values.at(450) == Approx(2.5).epsilon(1e-5));

    auto named = loadLights(R"(LightSource "distant" "spectrum L" "stdillum-F11")");
    const EmissionSpectrum& f11 = keptSpectrum(onlyLight(named).spectrum, onlyLight(named).intensity);
    CHECK(f11.label == "stdillum-F11");
    for (float nm : {435.0f, 546.0f, 611.0f}) // its mercury and europium lines
        CHECK(f11.values.at(nm) == Approx(spectral::cieIlluminant("F11")->at(nm)).epsilon(1e-5));

    // RGB under sRGB and an image sky have no spectrum of their own (a one-number spectrum is
    // an error, as in pbrt-v4: tests/pbrt/pbrt_materials_test.cpp).
    CHECK_FALSE(onlyLight(loadLights(R"(LightSource "point" "rgb I" [1 0.5 0.2])")).spectrum);
    writeImageFile("sky.pfm", 8, 8, 0.5f);
    CHECK_FALSE(
        onlyLight(loadLights(R"(LightSource "infinite" "string filename" "sky.pfm")")).spectrum);
    // An "rgb" under another colour space is that space's RGB illuminant spectrum.
    auto rec = loadLights(R"(ColorSpace "rec2020"
        LightSource "point" "rgb I" [0.2 0.9 0.1])");
    const Light& l = onlyLight(rec);
    REQUIRE(l.spectrum);
    const spectral::ColorSpace& cs = *spectral::colorSpaceByName("rec2020");
    spectral::RgbIlluminantSpectrum want(cs, 0.2f, 0.9f, 0.1f);
    CHECK(l.spectrum->values.at(530) == Approx(want(530)).epsilon(1e-5));
    CHECK(emissionScale(*l.spectrum, l.intensity) == Approx(1.0f));
}

TEST_CASE("pbrt constant skies add up with their spectra", "[lights][spectral]") {
    auto r = loadLights(R"(LightSource "infinite" "blackbody L" 3000
                          LightSource "infinite" "rgb L" [0.2 0.3 0.4])");
    const Light& sky = onlyLight(r);
    const Vec3 bb = pbrt::blackbodyRgb(3000);
    CHECK(sky.intensity.x == Approx(bb.x + 0.2f));
    REQUIRE(sky.spectrum);
    EmissionSpectrumRef alone = pbrt::blackbodyEmission(3000);
    spectral::RgbIlluminantSpectrum rgb(spectral::colorSpace(spectral::ColorSpaceId::Srgb), 0.2f,
                                        0.3f, 0.4f);
    CHECK(sky.spectrum->values.at(600) == Approx(alone->values.at(600) + rgb(600)).epsilon(1e-5));
    // The light set's sky takes it while the sky has no image.
    EmbreeScene accel(*r.scene);
    LightSet set = LightSet::build(*r.scene, accel);
    REQUIRE(set.environment.constantSpectrum());
    CHECK(set.environment.constantSpectrum()->values.at(600) == sky.spectrum->values.at(600));
}
