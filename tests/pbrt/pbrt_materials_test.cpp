// pbrt materials, constant textures, spectra (blackbody, constant, sampled) and lights as
// rayproc's materials and lights.
#include "pbrt_test_util.h"

#include "engine/material_bsdf.h"
#include "image/image.h"
#include "scene/metals.h"
#include "scene/pbrt/pbrt_spectrum.h"
#include "spectral/color_space.h"

#include <cmath>

using namespace rayproc;
using namespace rayproc::pbrt;
using namespace rayproc::test;

namespace {

bool near(const Vec3& a, const Vec3& b, float eps = 1e-4f) {
    return length(a - b) < eps;
}

// The material of the first shape after `world` declares it.
Material materialOf(const std::string& world, std::vector<std::string>* warnings = nullptr) {
    auto r = loadWorld(world + "\nShape \"sphere\"\n");
    if (warnings) *warnings = r.warnings;
    auto shapes = rootShapes(*r.scene);
    REQUIRE(!shapes.empty());
    return r.scene->materials[std::size_t(shapes[0].shape->material)];
}

bool anyContains(const std::vector<std::string>& v, const std::string& s) {
    for (const auto& x : v)
        if (x.find(s) != std::string::npos) return true;
    return false;
}

} // namespace

TEST_CASE("diffuse, the default material, and named materials", "[pbrt]") {
    Material d = materialOf("Material \"diffuse\" \"rgb reflectance\" [0.1 0.2 0.3]");
    CHECK(d.type == MaterialType::Diffuse);
    CHECK(d.color == Vec3(0.1f, 0.2f, 0.3f));
    Material def = materialOf("");
    CHECK(def.type == MaterialType::Diffuse);
    CHECK(def.color == Vec3(0.5f));
    // One number is no spectrum in pbrt-v4 (an odd count of wavelength, value pairs): an
    // error that names the file and line, on a material, a light and a constant texture alike.
    CHECK_THAT(pbrtErrorOf(std::string(kPbrtHeader) +
                           "Material \"diffuse\" \"spectrum reflectance\" 0.25\n"),
               Catch::Contains("bad.pbrt:5") && Catch::Contains("\"spectrum reflectance\"") &&
                   Catch::Contains("got 1 value"));
    CHECK_THAT(pbrtErrorOf(std::string(kPbrtHeader) + "\nLightSource \"point\" \"spectrum I\" [2]\n"),
               Catch::Contains("bad.pbrt:6") && Catch::Contains("\"spectrum I\""));
    CHECK_THAT(pbrtErrorOf(std::string(kPbrtHeader) +
                           "Texture \"t\" \"spectrum\" \"constant\" \"spectrum value\" [0.5]\n"
                           "Material \"diffuse\" \"texture reflectance\" \"t\"\n"),
               Catch::Contains("bad.pbrt:5") && Catch::Contains("\"spectrum value\""));
    CHECK_THAT(pbrtErrorOf(std::string(kPbrtHeader) +
                           "Material \"dielectric\" \"spectrum eta\" [1.5]\n"),
               Catch::Contains("bad.pbrt:5"));
    CHECK_THAT(pbrtErrorOf(std::string(kPbrtHeader) +
                           "Material \"diffuse\" \"spectrum reflectance\" [400 0.5 500]\n"),
               Catch::Contains("bad.pbrt:5") && Catch::Contains("odd count"));

    // Used before it is defined: resolved after parsing.
    auto r = loadWorld("NamedMaterial \"late\"\nShape \"sphere\"\n"
                       "MakeNamedMaterial \"late\" \"string type\" \"diffuse\" "
                       "\"rgb reflectance\" [0 1 0]\n");
    const Shape& s = *rootShapes(*r.scene)[0].shape;
    CHECK(r.scene->materials[std::size_t(s.material)].name == "late");
    CHECK(r.scene->materials[std::size_t(s.material)].color == Vec3(0, 1, 0));
}

TEST_CASE("conductor: complex index (rgb, named metal, copper default) or reflectance, pbrt's roughness", "[pbrt]") {
    Material m = materialOf("Material \"conductor\" \"rgb reflectance\" [0.9 0.8 0.7]");
    CHECK(m.type == MaterialType::Conductor);
    CHECK(m.useReflectance);
    CHECK(m.color == Vec3(0.9f, 0.8f, 0.7f));
    CHECK(materialClass({m}, 0) == MaterialClass::Specular); // roughness 0: a delta lobe

    Material gold = materialOf("Material \"conductor\" \"spectrum eta\" \"metal-Au-eta\" "
                               "\"spectrum k\" \"metal-Au-k\"");
    CHECK_FALSE(gold.useReflectance);
    Vec3 auEta, auK;
    REQUIRE(namedMetal("Au", auEta, auK));
    CHECK(gold.eta.value == auEta);
    CHECK(gold.k.value == auK);
    CHECK(gold.eta.value.z > gold.eta.value.x); // gold: blue has the higher index

    Vec3 cuEta, cuK;
    REQUIRE(namedMetal("Cu", cuEta, cuK));
    Material defaults = materialOf("Material \"conductor\"");
    CHECK(defaults.eta.value == cuEta); // pbrt-v4's default metal is copper
    CHECK(defaults.k.value == cuK);
    Material rgbEta = materialOf("Material \"conductor\" \"rgb eta\" [0.2 0.3 0.4] "
                                 "\"rgb k\" [3 4 5]");
    CHECK(rgbEta.eta.value == Vec3(0.2f, 0.3f, 0.4f));
    CHECK(rgbEta.k.value == Vec3(3, 4, 5));

    // pbrt-v4: alpha = sqrt(roughness) when remapping (the default), else roughness.
    Material rough = materialOf("Material \"conductor\" \"float roughness\" 0.3");
    CHECK(rough.uRoughness.value == Approx(0.3f));
    CHECK(rough.remapRoughness);
    CHECK(bsdfOf(rough).alphaX == Approx(std::sqrt(0.3f)));
    CHECK(materialClass({rough}, 0) == MaterialClass::Glossy);
    Material raw = materialOf("Material \"conductor\" \"float roughness\" 0.3 "
                              "\"bool remaproughness\" false");
    CHECK(bsdfOf(raw).alphaX == Approx(0.3f));
    Material aniso = materialOf("Material \"conductor\" \"float uroughness\" 0.1 "
                                "\"float vroughness\" 0.4 \"bool remaproughness\" false");
    CHECK(bsdfOf(aniso).alphaX == Approx(0.1f));
    CHECK(bsdfOf(aniso).alphaY == Approx(0.4f));
    // Below pbrt's 1e-3 the lobe is a delta: roughness 1e-7 remapped is alpha 3e-4.
    CHECK(materialClass({materialOf("Material \"conductor\" \"float roughness\" 1e-7")}, 0) ==
          MaterialClass::Specular);
    // pbrt-v4's reflectance parameterisation: eta 1, k = 2 sqrt(r) / sqrt(1 - r).
    kernels::BsdfParams rb = bsdfOf(m);
    CHECK(rb.eta == Vec3(1.0f));
    CHECK(rb.k.x == Approx(2 * std::sqrt(0.9f) / std::sqrt(0.1f)));
}

TEST_CASE("dielectric, thindielectric, diffusetransmission, coateddiffuse, mix, interface and unsupported materials", "[pbrt]") {
    Material glass = materialOf("Material \"dielectric\" \"float eta\" 1.33");
    CHECK(glass.type == MaterialType::Dielectric);
    CHECK(glass.ior == Approx(1.33f));
    CHECK(glass.color == Vec3(1.0f));
    CHECK(materialOf("Material \"dielectric\"").ior == Approx(1.5f));
    CHECK(materialOf("Material \"dielectric\" \"spectrum eta\" \"glass-BK7\"").ior ==
          Approx(1.5168f));
    std::vector<std::string> w;
    Material roughGlass = materialOf("Material \"dielectric\" \"float roughness\" 0.2", &w);
    CHECK(w.empty());
    CHECK(materialClass({roughGlass}, 0) == MaterialClass::Glossy);
    CHECK(materialClass({glass}, 0) == MaterialClass::Specular);

    Material thin = materialOf("Material \"thindielectric\" \"float eta\" 1.4");
    CHECK(thin.type == MaterialType::ThinDielectric);
    CHECK(thin.ior == Approx(1.4f));

    Material dt = materialOf("Material \"diffusetransmission\" \"rgb transmittance\" [0.1 0.2 0.3] "
                             "\"float scale\" 2");
    CHECK(dt.type == MaterialType::DiffuseTransmission);
    CHECK(dt.color == Vec3(0.25f)); // pbrt-v4's default reflectance
    CHECK(bsdfOf(dt).transmittance == Vec3(0.2f, 0.4f, 0.6f));
    CHECK(bsdfOf(dt).color == Vec3(0.5f));

    Material coated = materialOf("Material \"coateddiffuse\" \"rgb reflectance\" [0.2 0.4 0.6] "
                                 "\"float roughness\" 0.1 \"float thickness\" 0.05 \"integer nsamples\" 4",
                                 &w);
    CHECK(w.empty());
    CHECK(coated.type == MaterialType::CoatedDiffuse);
    CHECK(coated.color == Vec3(0.2f, 0.4f, 0.6f));
    CHECK(coated.thickness.value == Approx(0.05f));
    CHECK(coated.nSamples == 4);
    CHECK(coated.maxDepth == 10);
    CHECK(coated.ior == Approx(1.5f));

    auto mixed = loadWorld("MakeNamedMaterial \"both\" \"string type\" \"mix\" "
                           "\"string materials\" [\"red\" \"gold\"] \"float amount\" 0.25\n"
                           "NamedMaterial \"both\"\nShape \"sphere\"\n"
                           "MakeNamedMaterial \"red\" \"string type\" \"diffuse\" \"rgb reflectance\" [1 0 0]\n"
                           "MakeNamedMaterial \"gold\" \"string type\" \"conductor\"\n");
    const Material& mix = mixed.scene->materials[std::size_t(rootShapes(*mixed.scene)[0].shape->material)];
    CHECK(mix.type == MaterialType::Mix);
    CHECK(mix.amount.value == Approx(0.25f));
    CHECK(mixed.scene->materials[std::size_t(mix.mix[0])].name == "red");
    CHECK(mixed.scene->materials[std::size_t(mix.mix[1])].name == "gold");
    std::string e = pbrtErrorOf(std::string(kPbrtHeader) + "MakeNamedMaterial \"a\" \"string type\" \"mix\" "
                              "\"string materials\" [\"a\" \"b\"]\n"
                              "MakeNamedMaterial \"b\" \"string type\" \"diffuse\"\n"
                              "NamedMaterial \"a\"\nShape \"sphere\"\n");
    CHECK_THAT(e, Catch::Contains("contains itself"));
    e = pbrtErrorOf(std::string(kPbrtHeader) + "Material \"mix\" \"string materials\" [\"x\" \"y\"]\nShape \"sphere\"\n");
    CHECK_THAT(e, Catch::Contains("\"x\", which was never defined"));

    Material hair = materialOf("Material \"hair\" \"float eumelanin\" 1.3", &w);
    CHECK(hair.type == MaterialType::Diffuse);
    CHECK(hair.color == Vec3(0.5f));
    CHECK(anyContains(w, "Material \"hair\" is not supported; using diffuse 0.5"));
    CHECK_FALSE(anyContains(w, "eumelanin")); // the material is reported, not its parameters

    auto boundary = loadWorld("Material \"interface\"\nShape \"sphere\"\n"
                              "Material \"diffuse\"\nShape \"sphere\"\n");
    CHECK(rootShapes(*boundary.scene).size() == 1);
    CHECK(boundary.warned("material \"interface\""));
}

TEST_CASE("Constant textures stand for values, other classes fall back with a warning", "[pbrt]") {
    Material m =
        materialOf("Texture \"red\" \"spectrum\" \"constant\" \"rgb value\" [0.8 0.1 0.1]\n"
                   "Texture \"r\" \"float\" \"constant\" \"float value\" 0.3\n"
                   "Material \"diffuse\" \"texture reflectance\" \"red\"");
    CHECK(m.color == Vec3(0.8f, 0.1f, 0.1f));
    Material g = materialOf("Texture \"r\" \"float\" \"constant\" \"float value\" 0.3\n"
                            "Material \"conductor\" \"texture roughness\" \"r\"");
    CHECK(g.type == MaterialType::Conductor);
    CHECK(bsdfOf(g).alphaX == Approx(std::sqrt(0.3f))); // remapped, as pbrt-v4 does
    std::vector<std::string> w;
    Material img = materialOf("Texture \"wood\" \"spectrum\" \"imagemap\" \"string filename\" "
                              "\"wood.png\"\nMaterial \"diffuse\" \"texture reflectance\" \"wood\"",
                              &w);
    CHECK(img.color == Vec3(0.5f)); // the file is missing: the parameter keeps its default
    CHECK(img.colorTexture == -1);
    CHECK(anyContains(w, "cannot read the texture"));
    CHECK(anyContains(w, "parameters that use texture \"wood\" keep their default values"));
    // Where pbrt-v4 takes a value, not a texture (a dielectric's eta), a constant texture gives
    // its value and a varying one warns and keeps the default.
    w.clear();
    Material eta = materialOf("Texture \"e\" \"float\" \"constant\" \"float value\" 1.7\n"
                              "Material \"dielectric\" \"texture eta\" \"e\"", &w);
    CHECK(eta.ior == Approx(1.7f));
    CHECK(w.empty());
    Material varying = materialOf("Texture \"e\" \"float\" \"checkerboard\" \"float tex1\" 1.3 "
                                  "\"float tex2\" 1.7\nMaterial \"dielectric\" \"texture eta\" "
                                  "\"e\"",
                                  &w);
    CHECK(varying.ior == Approx(1.5f));
    CHECK(anyContains(w, "parameter \"texture eta\": a texture that varies over the surface is "
                         "not supported here; using the default 1.5"));
    std::string e = pbrtErrorOf(std::string(kPbrtHeader) +
                                "Material \"diffuse\" \"texture reflectance\" \"nope\"\n");
    CHECK_THAT(e, Catch::Contains(":5:20: no spectrum texture named \"nope\""));
}

TEST_CASE("Blackbody colours: Planck's law through the CIE 1931 observer, luminance 1", "[pbrt]") {
    Vec3 white = blackbodyRgb(6500);
    CHECK(luminance(white) == Approx(1.0f).epsilon(1e-4));
    for (int c = 0; c < 3; ++c) CHECK(white[c] == Approx(1.0f).margin(0.1)); // roughly white
    Vec3 warm = blackbodyRgb(2700);
    CHECK(warm.x > warm.y);
    CHECK(warm.y > warm.z);
    Vec3 cool = blackbodyRgb(12000);
    CHECK(cool.z > cool.x);
    // The CIE tables' values (CIE 15:2004), and between their 5 nm samples linear.
    double x, y, z;
    cieColorMatch(555, x, y, z);
    CHECK(y == 1.0);
    cieColorMatch(600, x, y, z);
    CHECK(x == Approx(1.0622));
    cieColorMatch(602.5, x, y, z);
    CHECK(x == Approx((1.0622 + 1.0456) / 2));
    // A 2856 K blackbody is CIE illuminant A: chromaticity 0.44757, 0.40745 (CIE 15:2004).
    Vec3 a = blackbodyRgb(2856), tabulatedA;
    REQUIRE(namedIlluminantRgb("stdillum-A", tabulatedA));
    CHECK(near(a, tabulatedA, 3e-3f));
    // Flat reflectance spectra over the whole range are grey; flat emission is white with
    // luminance 1.
    CHECK(near(sampledReflectanceRgb({360, 0.5, 830, 0.5}), Vec3(0.5f), 1e-4f));
    CHECK(luminance(sampledEmissionRgb({360, 2, 830, 2})) == Approx(1.0f).epsilon(1e-4));
    // Pairs are zero outside their range (pbrt-v4): 400-700 nm loses a little red and blue.
    Vec3 cut = sampledReflectanceRgb({400, 0.5, 700, 0.5});
    CHECK(cut.x < 0.4995f);
    CHECK(cut.z < 0.4995f);
    CHECK(cut.x > 0.49f);
    // pbrt-v4's named illuminants: D65 is sRGB's white; B is not one of pbrt-v4's names.
    Vec3 d65;
    REQUIRE(namedIlluminantRgb("stdillum-D65", d65));
    CHECK(near(d65, Vec3(1.0f), 1e-5f));
    Vec3 f11;
    CHECK(namedIlluminantRgb("stdillum-F11", f11));
    CHECK(luminance(f11) == Approx(1.0f).epsilon(1e-4));
    CHECK_FALSE(namedIlluminantRgb("stdillum-B", f11));
    CHECK_FALSE(namedIlluminantRgb("D65", f11));
}

TEST_CASE("Lights: point, spot, distant, infinite, area, scale, power and blackbody", "[pbrt]") {
    auto r = loadWorld(
        "LightSource \"point\" \"rgb I\" [1 2 3] \"point3 from\" [1 2 3] \"float scale\" 2\n"
        "LightSource \"point\" \"blackbody I\" 3000 \"float power\" 100\n"
        "Translate 0 5 0\n"
        "LightSource \"spot\" \"point3 from\" [0 0 0] \"point3 to\" [0 -1 0] "
        "\"float coneangle\" 40 \"float conedeltaangle\" 10\n"
        "LightSource \"distant\" \"point3 from\" [0 0 0] \"point3 to\" [1 -1 0] "
        "\"rgb L\" [3 3 3] \"float scale\" 0.5\n"
        "LightSource \"infinite\" \"rgb L\" [0.1 0.2 0.3]\n"
        "LightSource \"infinite\" \"rgb L\" [0.1 0.1 0.1]\n"
        "LightSource \"goniometric\"\n"
        "Shape \"sphere\"\n");
    const auto& L = r.scene->lights;
    REQUIRE(L.size() == 6);
    CHECK(L[0].type == LightType::Point);
    CHECK(L[0].intensity == Vec3(2, 4, 6));
    CHECK(L[0].position == Vec3(1, 2, 3));
    CHECK(luminance(L[1].intensity) == Approx(100 / (4 * kPi)).epsilon(1e-4));
    CHECK(L[2].type == LightType::Spot);
    CHECK(L[2].position == Vec3(0, 5, 0));
    CHECK(near(L[2].direction, {0, -1, 0}));
    CHECK(L[2].coneAngle == Approx(30.0f)); // full intensity inside coneangle - delta
    CHECK(L[2].falloffAngle == Approx(10.0f));
    CHECK(L[3].type == LightType::Directional);
    CHECK(near(L[3].direction, normalize(Vec3(1, -1, 0))));
    CHECK(L[3].intensity == Vec3(1.5f));
    CHECK(L[4].type == LightType::Environment); // two skies add up
    CHECK(near(L[4].intensity, {0.2f, 0.3f, 0.4f}));
    CHECK(L[5].type == LightType::Goniometric); // image skies and goniometric: tests/lighting
    CHECK(r.warned("goniometric light without \"filename\""));
    CHECK(pbrtErrorOf(std::string(kPbrtHeader) +
                      "LightSource \"infinite\" \"string filename\" \"sky.exr\"\n")
              .find("sky.exr") != std::string::npos);

    auto area = loadWorld("AttributeBegin\n"
                          "AreaLightSource \"diffuse\" \"rgb L\" [17 12 4] \"bool twosided\" true\n"
                          "Shape \"sphere\"\nAttributeEnd\n"
                          "AreaLightSource \"diffuse\" \"blackbody L\" 6500 \"float scale\" 5\n"
                          "Shape \"disk\"\n"
                          "AreaLightSource \"projector\"\nShape \"disk\"\n");
    auto shapes = rootShapes(*area.scene);
    REQUIRE(shapes.size() == 3);
    CHECK(shapes[0].shape->emission == Vec3(17, 12, 4));
    CHECK(shapes[0].shape->twoSided);
    CHECK(luminance(shapes[1].shape->emission) == Approx(5.0f).epsilon(1e-4));
    CHECK_FALSE(shapes[1].shape->twoSided);
    CHECK_FALSE(shapes[2].shape->isEmissive());
    CHECK(area.warned("AreaLightSource \"projector\" is not supported"));
}

TEST_CASE("Media: absorbing media fill their shapes, others warn where used", "[pbrt]") {
    auto unused = loadWorld("MakeNamedMedium \"green\" \"string type\" \"homogeneous\" "
                            "\"rgb sigma_a\" [0.5 0.2 0.4]\n"
                            "AttributeBegin\nMediumInterface \"green\" \"\"\nAttributeEnd\n"
                            "Shape \"sphere\"\n");
    CHECK(unused.warnings.empty());
    CHECK(rootShapes(*unused.scene)[0].shape->interiorAbsorption == Vec3(0.0f));
    auto green = loadWorld("MakeNamedMedium \"green\" \"string type\" \"homogeneous\" "
                           "\"rgb sigma_a\" [0.5 0.2 0.4] \"rgb sigma_s\" [0 0 0] \"float scale\" 2\n"
                           "AttributeBegin\nMediumInterface \"green\" \"\"\nShape \"sphere\"\nAttributeEnd\n"
                           "Shape \"sphere\"\n");
    CHECK(green.warnings.empty());
    REQUIRE(rootShapes(*green.scene).size() == 2);
    CHECK(rootShapes(*green.scene)[0].shape->interiorAbsorption == Vec3(1.0f, 0.4f, 0.8f));
    CHECK(rootShapes(*green.scene)[1].shape->interiorAbsorption == Vec3(0.0f));
    // pbrt-v4's default homogeneous medium scatters: not rendered, said so.
    auto used = loadWorld("MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\n"
                          "MediumInterface \"fog\" \"\"\nShape \"sphere\"\n");
    CHECK(used.warned("media that scatter or emit are not supported: medium \"fog\""));
    std::string e = pbrtErrorOf(std::string(kPbrtHeader) + "MediumInterface \"nope\"\n"
                                                           "Shape \"sphere\"\n");
    CHECK_THAT(e, Catch::Contains(":5:1: MediumInterface names \"nope\", which was never defined"));
}

TEST_CASE("displacement textures and normal maps reach the material (bump mapping)", "[pbrt]") {
    // Image files for a float displacement texture and a normal map, written beside the scene.
    Image ramp(4, 1), flat(2, 2);
    for (int x = 0; x < 4; ++x) ramp.at(x, 0)[0] = ramp.at(x, 0)[1] = ramp.at(x, 0)[2] = 0.1f * x;
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x) {
            float* c = flat.at(x, y);
            c[0] = c[1] = 0.5f;
            c[2] = 1.0f;
        }
    writeImage((pbrtTestDir() / "bump-ramp.pfm").string(), ramp);
    writeImage((pbrtTestDir() / "bump-flat-normals.pfm").string(), flat);
    std::vector<std::string> warnings;
    Material bumped = materialOf("Texture \"ramp\" \"float\" \"imagemap\" \"string filename\" "
                                 "\"bump-ramp.pfm\"\n"
                                 "Material \"diffuse\" \"texture displacement\" \"ramp\"",
                                 &warnings);
    CHECK(warnings.empty());
    CHECK(bumped.displacement >= 0);
    CHECK(bumped.normalMap < 0);
    Material mapped = materialOf(
        "Material \"conductor\" \"string normalmap\" \"bump-flat-normals.pfm\"", &warnings);
    CHECK(warnings.empty());
    CHECK(mapped.normalMap >= 0);
    // A constant displacement changes no normal: nothing to evaluate.
    CHECK(materialOf("Material \"diffuse\" \"float displacement\" 0.2", &warnings).displacement <
          0);
    CHECK(warnings.empty());
    // A missing normal map warns and keeps the material's own normals.
    Material missing =
        materialOf("Material \"diffuse\" \"string normalmap\" \"no-such-normals.png\"", &warnings);
    CHECK(missing.normalMap < 0);
    CHECK(anyContains(warnings, "no-such-normals.png"));
    CHECK(anyContains(warnings, "keeps its own normals"));
}

TEST_CASE("ColorSpace: rgb values in rec2020, dci-p3 and aces2065-1 become sRGB, scoped by attributes",
          "[pbrt]") {
    // White and grey reflectances are flat spectra in every colour space: the same sRGB.
    Material white = materialOf("ColorSpace \"aces2065-1\"\n"
                                "Material \"diffuse\" \"rgb reflectance\" [1 1 1]");
    CHECK(near(white.color, Vec3(1.0f), 1e-3f));
    Material grey = materialOf("ColorSpace \"rec2020\"\n"
                               "Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]");
    CHECK(near(grey.color, Vec3(0.5f), 1e-3f));
    // sRGB's red written in Rec2020 (its XYZ through Rec2020's matrix) comes back as red.
    const spectral::ColorSpace& rec2020 = spectral::colorSpace(spectral::ColorSpaceId::Rec2020);
    const spectral::ColorSpace& srgb = spectral::colorSpace(spectral::ColorSpaceId::Srgb);
    spectral::ColorSpace::Rgb v = rec2020.fromXyz(srgb.toXyz(0.8, 0.2, 0.1));
    char text[200];
    std::snprintf(text, sizeof text,
                  "ColorSpace \"rec2020\"\nMaterial \"diffuse\" \"rgb reflectance\" [%.9g %.9g %.9g]",
                  v.r, v.g, v.b);
    Material red = materialOf(text);
    CHECK(near(red.color, Vec3(0.8f, 0.2f, 0.1f), 2e-3f));
    // The same numbers read as sRGB differ from it (the conversion is not the identity).
    CHECK_FALSE(near(Vec3(float(v.r), float(v.g), float(v.b)), Vec3(0.8f, 0.2f, 0.1f), 2e-2f));

    // An illuminant's white is the colour space's illuminant: ACES's D60 is warmer than D65,
    // at luminance 1; pbrt-v4's "illum-acesD60" is the same spectrum.
    auto lightColor = [](const std::string& world) {
        auto r = loadWorld(world + "\nShape \"sphere\"\n");
        REQUIRE(!r.scene->lights.empty());
        return r.scene->lights[0].intensity;
    };
    Vec3 d60 = lightColor("ColorSpace \"aces2065-1\"\nLightSource \"point\" \"rgb I\" [1 1 1]");
    CHECK(d60.x > d60.y);
    CHECK(d60.y > d60.z);
    CHECK(luminance(d60) == Approx(1.0f).epsilon(2e-3));
    Vec3 named = lightColor("LightSource \"point\" \"spectrum I\" \"illum-acesD60\"");
    CHECK(near(named, d60, 2e-3f));
    // sRGB's own white light stays (1, 1, 1) exactly.
    CHECK(lightColor("LightSource \"point\" \"rgb I\" [1 1 1]") == Vec3(1.0f));

    // AttributeEnd restores the colour space of the enclosing state.
    Material after = materialOf("AttributeBegin\nColorSpace \"rec2020\"\nAttributeEnd\n"
                                "Material \"diffuse\" \"rgb reflectance\" [0.8 0.2 0.1]");
    CHECK(after.color == Vec3(0.8f, 0.2f, 0.1f));
    // Constant textures keep the colour space they were defined in.
    Material tex = materialOf("ColorSpace \"rec2020\"\n"
                              "Texture \"t\" \"spectrum\" \"constant\" \"rgb value\" [0.5 0.5 0.5]\n"
                              "ColorSpace \"srgb\"\n"
                              "Material \"diffuse\" \"texture reflectance\" \"t\"");
    CHECK(near(tex.color, Vec3(0.5f), 1e-3f));

    // An unknown name is an error at its line; a film under another space warns.
    std::string error = pbrtErrorOf(std::string(kPbrtHeader) + "ColorSpace \"adobe-rgb\"\n");
    CHECK_THAT(error, Catch::Contains("bad.pbrt:5:"));
    CHECK_THAT(error, Catch::Contains("unknown colour space \"adobe-rgb\""));
    auto r = loadPbrt("ColorSpace \"aces2065-1\"\n" + std::string(kPbrtHeader) + "Shape \"sphere\"\n");
    CHECK(anyContains(r.warnings, "film's colour space \"aces2065-1\" is not applied"));
}
