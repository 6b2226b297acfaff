// Reflectance spectra in the spectral mode (scene/reflectance_spectrum.h, docs/spectral.md,
// "Reflectance spectra"): a pbrt-v4 material's sampled reflectance, or an rgb reflectance
// under another ColorSpace, keeps its spectrum for the spectral mode, which evaluates it at the
// path's wavelengths instead of upsampling its sRGB colour; RGB mode renders the colour as
// before. Against the test's own quadrature of light x reflectance x CIE functions.
#include "../analytic/analytic.h"
#include "engine/material_bsdf.h"
#include "engine/spectral_render.h"
#include "lighting/light_set.h"
#include "pbrt/pbrt_test_util.h"
#include "scene/pbrt/pbrt_spectrum.h"
#include "scene/reflectance_spectrum.h"
#include "spectral/color_space.h"
#include "spectral/rgb_spectrum.h"
#include "spectral/spectra.h"
#include "texture/texture_eval.h"

#include <algorithm>
#include <cstdio>
#include <functional>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// A reflectance with steps the sigmoid family cannot follow: its sRGB metamer differs.
const std::vector<double> kPairs = {400, 0.1, 480, 0.8, 520, 0.05, 600, 0.9, 650, 0.15, 700, 0.6};
const char* kPairsText = "[400 0.1 480 0.8 520 0.05 600 0.9 650 0.15 700 0.6]";

const spectral::ColorSpace& srgb() { return spectral::colorSpace(spectral::ColorSpaceId::Srgb); }

// The material of the first shape after `world`.
Material materialOf(const std::string& world) {
    auto r = loadWorld(world + "\nShape \"sphere\"\n");
    REQUIRE(r.warnings.empty());
    auto shapes = rootShapes(*r.scene);
    REQUIRE(!shapes.empty());
    return r.scene->materials[std::size_t(shapes[0].shape->material)];
}

// Linear sRGB of rho(l) E(l) / pi (a Lambertian surface under a head-on light of irradiance
// spectrum E): XYZ summed over every nanometre over the y-bar integral, then sRGB's matrix.
Vec3 lambertianUnder(const std::function<double(double)>& rho,
                     const std::function<double(double)>& irradiance) {
    spectral::Xyz xyz = spectral::toXyz(
        [&](double nm) { return rho(nm) * irradiance(nm) / 3.14159265358979323846; });
    spectral::ColorSpace::Rgb c = srgb().fromXyz({xyz.x, xyz.y, xyz.z});
    return {float(c.r), float(c.g), float(c.b)};
}

// The spectrum sRGB's table upsamples `colour` to, as a reflectance.
std::function<double(double)> upsampled(const Vec3& colour) {
    const spectral::RgbAlbedoSpectrum metamer(srgb(), colour.x, colour.y, colour.z);
    return [metamer](double nm) { return double(metamer(float(nm))); };
}

// The largest difference between two colours' channels.
double largestGap(const Vec3& a, const Vec3& b) {
    double gap = 0;
    for (int c = 0; c < 3; ++c) gap = std::max(gap, double(std::abs(a[c] - b[c])));
    return gap;
}

// A 4000 K blackbody's spectral irradiance as pbrt-v4 scales a light's (Planck's law over its
// photometric integral): irradiance 1 head-on.
std::function<double(double)> planck4000() {
    double planckY = 0;
    for (int nm = 360; nm <= 830; ++nm)
        planckY += spectral::cieY().at(float(nm)) * kernels::spectral::planck(nm, 4000);
    const double unit = spectral::cieYIntegral() / planckY;
    return [unit](double nm) { return kernels::spectral::planck(nm, 4000) * unit; };
}

std::string squareUnder(const std::string& material) {
    return "LightSource \"distant\" \"blackbody L\" 4000 \"point3 from\" [0 0 1] "
           "\"point3 to\" [0 0 0]\n" +
           material + "\nShape \"bilinearmesh\" \"point3 P\" [-5 -5 0 5 -5 0 -5 5 0 5 5 0]\n";
}

// Path mode, 16 x 16 pixels (every stage reads a material's colour at the lane through the
// same precomputed value, engine/spectral_render.h).
Image render(Scene& scene, int spp, bool spectral) {
    scene.camera.width = scene.camera.height = 16;
    EmbreeScene accel(scene);
    return renderPath(scene, accel, pathSettings(scene.render, ModeOverrides{spp, 0, 0}),
                      quietTwoThreads(spectral))
        .image;
}

// The spectral render of `scene` (64 spp) is `expected` in every channel within 4 standard
// errors plus `tolerance`, with a standard error under 2 tolerances; `before` (what the mode
// rendered until then) is only reported.
void checkSpectralRender(Scene& scene, const Vec3& expected, const Vec3& before,
                         double tolerance) {
    Image img = render(scene, 64, true);
    for (int c = 0; c < 3; ++c) {
        PixelStats s = pixelStats(img, c);
        INFO("channel " << c << ": rendered " << s.mean << " +- " << s.stdError << ", expected "
                        << expected[c] << ", before " << before[c]);
        CHECK(std::abs(s.mean - expected[c]) <= 4 * s.stdError + tolerance);
        CHECK(s.stdError < 2 * tolerance);
    }
}

// bsdfAt's parameters on `material` facing +z at three lanes: check(b, i, nm) for each of a
// lane's wavelengths i, nm its nearest nanometre's index into a DenseSpectrum.
template <class Check> void atLanes(const Scene& scene, int material, const Check& check) {
    EmbreeScene accel(scene);
    LightSet lights = LightSet::build(scene, accel);
    SpectralRender spectral(scene, lights);
    LaneShading wl(&spectral);
    SurfaceHit hit;
    hit.ng = hit.ns = Vec3(0, 0, 1);
    hit.material = material;
    for (float u : {0.1f, 0.35f, 0.6f}) {
        wl.select(u);
        const kernels::BsdfParams b = bsdfAt(scene, material, hit, 0, wl.shading());
        for (int i = 0; i < 3; ++i) {
            INFO("lambda " << wl.lane().w.lambda[i]);
            check(b, i, std::size_t(wl.lane().nm[i]));
        }
    }
}

} // namespace

TEST_CASE("pbrt reflectance spectra are kept for the spectral mode beside their colour",
          "[pbrt][spectral]") {
    // Sampled pairs: the spectrum itself (zero outside its range), the colour as before.
    Material d = materialOf(std::string("Material \"diffuse\" \"spectrum reflectance\" ") + kPairsText);
    REQUIRE(d.colorSpectrum);
    CHECK(d.colorSpectrum->values.at(480) == Approx(0.8));
    CHECK(d.colorSpectrum->values.at(500) == Approx(0.425));
    CHECK(d.colorSpectrum->values.at(390) == 0.0f);
    CHECK(d.color == pbrt::sampledReflectanceRgb(kPairs));
    // Values above 1 are clamped, as pbrt-v4's materials clamp a reflectance.
    Material bright = materialOf("Material \"diffuse\" \"spectrum reflectance\" [400 0.2 500 1.3 600 0.2]");
    REQUIRE(bright.colorSpectrum);
    CHECK(bright.colorSpectrum->values.at(500) == 1.0f);
    // An rgb under sRGB has none (the spectral mode upsamples it itself); under rec2020 it is
    // rec2020's spectrum, not the sRGB metamer of its colour.
    CHECK_FALSE(materialOf("Material \"diffuse\" \"rgb reflectance\" [0.2 0.5 0.7]").colorSpectrum);
    Material rec = materialOf("ColorSpace \"rec2020\"\nMaterial \"diffuse\" \"rgb reflectance\" [0.7 0.2 0.1]");
    REQUIRE(rec.colorSpectrum);
    spectral::RgbAlbedoSpectrum rho(spectral::colorSpace(spectral::ColorSpaceId::Rec2020), 0.7f, 0.2f, 0.1f);
    for (float nm : {450.0f, 550.0f, 650.0f})
        CHECK(rec.colorSpectrum->values.at(nm) == Approx(rho(nm)).epsilon(1e-5));
    // coateddiffuse, a conductor's reflectance, diffusetransmission's two colours, and a
    // constant texture's value.
    const std::string pairs = std::string("\"spectrum reflectance\" ") + kPairsText;
    CHECK(materialOf("Material \"coateddiffuse\" " + pairs).colorSpectrum);
    CHECK(materialOf("Material \"conductor\" " + pairs).colorSpectrum);
    Material dt = materialOf("Material \"diffusetransmission\" " + pairs +
                             " \"spectrum transmittance\" [400 0.5 700 0.1]");
    CHECK(dt.colorSpectrum);
    REQUIRE(dt.transmittanceSpectrum);
    CHECK(dt.transmittanceSpectrum->values.at(550) == Approx(0.3));
    CHECK(materialOf(std::string("Texture \"t\" \"spectrum\" \"constant\" \"spectrum value\" ") +
                     kPairsText + "\nMaterial \"diffuse\" \"texture reflectance\" \"t\"")
              .colorSpectrum);
}

TEST_CASE("A coated layer's sampled albedo is kept, and the spectral BSDF takes it",
          "[pbrt][spectral]") {
    // coateddiffuse's (and coatedconductor's) medium `albedo`, pbrt-v4's SpectrumTexture of
    // reflectance-like values, like the reflectance above: its own spectrum beside its colour.
    auto r = loadWorld(std::string("Material \"coateddiffuse\" \"spectrum albedo\" ") +
                       kPairsText + " \"float thickness\" 0.1\nShape \"sphere\"\n");
    REQUIRE(r.warnings.empty());
    const int material = rootShapes(*r.scene)[0].shape->material;
    const Material& m = r.scene->materials[std::size_t(material)];
    REQUIRE(m.albedoSpectrum);
    CHECK(m.albedoSpectrum->values.at(480) == Approx(0.8));
    CHECK(m.albedo.value == pbrt::sampledReflectanceRgb(kPairs));
    CHECK_FALSE(materialOf("Material \"coateddiffuse\" \"rgb albedo\" [0.2 0.5 0.7]")
                    .albedoSpectrum);
    CHECK(materialOf("Material \"coatedconductor\" \"spectrum albedo\" " +
                     std::string(kPairsText))
              .albedoSpectrum);
    // At a lane's wavelengths the BSDF's albedo is the spectrum's, at the nearest nanometre.
    atLanes(*r.scene, material, [&](const kernels::BsdfParams& b, int i, std::size_t nm) {
        CHECK(b.albedo[i] == m.albedoSpectrum->values.values[nm]);
    });
}

TEST_CASE("Spectral mode: a sampled reflectance renders its own spectrum, RGB mode its colour",
          "[spectral-mode][spectral]") {
    auto sampled = loadWorld(squareUnder(std::string("Material \"diffuse\" \"spectrum reflectance\" ") + kPairsText));
    REQUIRE(sampled.warnings.empty());
    const Vec3 colour = pbrt::sampledReflectanceRgb(kPairs);
    char rgbText[160];
    std::snprintf(rgbText, sizeof rgbText, "Material \"diffuse\" \"rgb reflectance\" [%.9g %.9g %.9g]",
                  colour.x, colour.y, colour.z);
    auto rgb = loadWorld(squareUnder(rgbText));
    // The light: Planck's law over its photometric integral (pbrt-v4's), irradiance 1 head-on.
    const auto light = planck4000();
    const Vec3 expected = lambertianUnder(
        [](double nm) { return spectral::piecewiseLinear(kPairs, nm); }, light);
    // What the mode rendered before: the sRGB upsampled spectrum of the colour.
    const Vec3 before = lambertianUnder(upsampled(colour), light);
    const double tolerance = 1e-3 * maxComponent(expected);
    INFO("expected " << expected.x << " " << expected.y << " " << expected.z << ", before "
                     << before.x << " " << before.y << " " << before.z);
    CHECK(largestGap(before, expected) > 10 * tolerance);
    checkSpectralRender(*sampled.scene, expected, before, tolerance);
    // RGB mode takes the colour: the same image as the colour written as rgb, to the bit.
    CHECK(sameBits(render(*sampled.scene, 2, false), render(*rgb.scene, 2, false)));
}

namespace {

// A gold-like conductor: eta falls and k rises towards the red, so it reflects red most.
const std::vector<double> kEtaPairs = {400, 1.5, 500, 0.5, 600, 0.2, 700, 0.15};
const std::vector<double> kKPairs = {400, 1.8, 500, 2.5, 600, 3.5, 700, 4.2};
const char* kConductorText = "Material \"conductor\" \"spectrum eta\" [400 1.5 500 0.5 600 0.2 "
                             "700 0.15] \"spectrum k\" [400 1.8 500 2.5 600 3.5 700 4.2]";

} // namespace

TEST_CASE("A conductor's sampled eta and k are kept, and the spectral BSDF takes them",
          "[pbrt][spectral]") {
    // pbrt-v4's conductor takes eta and k as unbounded spectra: pairs (zero outside their
    // range), or an rgb upsampled as RGBUnboundedSpectrum in the file's colour space.
    auto r = loadWorld(std::string(kConductorText) + "\nShape \"sphere\"\n");
    REQUIRE(r.warnings.empty());
    const int material = rootShapes(*r.scene)[0].shape->material;
    const Material& m = r.scene->materials[std::size_t(material)];
    REQUIRE(m.etaSpectrum);
    REQUIRE(m.kSpectrum);
    CHECK(m.etaSpectrum->values.at(450) == Approx(1.0));
    CHECK(m.kSpectrum->values.at(650) == Approx(3.85));
    CHECK(m.kSpectrum->values.at(390) == 0.0f);
    // RGB mode's values are as before: each spectrum at 587.6 nm.
    CHECK(m.eta.value == Vec3(float(pbrt::sampledValueAt(kEtaPairs, 587.6))));
    CHECK(m.k.value == Vec3(float(pbrt::sampledValueAt(kKPairs, 587.6))));
    // sRGB rgb, a named metal and a reflectance keep none; rec2020's rgb keeps its own
    // unbounded spectrum (not clamped to 1).
    CHECK_FALSE(materialOf("Material \"conductor\" \"rgb eta\" [0.2 0.9 1.1] "
                           "\"rgb k\" [3.9 2.4 2.1]")
                    .etaSpectrum);
    CHECK_FALSE(materialOf("Material \"conductor\" \"spectrum eta\" \"metal-Au-eta\" "
                           "\"spectrum k\" \"metal-Au-k\"")
                    .kSpectrum);
    CHECK_FALSE(materialOf("Material \"conductor\" \"rgb reflectance\" [0.9 0.6 0.2]").etaSpectrum);
    Material rec = materialOf("ColorSpace \"rec2020\"\nMaterial \"conductor\" \"rgb eta\" "
                              "[0.2 0.9 1.1] \"rgb k\" [3.9 2.4 2.1]");
    REQUIRE(rec.kSpectrum);
    spectral::RgbUnboundedSpectrum k(spectral::colorSpace(spectral::ColorSpaceId::Rec2020), 3.9f,
                                     2.4f, 2.1f);
    for (float nm : {450.0f, 550.0f, 650.0f})
        CHECK(rec.kSpectrum->values.at(nm) == Approx(k(nm)).epsilon(1e-5));
    CHECK(rec.kSpectrum->values.at(650.0f) > 1.0f);
    // At a lane's wavelengths the BSDF's eta and k are the spectra's, at the nearest nanometre.
    atLanes(*r.scene, material, [&](const kernels::BsdfParams& b, int i, std::size_t nm) {
        CHECK(b.eta[i] == m.etaSpectrum->values.values[nm]);
        CHECK(b.k[i] == m.kSpectrum->values.values[nm]);
    });
}

TEST_CASE("Spectral mode: a conductor of sampled eta and k reflects its own Fresnel spectrum",
          "[spectral-mode][spectral]") {
    // A smooth conductor seen head-on (fov 4 degrees: within 2.9 degrees of normal incidence,
    // where a metal's reflectance is its F0 to 1e-5) under a 4000 K sky: each pixel is the
    // sky's spectrum times F0(lambda) = ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2).
    const std::string head = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 4\n"
                             "Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16\n"
                             "WorldBegin\nLightSource \"infinite\" \"blackbody L\" 4000\n";
    const std::string square =
        "\nShape \"bilinearmesh\" \"point3 P\" [-5 -5 0 5 -5 0 -5 5 0 5 5 0]\n";
    auto sampled = loadPbrt(head + kConductorText + square, "conductor.pbrt");
    REQUIRE(sampled.warnings.empty());
    const float eta587 = float(pbrt::sampledValueAt(kEtaPairs, 587.6));
    const float k587 = float(pbrt::sampledValueAt(kKPairs, 587.6));
    char rgbText[160];
    std::snprintf(rgbText, sizeof rgbText,
                  "Material \"conductor\" \"rgb eta\" [%.9g %.9g %.9g] \"rgb k\" [%.9g %.9g %.9g]",
                  eta587, eta587, eta587, k587, k587, k587);
    auto grey = loadPbrt(head + rgbText + square, "grey.pbrt");
    REQUIRE(grey.warnings.empty());
    const auto light = planck4000();
    auto f0 = [](double n, double k) {
        return ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
    };
    auto reflected = [&](const std::function<double(double)>& f) {
        spectral::Xyz xyz = spectral::toXyz(
            [&](double nm) { return f(nm) * light(nm); });
        spectral::ColorSpace::Rgb c = srgb().fromXyz({xyz.x, xyz.y, xyz.z});
        return Vec3(float(c.r), float(c.g), float(c.b));
    };
    // Outside the pairs' range eta = k = 0, as pbrt-v4's: F0 = 1.
    const Vec3 expected = reflected([&](double nm) {
        return f0(spectral::piecewiseLinear(kEtaPairs, nm), spectral::piecewiseLinear(kKPairs, nm));
    });
    // What the mode rendered before: eta and k at 587.6 nm at every wavelength, a grey F0.
    const double greyF0 = f0(eta587, k587);
    const Vec3 before = reflected([&](double) { return greyF0; });
    const double tolerance = 2e-3 * maxComponent(expected);
    INFO("expected " << expected.x << " " << expected.y << " " << expected.z << ", before "
                     << before.x << " " << before.y << " " << before.z);
    CHECK(std::abs(before.z - expected.z) > 10 * tolerance);
    checkSpectralRender(*sampled.scene, expected, before, tolerance);
    // RGB mode takes the values at 587.6 nm: the same image as those written as rgb, to the bit.
    CHECK(sameBits(render(*sampled.scene, 2, false), render(*grey.scene, 2, false)));
}

namespace {

// The texture the first shape's material reads as its reflectance.
const rayproc::Texture& reflectanceTexture(const LoadedPbrt& r) {
    const Material& m = r.scene->materials[std::size_t(rootShapes(*r.scene)[0].shape->material)];
    REQUIRE(m.colorTexture >= 0);
    return r.scene->textures[std::size_t(m.colorTexture)];
}

LoadedPbrt texturedSphere(const std::string& textures, const std::string& material = "diffuse",
                          const std::string& parameter = "reflectance") {
    auto r = loadWorld(textures + "Material \"" + material + "\" \"texture " + parameter +
                       "\" \"t\"\nShape \"sphere\"\n");
    REQUIRE(r.warnings.empty());
    return r;
}

// A second sampled reflectance, a ramp.
const std::vector<double> kRampPairs = {400, 0.9, 700, 0.2};

} // namespace

TEST_CASE("pbrt textures of spectra keep their operands' spectra", "[pbrt][spectral]") {
    const std::string pairs(kPairsText);
    // scale: "tex" given as pairs keeps them, unclamped and the same for both uses.
    auto scaled = texturedSphere("Texture \"t\" \"spectrum\" \"scale\" \"spectrum tex\" " + pairs +
                                 " \"float scale\" 0.5\n");
    const rayproc::Texture& s = reflectanceTexture(scaled);
    CHECK(s.spectral);
    REQUIRE(s.aSpectrum);
    CHECK(s.aSpectrum.unbounded->values.at(480) == Approx(0.8));
    CHECK(s.aSpectrum.albedo == s.aSpectrum.unbounded);
    // RGB mode reads the texture as a reflectance through a copy whose operand is the pairs'
    // colour as a reflectance; the texture itself keeps their unbounded value (at 587.6 nm).
    CHECK(s.aValue == pbrt::sampledReflectanceRgb(kPairs));
    CHECK(s.name == "t (as a reflectance)");
    REQUIRE(scaled.scene->textures.size() == 2);
    CHECK(scaled.scene->textures[0].aValue == Vec3(float(pbrt::sampledValueAt(kPairs, 587.6))));
    // sRGB rgb operands keep none; a rec2020 rgb keeps its albedo and unbounded spectra.
    CHECK_FALSE(reflectanceTexture(texturedSphere("Texture \"t\" \"spectrum\" \"mix\" "
                                                  "\"rgb tex1\" [0.2 0.5 0.7]\n"))
                    .spectral);
    auto rec = texturedSphere("ColorSpace \"rec2020\"\nTexture \"t\" \"spectrum\" \"checkerboard\" "
                              "\"rgb tex1\" [0.7 0.2 0.1]\n");
    const rayproc::Texture& c = reflectanceTexture(rec);
    CHECK(c.spectral);
    REQUIRE(c.aSpectrum);
    CHECK_FALSE(c.bSpectrum); // tex2's default, 0
    spectral::RgbAlbedoSpectrum albedo(spectral::colorSpace(spectral::ColorSpaceId::Rec2020), 0.7f,
                                       0.2f, 0.1f);
    CHECK(c.aSpectrum.albedo->values.at(550) == Approx(albedo(550)).epsilon(1e-5));
    CHECK(c.aSpectrum.albedo != c.aSpectrum.unbounded);
    // A texture of such a texture, a constant texture's spectrum and a bilerp's corner.
    auto nested = texturedSphere("Texture \"s\" \"spectrum\" \"scale\" \"spectrum tex\" " + pairs +
                                 "\nTexture \"t\" \"spectrum\" \"directionmix\" \"texture tex1\" "
                                 "\"s\"\n");
    CHECK(reflectanceTexture(nested).spectral);
    auto constant = texturedSphere("Texture \"k\" \"spectrum\" \"constant\" \"spectrum value\" " +
                                   pairs + "\nTexture \"t\" \"spectrum\" \"mix\" \"texture tex2\" "
                                   "\"k\"\n");
    CHECK(reflectanceTexture(constant).bSpectrum);
    auto corner = texturedSphere("Texture \"t\" \"spectrum\" \"bilerp\" \"spectrum v11\" " + pairs +
                                 "\n");
    CHECK(reflectanceTexture(corner).cornerSpectra[3]);
    CHECK_FALSE(reflectanceTexture(corner).cornerSpectra[0]);
    // A float texture has no spectra.
    auto floats = texturedSphere("Texture \"t\" \"float\" \"scale\" \"float tex\" 0.5\n",
                                 "conductor", "roughness");
    CHECK_FALSE(floats.scene->textures.back().spectral);
}

TEST_CASE("Spectral mode: a mix and a scale of sampled spectra render the combined spectrum",
          "[spectral-mode][spectral]") {
    // rho(l) = 0.75 * (0.5 * pairs(l)) + 0.25 * ramp(l): pbrt-v4 combines its spectrum textures
    // at the path's wavelengths. Before, the texture combined the operands' colours and the
    // spectral mode upsampled the result with sRGB's table.
    auto mixed = loadWorld(squareUnder(
        std::string("Texture \"half\" \"spectrum\" \"scale\" \"spectrum tex\" ") + kPairsText +
        " \"float scale\" 0.5\nTexture \"t\" \"spectrum\" \"mix\" \"texture tex1\" \"half\" "
        "\"spectrum tex2\" [400 0.9 700 0.2] \"float amount\" 0.25\n"
        "Material \"diffuse\" \"texture reflectance\" \"t\""));
    REQUIRE(mixed.warnings.empty());
    const auto light = planck4000();
    const Vec3 expected = lambertianUnder(
        [](double nm) {
            return 0.75 * 0.5 * spectral::piecewiseLinear(kPairs, nm) +
                   0.25 * spectral::piecewiseLinear(kRampPairs, nm);
        },
        light);
    // The colour RGB mode combines (the texture is the same everywhere), upsampled.
    const Vec3 colour = evalTexture(*mixed.scene, int(mixed.scene->textures.size()) - 1, {});
    const Vec3 before = lambertianUnder(upsampled(colour), light);
    const double tolerance = 1e-3 * maxComponent(expected);
    INFO("expected " << expected.x << " " << expected.y << " " << expected.z << ", before "
                     << before.x << " " << before.y << " " << before.z);
    CHECK(largestGap(before, expected) > 4 * tolerance);
    checkSpectralRender(*mixed.scene, expected, before, tolerance);
}

TEST_CASE("RGB mode: a texture of sampled spectra read as a reflectance combines their colours",
          "[pbrt][spectral]") {
    // scale(pairs, 0.5) as a diffuse reflectance renders as the pairs' colour times 0.5 written
    // as rgb (before, the pairs were read as an unbounded value: their 587.6 nm value, a grey).
    auto scaled = loadWorld(squareUnder(std::string("Texture \"t\" \"spectrum\" \"scale\" ") +
                                        "\"spectrum tex\" " + kPairsText + " \"float scale\" 0.5\n"
                                        "Material \"diffuse\" \"texture reflectance\" \"t\""));
    REQUIRE(scaled.warnings.empty());
    const Vec3 colour = pbrt::sampledReflectanceRgb(kPairs) * 0.5f;
    char rgbText[160];
    std::snprintf(rgbText, sizeof rgbText,
                  "Material \"diffuse\" \"rgb reflectance\" [%.9g %.9g %.9g]", colour.x,
                  colour.y, colour.z);
    auto rgb = loadWorld(squareUnder(rgbText));
    const Image a = render(*scaled.scene, 4, false), b = render(*rgb.scene, 4, false);
    for (int c = 0; c < 3; ++c) {
        INFO("channel " << c);
        CHECK(pixelStats(a, c).mean == Approx(pixelStats(b, c).mean).epsilon(1e-6));
    }
}

TEST_CASE("Spectral mode: a conductor's eta texture of pairs is read unclamped at the lane",
          "[pbrt][spectral]") {
    // eta = 1.0 x the pairs (above 1 in the blue): the unbounded spectrum, not clamped to 1.
    auto r = loadWorld("Texture \"e\" \"spectrum\" \"scale\" \"spectrum tex\" [400 1.5 500 0.5 "
                       "600 0.2 700 0.15] \"float scale\" 1\nMaterial \"conductor\" "
                       "\"texture eta\" \"e\" \"spectrum k\" [400 1.8 700 4.2]\n"
                       "Shape \"sphere\"\n");
    REQUIRE(r.warnings.empty());
    const int material = rootShapes(*r.scene)[0].shape->material;
    const rayproc::Texture& e = r.scene->textures.back();
    REQUIRE(e.aSpectrum);
    atLanes(*r.scene, material, [&](const kernels::BsdfParams& b, int i, std::size_t nm) {
        CHECK(b.eta[i] == e.aSpectrum.unbounded->values.values[nm]);
    });
}
