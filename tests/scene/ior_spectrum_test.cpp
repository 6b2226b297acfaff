// scene/ior_spectrum.h: a dielectric's index over wavelength. The named glasses' Sellmeier
// coefficients checked against two independent catalogue figures per glass (Schott): the index
// n_d at the helium d line (587.56 nm), which the importer's RGB mode takes, and the Abbe number
// v_d = (n_d - 1) / (n_F - n_C), F = 486.13 nm, C = 656.27 nm; sampled pairs; what the importer
// keeps for the spectral mode.
#include "pbrt/pbrt_test_util.h"
#include "scene/ior_spectrum.h"
#include "test_util.h"

#include <catch2/catch.hpp>

using namespace rayproc;
using namespace rayproc::test;

TEST_CASE("Named glasses' Sellmeier formulas give their catalogue n_d and Abbe number",
          "[scene][spectral][dispersion]") {
    // Schott's catalogue Abbe numbers (N-BK7, N-BAF10, N-FK51A, N-LASF9, SF5, SF10, SF11).
    const std::pair<const char*, double> kAbbe[] = {
        {"glass-BK7", 64.17},   {"glass-BAF10", 47.11}, {"glass-FK51A", 84.47},
        {"glass-LASF9", 32.17}, {"glass-F5", 32.21},    {"glass-F10", 28.41},
        {"glass-F11", 25.68}};
    for (const auto& [name, abbe] : kAbbe) {
        IorSpectrumRef s = namedGlassDispersion(name);
        REQUIRE(s);
        double catalogueNd = 0;
        REQUIRE(namedGlassIndex(name, catalogueNd));
        const double nd = s->at(587.56f), nF = s->at(486.13f), nC = s->at(656.27f);
        const double vd = (nd - 1) / (nF - nC);
        INFO(name << ": n_d " << nd << " (catalogue " << catalogueNd << "), v_d " << vd
                  << " (catalogue " << abbe << ")");
        CHECK(std::abs(nd - catalogueNd) < 2e-4);
        CHECK(std::abs(vd - abbe) < 0.5);
        // Normal dispersion: the index falls with wavelength over the visible range.
        CHECK(s->at(400) > s->at(550));
        CHECK(s->at(550) > s->at(700));
    }
    CHECK_FALSE(namedGlassDispersion("glass-unknown"));
    CHECK_FALSE(namedGlassDispersion("metal-Cu-eta"));
}

TEST_CASE("Sampled index pairs: linear between them, the ends held, a constant one disperses "
          "nothing",
          "[scene][spectral][dispersion]") {
    IorSpectrumRef s = sampledIor({400, 1.6, 500, 1.55, 700, 1.5});
    REQUIRE(s);
    CHECK(s->at(450) == Approx(1.575));
    CHECK(s->at(600) == Approx(1.525));
    CHECK(s->at(380) == Approx(1.6));
    CHECK(s->at(800) == Approx(1.5));
    CHECK_FALSE(sampledIor({400, 1.5, 700, 1.5}));
    CHECK_FALSE(sampledIor({}));
}

namespace {

Material materialOf(const std::string& material) {
    auto r = loadWorld(material + "\nShape \"sphere\"\n");
    REQUIRE(r.warnings.empty());
    auto shapes = rootShapes(*r.scene);
    REQUIRE(!shapes.empty());
    return r.scene->materials[std::size_t(shapes[0].shape->material)];
}

} // namespace

TEST_CASE("pbrt dielectrics and coats keep a varying eta for the spectral mode beside its n_d",
          "[pbrt][spectral][dispersion]") {
    Material bk7 = materialOf("Material \"dielectric\" \"spectrum eta\" \"glass-BK7\"");
    CHECK(bk7.ior == 1.5168f);
    REQUIRE(bk7.iorSpectrum);
    CHECK(bk7.iorSpectrum->label == "glass-BK7");
    Material thin = materialOf("Material \"thindielectric\" \"spectrum eta\" \"glass-F11\"");
    CHECK(thin.ior == 1.7847f);
    CHECK(thin.iorSpectrum);
    Material pairs = materialOf("Material \"dielectric\" \"spectrum eta\" [400 1.6 700 1.5]");
    REQUIRE(pairs.iorSpectrum);
    CHECK(pairs.ior == Approx(1.6 - 0.1 * 187.6 / 300));
    CHECK(pairs.iorSpectrum->at(550) == Approx(1.55));
    // Constant: none.
    CHECK_FALSE(materialOf("Material \"dielectric\" \"float eta\" 1.5").iorSpectrum);
    CHECK_FALSE(materialOf("Material \"dielectric\" \"spectrum eta\" [400 1.5 700 1.5]").iorSpectrum);
    CHECK_FALSE(materialOf("Material \"dielectric\"").iorSpectrum);
    // The coats: coateddiffuse's eta, coatedconductor's interface.eta.
    Material coated = materialOf("Material \"coateddiffuse\" \"spectrum eta\" \"glass-BK7\"");
    CHECK(coated.ior == 1.5168f);
    REQUIRE(coated.iorSpectrum);
    CHECK(coated.iorSpectrum->label == "glass-BK7");
    Material interface = materialOf(
        "Material \"coatedconductor\" \"spectrum interface.eta\" [400 1.6 700 1.5]");
    REQUIRE(interface.iorSpectrum);
    CHECK(interface.ior == Approx(1.6 - 0.1 * 187.6 / 300));
    CHECK_FALSE(materialOf("Material \"coateddiffuse\" \"float eta\" 1.5").iorSpectrum);
    CHECK_FALSE(materialOf("Material \"coatedconductor\"").iorSpectrum);
    // The conductor's own eta is no coat's.
    CHECK_FALSE(
        materialOf("Material \"coatedconductor\" \"spectrum conductor.eta\" \"metal-Au-eta\" "
                   "\"spectrum conductor.k\" \"metal-Au-k\"")
            .iorSpectrum);
}

namespace {

Material jsonMaterial(const std::string& material) {
    auto scene = sceneFromJson(R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
        "materials": {"m": )" + material + R"(},
        "nodes": [{"type": "sphere", "material": "m", "radius": 1}]})");
    for (const Material& m : scene->materials)
        if (m.name == "m") return m;
    FAIL("no material m");
    return {};
}

} // namespace

TEST_CASE("JSON dielectrics and coats take a named glass or index pairs as their ior",
          "[scene][spectral][dispersion]") {
    Material named = jsonMaterial(R"({"type": "dielectric", "ior": "glass-F11"})");
    CHECK(named.ior == 1.7847f);
    REQUIRE(named.iorSpectrum);
    CHECK(named.iorSpectrum->at(450) > named.iorSpectrum->at(650));
    Material pairs = jsonMaterial(R"({"type": "thindielectric", "ior": [400, 1.6, 700, 1.5]})");
    REQUIRE(pairs.iorSpectrum);
    CHECK(pairs.ior == Approx(1.6 - 0.1 * 187.6 / 300));
    Material flat = jsonMaterial(R"({"type": "dielectric", "ior": [400, 1.5, 700, 1.5]})");
    CHECK_FALSE(flat.iorSpectrum);
    CHECK(flat.ior == 1.5f);
    CHECK_FALSE(jsonMaterial(R"({"type": "dielectric", "ior": 1.33})").iorSpectrum);
    // The coats' "ior" likewise.
    Material coated = jsonMaterial(R"({"type": "coateddiffuse", "ior": "glass-BK7"})");
    CHECK(coated.ior == 1.5168f);
    CHECK(coated.iorSpectrum);
    Material lacquer =
        jsonMaterial(R"({"type": "coatedconductor", "metal": "Au", "ior": [400, 1.6, 700, 1.5]})");
    REQUIRE(lacquer.iorSpectrum);
    CHECK(lacquer.ior == Approx(1.6 - 0.1 * 187.6 / 300));
    CHECK(jsonMaterial(R"({"type": "coateddiffuse", "ior": 1.4})").ior == 1.4f);
    CHECK_THROWS_WITH(jsonMaterial(R"({"type": "coatedconductor", "ior": "glass-XX"})"),
                      Catch::Contains("unknown glass"));
    CHECK_THROWS_WITH(jsonMaterial(R"({"type": "dielectric", "ior": "glass-XX"})"),
                      Catch::Contains("unknown glass"));
    CHECK_THROWS_WITH(jsonMaterial(R"({"type": "dielectric", "ior": [700, 1.5, 400, 1.6]})"),
                      Catch::Contains("ascend"));
}
