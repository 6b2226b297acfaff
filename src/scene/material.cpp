#include "scene/material.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace rayproc {

const char* materialTypeName(MaterialType t) {
    switch (t) {
    case MaterialType::Diffuse: return "diffuse";
    case MaterialType::Mirror: return "mirror";
    case MaterialType::Dielectric: return "dielectric";
    case MaterialType::Glossy: return "glossy";
    case MaterialType::Conductor: return "conductor";
    case MaterialType::CoatedDiffuse: return "coateddiffuse";
    case MaterialType::CoatedConductor: return "coatedconductor";
    case MaterialType::ThinDielectric: return "thindielectric";
    case MaterialType::DiffuseTransmission: return "diffusetransmission";
    case MaterialType::Mix: return "mix";
    }
    return "?";
}

bool coatModelNamed(const std::string& name, Material::CoatModel& model) {
    if (name == "auto") model = Material::CoatModel::Auto;
    else if (name == "analytic") model = Material::CoatModel::Analytic;
    else if (name == "random-walk") model = Material::CoatModel::RandomWalk;
    else return false;
    return true;
}

} // namespace rayproc

namespace rayproc {

namespace {
bool smooth(const FloatParam& u, const FloatParam& v, bool remap) {
    // Textured roughness may vary: only constant zero-like roughness is delta.
    return !u.textured() && !v.textured() && roughnessToAlpha(u.value, remap) < 1e-3f &&
           roughnessToAlpha(v.value, remap) < 1e-3f;
}
bool smooth(const Material& m) { return smooth(m.uRoughness, m.vRoughness, m.remapRoughness); }
// A coated conductor is all delta when its coat and its conductor are smooth and nothing
// scatters between them (kernels::coatedConductorDelta).
bool coatedConductorDelta(const Material& m) {
    return smooth(m) && smooth(m.conductorURoughness, m.conductorVRoughness, m.remapRoughness) &&
           !m.albedo.textured() && m.albedo.value == Vec3(0.0f);
}
} // namespace

float roughnessToAlpha(float roughness, bool remap) {
    roughness = std::max(roughness, 0.0f);
    return remap ? std::sqrt(roughness) : roughness;
}

kernels::LobeFlags materialLobes(const std::vector<Material>& materials, int index) {
    using namespace kernels;
    const Material& m = materials[std::size_t(index)];
    // Delta or glossy by the roughness, for the kinds that have one (looked at per hit: only
    // where it is asked).
    auto width = [&m] { return smooth(m) ? kLobeSpecular : kLobeGlossy; };
    switch (m.type) {
    case MaterialType::Diffuse: return kLobeReflection | kLobeDiffuse;
    case MaterialType::DiffuseTransmission: {
        const bool black = !m.transmittance.textured() && m.transmittance.value == Vec3(0.0f);
        return kLobeReflection | kLobeDiffuse | (black ? 0 : kLobeTransmission);
    }
    case MaterialType::CoatedDiffuse: return kLobeReflection | kLobeDiffuse | width();
    case MaterialType::Glossy: return kLobeReflection | kLobeGlossy;
    case MaterialType::Mirror: return kLobeReflection | kLobeSpecular;
    case MaterialType::ThinDielectric:
        return kLobeReflection | kLobeTransmission | kLobeSpecular | kLobeStraight;
    case MaterialType::Conductor: return kLobeReflection | width();
    case MaterialType::Dielectric: return kLobeReflection | kLobeTransmission | width();
    case MaterialType::CoatedConductor:
        if (coatedConductorDelta(m)) return kLobeReflection | kLobeSpecular;
        return kLobeReflection | kLobeGlossy | (smooth(m) ? kLobeSpecular : 0);
    case MaterialType::Mix:
        return materialLobes(materials, m.mix[0]) | materialLobes(materials, m.mix[1]);
    }
    return kLobeReflection | kLobeDiffuse;
}

MaterialClass materialClass(const std::vector<Material>& materials, int index) {
    const kernels::LobeFlags lobes = materialLobes(materials, index);
    if (kernels::hasLobe(lobes, kernels::kLobeDiffuse)) return MaterialClass::Diffuse;
    if (kernels::hasLobe(lobes, kernels::kLobeGlossy)) return MaterialClass::Glossy;
    return MaterialClass::Specular;
}

bool mixContainsItself(const std::vector<Material>& materials, int index) {
    // Depth-first colouring: 1 = on the current path, 2 = done; reaching a 1 is a cycle.
    std::vector<char> state(materials.size(), 0);
    std::function<bool(int)> cyclic = [&](int mat) {
        if (mat < 0 || std::size_t(mat) >= materials.size()) return false;
        const Material& m = materials[std::size_t(mat)];
        if (m.type != MaterialType::Mix || state[std::size_t(mat)] == 2) return false;
        if (state[std::size_t(mat)] == 1) return true;
        state[std::size_t(mat)] = 1;
        bool found = cyclic(m.mix[0]) || cyclic(m.mix[1]);
        state[std::size_t(mat)] = 2;
        return found;
    };
    return cyclic(index);
}

} // namespace rayproc
