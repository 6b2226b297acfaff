// The lobe flags (kernels/bsdf_flags.h) against what each BSDF kind does: every sample's kind
// (delta or not, reflected or transmitted) must be one its flags name, and every flag must be
// met by some sample (no lobe claimed that the BSDF lacks, none missing that it has). The
// material-level flags the stages route by (materialLobes) must be the BSDF's for constant
// parameters.
#include "engine/material_bsdf.h"
#include "kernels/bsdf_flags.h"
#include "kernels/bsdf_sampling.h"
#include "scene/material.h"
#include "statistical/statistical.h"

#include <catch2/catch.hpp>

#include <string>
#include <vector>

using namespace rayproc;
using namespace rayproc::kernels;

namespace {

struct Case {
    std::string label;
    BsdfParams b;
};

std::vector<Case> bsdfCases() {
    std::vector<Case> cases;
    auto add = [&](const std::string& label, BsdfKind kind, float alpha) {
        BsdfParams b;
        b.kind = kind;
        b.alpha = alpha > 0 ? alpha : 0.04f;
        b.alphaX = b.alphaY = alpha;
        b.transmittance = Vec3(0.4f);
        cases.push_back({label, b});
        return &cases.back().b;
    };
    add("diffuse", BsdfKind::Diffuse, 0.0f);
    add("mirror", BsdfKind::Mirror, 0.0f);
    add("glossy", BsdfKind::Glossy, 0.3f);
    add("smooth dielectric", BsdfKind::Dielectric, 0.0f);
    add("rough dielectric", BsdfKind::Dielectric, 0.3f);
    add("index-matched dielectric", BsdfKind::Dielectric, 0.3f)->ior = 1.0f;
    add("smooth conductor", BsdfKind::Conductor, 0.0f);
    add("rough conductor", BsdfKind::Conductor, 0.3f);
    add("thin dielectric", BsdfKind::ThinDielectric, 0.0f);
    add("diffuse transmission", BsdfKind::DiffuseTransmission, 0.0f);
    add("opaque diffuse transmission", BsdfKind::DiffuseTransmission, 0.0f)->transmittance =
        Vec3(0.0f);
    add("coated diffuse, smooth coat, walk", BsdfKind::CoatedDiffuse, 0.0f);
    add("coated diffuse, rough coat, walk", BsdfKind::CoatedDiffuse, 0.3f);
    add("coated diffuse, rough coat, analytic", BsdfKind::CoatedDiffuse, 0.3f)->coatWalk = false;
    add("coated conductor, all smooth", BsdfKind::CoatedConductor, 0.0f);
    add("coated conductor, rough base", BsdfKind::CoatedConductor, 0.0f)->baseAlphaX = 0.3f;
    return cases;
}

} // namespace

TEST_CASE("Lobe flags: each BSDF kind samples exactly the lobes its flags name", "[bsdf][flags]") {
    const Vec3 up(0.0f, 0.0f, 1.0f);
    for (Case& c : bsdfCases()) {
        c.b.baseAlphaY = c.b.baseAlphaX;
        const LobeFlags flags = bsdfFlags(c.b);
        INFO(c.label << ": flags " << int(flags));
        test::TestRng rng(17);
        bool sawDelta = false, sawSpread = false, sawTransmitted = false, sawReflected = false;
        bool sawDensity = false;
        for (float theta : {10.0f, 50.0f, 80.0f}) {
            const float t = theta * kPi / 180.0f;
            const Vec3 wo(std::sin(t), 0.0f, std::cos(t));
            for (int i = 0; i < 4000; ++i) {
                c.b.key = std::uint64_t(i) * 7919u + std::uint64_t(theta);
                BsdfSample s = sampleBsdf(c.b, wo, up, up, rng.uniform2(), rng.uniform());
                if (!s.valid) continue;
                const LobeFlags width =
                    s.delta ? LobeFlags(kLobeSpecular) : LobeFlags(kLobeDiffuse | kLobeGlossy);
                CHECK(hasLobe(flags, width));
                CHECK(hasLobe(flags, s.transmitted ? kLobeTransmission : kLobeReflection));
                (s.delta ? sawDelta : sawSpread) = true;
                (s.transmitted ? sawTransmitted : sawReflected) = true;
                float pdf = 0;
                if (!s.delta && !isBlack(evalBsdf(c.b, wo, s.wi, up, up, pdf))) sawDensity = true;
            }
        }
        CHECK(sawDelta == hasLobe(flags, kLobeSpecular));
        CHECK(sawSpread == !onlySpecular(flags));
        CHECK(sawDensity == !onlySpecular(flags));
        CHECK(sawTransmitted == hasLobe(flags, kLobeTransmission));
        CHECK(sawReflected == hasLobe(flags, kLobeReflection));
        CHECK(isDeltaBsdf(c.b) == onlySpecular(flags));
        CHECK(hasTransmission(c.b) == hasLobe(flags, kLobeTransmission));
    }
}

TEST_CASE("Lobe flags: a material's lobes are its BSDF's, and a mix has both components'",
          "[bsdf][flags]") {
    std::vector<Material> materials;
    auto add = [&](MaterialType type, float roughness) {
        Material m;
        m.type = type;
        m.uRoughness.value = m.vRoughness.value = roughness;
        m.conductorURoughness.value = m.conductorVRoughness.value = roughness;
        m.remapRoughness = false;
        materials.push_back(m);
        return int(materials.size()) - 1;
    };
    for (MaterialType type :
         {MaterialType::Diffuse, MaterialType::Mirror, MaterialType::Glossy,
          MaterialType::Dielectric, MaterialType::Conductor, MaterialType::ThinDielectric,
          MaterialType::DiffuseTransmission, MaterialType::CoatedDiffuse,
          MaterialType::CoatedConductor})
        for (float roughness : {0.0f, 0.3f}) {
            int index = add(type, roughness);
            INFO(materialTypeName(type) << ", roughness " << roughness);
            CHECK(materialLobes(materials, index) == bsdfFlags(bsdfOf(materials[std::size_t(index)])));
        }
    // A textured roughness may vary over the surface: its lobe counts as glossy, not delta.
    int textured = add(MaterialType::Conductor, 0.0f);
    materials[std::size_t(textured)].uRoughness.texture = 0;
    CHECK(materialLobes(materials, textured) == (kLobeReflection | kLobeGlossy));
    int mirror = add(MaterialType::Mirror, 0.0f), diffuse = add(MaterialType::Diffuse, 0.0f);
    Material mix;
    mix.type = MaterialType::Mix;
    mix.mix[0] = mirror;
    mix.mix[1] = diffuse;
    materials.push_back(mix);
    const int m = int(materials.size()) - 1;
    CHECK(materialLobes(materials, m) == (kLobeReflection | kLobeSpecular | kLobeDiffuse));
    CHECK(materialClass(materials, m) == MaterialClass::Diffuse);
}
