#include "scene/pbrt/pbrt_materials.h"

#include "scene/ior_spectrum.h"
#include "scene/metals.h"
#include "scene/pbrt/pbrt_spectrum.h"

#include <cmath>

namespace rayproc::pbrt {

namespace {

FloatParam floatParam(const ParamList& params, const ValueReader& values, std::string_view name,
                      float def) {
    return values.floatParam(params, name, def);
}

// An unbounded spectral parameter (a conductor's eta or k): rgb, a constant, or a named metal
// spectrum; `def` if absent. Pairs and an rgb under another colour space than sRGB keep their
// spectrum in `spectrum` for the spectral mode (a named metal: its colour is all there is).
ColorParam metalParam(const ParamList& params, const ValueReader& values, std::string_view name,
                      Vec3 def, ReflectanceSpectrumRef& spectrum) {
    spectrum = nullptr;
    const Param* p = params.find(name);
    if (p && p->type == "spectrum" && p->numbers.empty() && p->strings.size() == 1) {
        Vec3 v;
        if (namedMetalSpectrum(p->strings[0], v)) {
            p->used = true;
            ColorParam c;
            c.value = v;
            return c;
        }
    }
    return values.unbounded(params, name, def, spectrum);
}

// A dielectric's index `name` ("eta", coatedconductor's "interface.eta"): a float, a constant
// spectrum or a named glass (at 587.6 nm). `zeroIsOne`: 0 means index-matched (pbrt-v4's
// coatedconductor), else the index must be positive. With `dispersion`, an index that varies
// over wavelength (a named glass, sampled pairs) is kept there for the spectral mode.
float etaParam(const ParamList& params, const ValueReader& values, const SourceLoc& loc,
               float def, std::string_view name = "eta", bool zeroIsOne = false,
               IorSpectrumRef* dispersion = nullptr) {
    const Param* eta = params.find(name);
    double ior = def;
    if (eta && (eta->type == "float" || eta->type == "texture"))
        ior = values.scalar(params, name, def);
    else if (eta)
        ior = values.color(params, name, SpectrumUse::Unbounded, Vec3(def)).x;
    if (zeroIsOne && ior == 0) ior = 1.0;
    if (!(ior > 0)) failAt(eta ? eta->loc : loc, std::string(name) + " must be positive");
    if (dispersion && eta && eta->type == "spectrum")
        *dispersion = eta->strings.size() == 1 ? namedGlassDispersion(eta->strings[0])
                                               : sampledIor(eta->numbers);
    return float(ior);
}

// "<prefix>roughness", "<prefix>uroughness", "<prefix>vroughness", pbrt-v4's defaults (0).
void roughnessPair(const ParamList& params, const ValueReader& values, const SourceLoc& loc,
                   const std::string& prefix, FloatParam& u, FloatParam& v) {
    FloatParam r = floatParam(params, values, prefix + "roughness", 0.0f);
    u = params.find(prefix + "uroughness") ? floatParam(params, values, prefix + "uroughness", 0.0f)
                                           : r;
    v = params.find(prefix + "vroughness") ? floatParam(params, values, prefix + "vroughness", 0.0f)
                                           : r;
    if (u.value < 0 || v.value < 0) failAt(loc, prefix + "roughness must not be negative");
}

// "roughness", "uroughness", "vroughness" and "remaproughness", pbrt-v4's defaults.
void readRoughness(const ParamList& params, const ValueReader& values, const SourceLoc& loc,
                   Material& m) {
    roughnessPair(params, values, loc, "", m.uRoughness, m.vRoughness);
    m.remapRoughness = params.getBool("remaproughness", true);
}

// A conductor's index: "reflectance" (pbrt-v4's equivalent eta and k), else `etaName` and
// `kName` (spectra, named metals or textures), pbrt-v4's copper by default. `both`: whether
// giving reflectance with eta or k is an error (coatedconductor) or ignores them (conductor).
void conductorIndex(const ParamList& params, const ValueReader& values, const SourceLoc& loc,
                    std::string_view etaName, std::string_view kName, bool both, Material& m) {
    if (params.find("reflectance")) {
        if (both && (params.find(etaName) || params.find(kName)))
            failAt(loc, "Material \"coatedconductor\" takes \"reflectance\" or \"" +
                            std::string(etaName) + "\" and \"" + std::string(kName) +
                            "\", not both");
        ColorParam r = values.reflectance(params, "reflectance", Vec3(0.9f), m.colorSpectrum);
        m.color = r.value;
        m.colorTexture = r.texture;
        m.useReflectance = true;
        params.ignore({etaName, kName});
    } else {
        Vec3 cuEta, cuK;
        namedMetalSpectrum("metal-Cu-eta", cuEta);
        namedMetalSpectrum("metal-Cu-k", cuK);
        m.eta = metalParam(params, values, etaName, cuEta, m.etaSpectrum);
        m.k = metalParam(params, values, kName, cuK, m.kSpectrum);
    }
}

void conductor(const ParamList& params, const ValueReader& values, const SourceLoc& loc,
               Material& m) {
    m.type = MaterialType::Conductor;
    conductorIndex(params, values, loc, "eta", "k", false, m);
    readRoughness(params, values, loc, m);
}

// Bump and normal mapping (engine/material_bsdf.h, resolveShading): a "displacement" float texture
// (a constant displaces the whole surface and changes no normal), a "normalmap" image file.
void shadingNormals(const ParamList& params, const ValueReader& values, Material& m) {
    m.displacement = floatParam(params, values, "displacement", 0.0f).texture;
    if (const Param* p = params.find("normalmap")) {
        p->used = true;
        std::string file = params.getString("normalmap", "");
        if (!file.empty()) m.normalMap = values.normalMapTexture(file, p->loc);
    }
}

// The material's base colour from the spectrum or texture parameter `name` (a constant's own
// spectrum kept for the spectral mode).
void baseColor(const ParamList& params, const ValueReader& values, std::string_view name,
               Vec3 def, Material& m) {
    ColorParam c = values.reflectance(params, name, def, m.colorSpectrum);
    m.color = c.value;
    m.colorTexture = c.texture;
}

// The slab between a coat and its base (pbrt-v4's LayeredBxDF parameters and defaults).
void readLayer(const ParamList& params, const ValueReader& values, const SourceLoc& loc,
               Material& m) {
    m.thickness = floatParam(params, values, "thickness", 0.01f);
    m.albedo = values.reflectance(params, "albedo", Vec3(0.0f), m.albedoSpectrum);
    m.g = values.scalar(params, "g", 0.0f);
    m.maxDepth = int(params.getInt("maxdepth", 10));
    m.nSamples = int(params.getInt("nsamples", 1));
    if (!(m.g > -1 && m.g < 1)) failAt(loc, "\"g\" must lie in (-1, 1)");
    if (m.maxDepth < 1 || m.nSamples < 1)
        failAt(loc, "\"maxdepth\" and \"nsamples\" must be at least 1");
    if (!(m.thickness.value > 0)) failAt(loc, "\"thickness\" must be positive");
}

void coatedDiffuse(const ParamList& params, const ValueReader& values, const SourceLoc& loc,
                   Material& m) {
    m.type = MaterialType::CoatedDiffuse;
    baseColor(params, values, "reflectance", Vec3(0.5f), m);
    readRoughness(params, values, loc, m);
    m.ior = etaParam(params, values, loc, 1.5f, "eta", false, &m.iorSpectrum);
    readLayer(params, values, loc, m);
}

// pbrt-v4's CoatedConductorMaterial: a dielectric coat ("interface.*") over a conductor
// ("conductor.*" or "reflectance"), with the coateddiffuse's slab between them.
void coatedConductor(const ParamList& params, const ValueReader& values, const SourceLoc& loc,
                     Material& m) {
    m.type = MaterialType::CoatedConductor;
    roughnessPair(params, values, loc, "interface.", m.uRoughness, m.vRoughness);
    m.ior = etaParam(params, values, loc, 1.5f, "interface.eta", true, &m.iorSpectrum);
    conductorIndex(params, values, loc, "conductor.eta", "conductor.k", true, m);
    roughnessPair(params, values, loc, "conductor.", m.conductorURoughness,
                  m.conductorVRoughness);
    m.remapRoughness = params.getBool("remaproughness", true);
    readLayer(params, values, loc, m);
}

// A mix: its two materials' names (resolved by the caller) and the amount.
void mixMaterial(const ParamList& params, const ValueReader& values, const SourceLoc& loc,
                 MaterialResult& r) {
    r.material.type = MaterialType::Mix;
    const Param* names = params.get("materials", {"string"});
    if (!names || names->strings.size() != 2)
        failAt(names ? names->loc : loc, "Material \"mix\" needs \"string materials\" with "
                                         "two material names");
    r.mixNames[0] = names->strings[0];
    r.mixNames[1] = names->strings[1];
    r.material.amount = floatParam(params, values, "amount", 0.5f);
}

} // namespace

MaterialResult convertMaterial(const std::string& type, const ParamList& params,
                               const ValueReader& values, Warnings& warnings,
                               const SourceLoc& loc) {
    MaterialResult r;
    Material& m = r.material;
    m.type = MaterialType::Diffuse;
    m.color = Vec3(0.5f);
    shadingNormals(params, values, m);
    if (type == "diffuse") {
        baseColor(params, values, "reflectance", Vec3(0.5f), m);
    } else if (type == "coateddiffuse") {
        coatedDiffuse(params, values, loc, m);
    } else if (type == "conductor") {
        conductor(params, values, loc, m);
    } else if (type == "coatedconductor") {
        coatedConductor(params, values, loc, m);
    } else if (type == "dielectric") {
        m.type = MaterialType::Dielectric;
        m.color = Vec3(1.0f);
        m.ior = etaParam(params, values, loc, 1.5f, "eta", false, &m.iorSpectrum);
        readRoughness(params, values, loc, m);
    } else if (type == "thindielectric") {
        m.type = MaterialType::ThinDielectric;
        m.color = Vec3(1.0f);
        m.ior = etaParam(params, values, loc, 1.5f, "eta", false, &m.iorSpectrum);
    } else if (type == "diffusetransmission") {
        m.type = MaterialType::DiffuseTransmission;
        baseColor(params, values, "reflectance", Vec3(0.25f), m);
        m.transmittance =
            values.reflectance(params, "transmittance", Vec3(0.25f), m.transmittanceSpectrum);
        m.scale = values.scalar(params, "scale", 1.0f);
        if (!(m.scale >= 0)) failAt(loc, "\"scale\" must not be negative");
    } else if (type == "mix") {
        mixMaterial(params, values, loc, r);
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
