// The JSON scene keys of the coatedconductor material (docs/scene-format.md).
#include "scene_test_files.h"

#include "engine/material_bsdf.h"
#include "scene/metals.h"

using namespace rayproc;
using namespace rayproc::test;

TEST_CASE("coatedconductor in JSON: coat, conductor and slab keys", "[scene][coated-conductor]") {
    auto scene = loadScene(writeTestFile("coated-conductor.json", R"({
        "materials": {
            "lacquered-gold": {"type": "coatedconductor", "metal": "Au", "ior": 1.4,
                               "roughness": 0.01, "conductor_u_roughness": 0.04,
                               "conductor_v_roughness": 0.09, "thickness": 0.05,
                               "albedo": [0.5, 0.4, 0.3], "g": 0.2, "max_depth": 20,
                               "samples": 2, "remap_roughness": true},
            "candy": {"type": "coatedconductor", "reflectance": [0.9, 0.2, 0.1],
                      "conductor_roughness": 0.3},
            "plain": {"type": "coatedconductor"}},
        "nodes": [{"type": "sphere", "radius": 1, "material": "plain"}]})"));
    const auto& m = scene->materials;
    REQUIRE(m.size() == 3);
    Vec3 eta, k;
    REQUIRE(namedMetal("Au", eta, k));
    CHECK(m[0].type == MaterialType::CoatedConductor);
    CHECK(m[0].eta.value == eta);
    CHECK(m[0].k.value == k);
    CHECK(m[0].ior == 1.4f);
    CHECK(m[0].uRoughness.value == 0.01f);
    CHECK(m[0].conductorURoughness.value == 0.04f);
    CHECK(m[0].conductorVRoughness.value == 0.09f);
    CHECK(m[0].thickness.value == 0.05f);
    CHECK(m[0].albedo.value == Vec3(0.5f, 0.4f, 0.3f));
    CHECK(m[0].g == 0.2f);
    CHECK(m[0].maxDepth == 20);
    CHECK(m[0].nSamples == 2);
    kernels::BsdfParams b = bsdfOf(m[0]);
    CHECK(b.kind == kernels::BsdfKind::CoatedConductor);
    CHECK(b.alphaX == Approx(0.1f));
    CHECK(b.baseAlphaX == Approx(0.2f));
    CHECK(b.baseAlphaY == Approx(0.3f));
    CHECK(m[1].useReflectance);
    CHECK(m[1].color == Vec3(0.9f, 0.2f, 0.1f));
    CHECK(m[1].conductorURoughness.value == 0.3f);
    CHECK(m[1].conductorVRoughness.value == 0.3f);
    CHECK(m[1].uRoughness.value == 0.0f); // the coat stays smooth
    CHECK(materialClass(m, 1) == MaterialClass::Glossy);
    Vec3 cuEta, cuK;
    REQUIRE(namedMetal("Cu", cuEta, cuK));
    CHECK(length(m[2].eta.value - cuEta) < 1e-3f); // Material's copper default
    CHECK(length(m[2].k.value - cuK) < 1e-3f);
    CHECK(m[2].ior == 1.5f);
    CHECK(m[2].thickness.value == 0.01f);
    CHECK(materialClass(m, 2) == MaterialClass::Specular);

    checkLoadError("cc-key.json", R"({"materials": {"a": {"type": "coatedconductor",
        "color": [1, 0, 0]}}, "nodes": [{"type": "sphere", "radius": 1, "material": "a"}]})",
                   "/materials/a/color", "unknown key \"color\" in a coatedconductor material");
    checkLoadError("cc-both.json", R"({"materials": {"a": {"type": "coatedconductor", "metal": "Ag",
        "reflectance": [1, 1, 1]}}, "nodes": [{"type": "sphere", "radius": 1, "material": "a"}]})",
                   "/materials/a", "not several");
}
