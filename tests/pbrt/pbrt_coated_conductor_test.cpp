// pbrt-v4's coatedconductor as rayproc's CoatedConductor: every parameter of
// CoatedConductorMaterial::Create with its default, textures where pbrt-v4 takes them, the
// reflectance form, and no warning.
#include "pbrt_test_util.h"

#include "engine/material_bsdf.h"
#include "scene/metals.h"

#include <cmath>

using namespace rayproc;
using namespace rayproc::test;

namespace {

Material coatedOf(const std::string& world, std::vector<std::string>& warnings) {
    auto r = loadWorld(world + "\nShape \"sphere\"\n");
    warnings = r.warnings;
    auto shapes = rootShapes(*r.scene);
    REQUIRE(!shapes.empty());
    return r.scene->materials[std::size_t(shapes[0].shape->material)];
}

} // namespace

TEST_CASE("coatedconductor: pbrt-v4's defaults, no warning", "[pbrt][coated-conductor]") {
    std::vector<std::string> w;
    Material m = coatedOf("Material \"coatedconductor\"", w);
    CHECK(w.empty());
    CHECK(m.type == MaterialType::CoatedConductor);
    Vec3 cuEta, cuK;
    REQUIRE(namedMetal("Cu", cuEta, cuK));
    CHECK(m.eta.value == cuEta); // copper, as pbrt-v4
    CHECK(m.k.value == cuK);
    CHECK_FALSE(m.useReflectance);
    CHECK(m.ior == Approx(1.5f));
    CHECK(m.uRoughness.value == 0.0f);
    CHECK(m.conductorURoughness.value == 0.0f);
    CHECK(m.thickness.value == Approx(0.01f));
    CHECK(m.albedo.value == Vec3(0.0f));
    CHECK(m.g == 0.0f);
    CHECK(m.maxDepth == 10);
    CHECK(m.nSamples == 1);
    CHECK(m.remapRoughness);
    // Smooth coat, smooth conductor, nothing scattering: all delta.
    CHECK(materialClass({m}, 0) == MaterialClass::Specular);
    kernels::BsdfParams b = bsdfOf(m);
    CHECK(b.kind == kernels::BsdfKind::CoatedConductor);
    CHECK(kernels::isDeltaBsdf(b));
}

TEST_CASE("coatedconductor: every parameter", "[pbrt][coated-conductor]") {
    std::vector<std::string> w;
    Material m = coatedOf(
        "Material \"coatedconductor\" \"float interface.uroughness\" 0.04 "
        "\"float interface.vroughness\" 0.09 \"float interface.eta\" 1.33 "
        "\"spectrum conductor.eta\" \"metal-Au-eta\" \"spectrum conductor.k\" \"metal-Au-k\" "
        "\"float conductor.roughness\" 0.16 \"float thickness\" 0.2 \"rgb albedo\" [0.5 0.4 0.3] "
        "\"float g\" 0.25 \"integer maxdepth\" 20 \"integer nsamples\" 3",
        w);
    CHECK(w.empty());
    REQUIRE(m.type == MaterialType::CoatedConductor);
    Vec3 auEta, auK;
    REQUIRE(namedMetal("Au", auEta, auK));
    CHECK(m.eta.value == auEta);
    CHECK(m.k.value == auK);
    CHECK(m.ior == Approx(1.33f));
    CHECK(m.thickness.value == Approx(0.2f));
    CHECK(m.albedo.value == Vec3(0.5f, 0.4f, 0.3f));
    CHECK(m.g == Approx(0.25f));
    CHECK(m.maxDepth == 20);
    CHECK(m.nSamples == 3);
    CHECK(materialClass({m}, 0) == MaterialClass::Glossy);
    // pbrt-v4's remapping (alpha = sqrt(roughness)) on both layers.
    kernels::BsdfParams b = bsdfOf(m);
    CHECK(b.alphaX == Approx(0.2f));
    CHECK(b.alphaY == Approx(0.3f));
    CHECK(b.baseAlphaX == Approx(0.4f));
    CHECK(b.baseAlphaY == Approx(0.4f));
    CHECK(b.ior == Approx(1.33f));
    CHECK(b.eta == auEta); // relative to the coat inside the kernel, not here
    CHECK(b.thickness == Approx(0.2f));
    CHECK(b.nSamples == 3);

    Material raw = coatedOf("Material \"coatedconductor\" \"float interface.roughness\" 0.3 "
                            "\"float conductor.uroughness\" 0.1 \"float conductor.vroughness\" 0.2 "
                            "\"bool remaproughness\" false \"rgb conductor.eta\" [0.2 0.3 0.4] "
                            "\"rgb conductor.k\" [3 4 5]",
                            w);
    CHECK(w.empty());
    kernels::BsdfParams rb = bsdfOf(raw);
    CHECK(rb.alphaX == Approx(0.3f));
    CHECK(rb.alphaY == Approx(0.3f));
    CHECK(rb.baseAlphaX == Approx(0.1f));
    CHECK(rb.baseAlphaY == Approx(0.2f));
    CHECK(rb.eta == Vec3(0.2f, 0.3f, 0.4f));
    CHECK(rb.k == Vec3(3, 4, 5));

    // interface.eta 0 is index-matched in pbrt-v4 (ieta == 0 -> 1).
    CHECK(coatedOf("Material \"coatedconductor\" \"float interface.eta\" 0", w).ior == 1.0f);
}

TEST_CASE("coatedconductor: reflectance, textures and errors", "[pbrt][coated-conductor]") {
    std::vector<std::string> w;
    Material r = coatedOf("Material \"coatedconductor\" \"rgb reflectance\" [0.9 0.5 0.2]", w);
    CHECK(w.empty());
    CHECK(r.useReflectance);
    CHECK(r.color == Vec3(0.9f, 0.5f, 0.2f));
    kernels::BsdfParams b = bsdfOf(r);
    CHECK(b.eta == Vec3(1.0f));
    CHECK(b.k.x == Approx(2 * std::sqrt(0.9f) / std::sqrt(0.1f)));

    // Textured conductor roughness, conductor index and thickness, as pbrt-v4 takes them.
    Material t = coatedOf(
        "Texture \"rough\" \"float\" \"checkerboard\" \"float tex1\" 0.1 \"float tex2\" 0.4\n"
        "Texture \"eta\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [0.2 0.3 0.4] "
        "\"rgb tex2\" [1 1 1]\n"
        "Texture \"thick\" \"float\" \"checkerboard\" \"float tex1\" 0.01 \"float tex2\" 0.3\n"
        "Material \"coatedconductor\" \"texture conductor.roughness\" \"rough\" "
        "\"texture conductor.eta\" \"eta\" \"texture thickness\" \"thick\"",
        w);
    CHECK(w.empty());
    CHECK(t.conductorURoughness.textured());
    CHECK(t.conductorVRoughness.textured());
    CHECK(t.eta.textured());
    CHECK(t.thickness.textured());
    CHECK(materialClass({t}, 0) == MaterialClass::Glossy); // textured roughness may be rough

    std::string e = pbrtErrorOf(std::string(kPbrtHeader) +
                                "Material \"coatedconductor\" \"rgb reflectance\" [0.5 0.5 0.5] "
                                "\"rgb conductor.eta\" [1 1 1]\nShape \"sphere\"\n");
    CHECK_THAT(e, Catch::Contains("not both"));
    e = pbrtErrorOf(std::string(kPbrtHeader) +
                    "Material \"coatedconductor\" \"float g\" 1.5\nShape \"sphere\"\n");
    CHECK_THAT(e, Catch::Contains("\"g\""));
}
