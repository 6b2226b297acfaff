#include "scene/pbrt/pbrt_materials.h"

#include <cmath>

namespace rayproc::pbrt {

namespace {

// pbrt treats microfacet alphas below this as perfectly smooth (EffectivelySmooth).
constexpr double kSmoothAlpha = 1e-3;

// The mean GGX alpha of (u, v)roughness; anisotropy is averaged away with a warning.
double readAlpha(const ParamList& params, const ValueReader& values, Warnings& warnings,
                 const SourceLoc& loc) {
    float r = values.scalar(params, "roughness", 0.0f);
    float u = values.scalar(params, "uroughness", r);
    float v = values.scalar(params, "vroughness", r);
    bool remap = params.getBool("remaproughness", true);
    if (u < 0 || v < 0) failAt(loc, "roughness must not be negative");
    double au = roughnessToAlpha(u, remap), av = roughnessToAlpha(v, remap);
    if (std::fabs(au - av) > 1e-6)
        warnings.add(loc, "anisotropic roughness is not supported; the mean of uroughness and "
                          "vroughness is used");
    return 0.5 * (au + av);
}

// Normal-incidence reflectance of a conductor with complex index eta + ik.
float conductorF0(float eta, float k) {
    return ((eta - 1) * (eta - 1) + k * k) / ((eta + 1) * (eta + 1) + k * k);
}

void conductor(const ParamList& params, const ValueReader& values, Warnings& warnings,
               const SourceLoc& loc, Material& m) {
    Vec3 color(0.9f);
    if (params.has("reflectance")) {
        color = values.color(params, "reflectance", SpectrumUse::Albedo, Vec3(0.9f));
        params.ignore({"eta", "k"});
    } else {
        const Param* eta = params.get("eta", {"rgb", "spectrum", "float", "texture"});
        const Param* k = params.get("k", {"rgb", "spectrum", "float", "texture"});
        Vec3 e, kk;
        if (eta && k && ValueReader::plainColor(*eta, e) && ValueReader::plainColor(*k, kk))
            color = {conductorF0(e.x, kk.x), conductorF0(e.y, kk.y), conductorF0(e.z, kk.z)};
    }
    double alpha = readAlpha(params, values, warnings, loc);
    m.color = color;
    if (alpha < kSmoothAlpha) {
        m.type = MaterialType::Mirror;
    } else {
        m.type = MaterialType::Glossy;
        m.roughness = float(std::sqrt(alpha));
    }
}

void dielectric(const ParamList& params, const ValueReader& values, Warnings& warnings,
                const SourceLoc& loc, Material& m) {
    m.type = MaterialType::Dielectric;
    m.color = Vec3(1.0f);
    const Param* eta = params.find("eta");
    double ior = 1.5;
    if (eta && (eta->type == "float" || eta->type == "texture"))
        ior = values.scalar(params, "eta", 1.5f);
    else if (eta)
        ior = values.color(params, "eta", SpectrumUse::Unbounded, Vec3(1.5f)).x;
    if (!(ior > 0)) failAt(eta ? eta->loc : loc, "dielectric eta must be positive");
    m.ior = float(ior);
    if (readAlpha(params, values, warnings, loc) >= kSmoothAlpha)
        warnings.add(loc, "rough dielectrics are not supported; rendered smooth");
}

} // namespace

double roughnessToAlpha(double roughness, bool remap) {
    return remap ? std::sqrt(roughness) : roughness;
}

MaterialResult convertMaterial(const std::string& type, const ParamList& params,
                               const ValueReader& values, Warnings& warnings,
                               const SourceLoc& loc) {
    MaterialResult r;
    Material& m = r.material;
    m.type = MaterialType::Diffuse;
    m.color = Vec3(0.5f);
    if (type == "diffuse") {
        m.color = values.color(params, "reflectance", SpectrumUse::Albedo, Vec3(0.5f));
    } else if (type == "coateddiffuse") {
        m.color = values.color(params, "reflectance", SpectrumUse::Albedo, Vec3(0.5f));
        params.ignore({"roughness", "uroughness", "vroughness", "remaproughness", "thickness",
                       "eta", "albedo", "g", "maxdepth", "nsamples"});
        warnings.add(loc, "Material \"coateddiffuse\" is approximated as diffuse with its "
                          "reflectance (no clear-coat highlight)");
    } else if (type == "conductor") {
        conductor(params, values, warnings, loc, m);
    } else if (type == "dielectric") {
        dielectric(params, values, warnings, loc, m);
    } else if (type == "interface" || type == "" || type == "none") {
        r.interface = true;
        m.type = MaterialType::Dielectric; // if it must stand somewhere: pass straight through
        m.color = Vec3(1.0f);
        m.ior = 1.0f;
    } else {
        warnings.add(loc, "Material \"" + type + "\" is not supported; using diffuse 0.5");
        for (const Param& p : params.all()) p.used = true; // the material is reported instead
    }
    return r;
}

} // namespace rayproc::pbrt
