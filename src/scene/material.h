// Materials as the scene describes them: pbrt-v4's set (diffuse, coateddiffuse, conductor,
// coatedconductor, dielectric, thindielectric, diffusetransmission, mix) plus rayproc's own
// mirror and glossy. Any colour or float parameter may be a texture (Scene::textures); the
// engine resolves a material at a hit into the kernels' BsdfParams (engine/material_bsdf.h).
#pragma once

#include "core/math.h"
#include "kernels/bsdf_flags.h"

#include <memory>
#include <string>
#include <vector>

namespace rayproc {

// A reflectance given as a spectrum, kept for the spectral mode (scene/reflectance_spectrum.h).
struct ReflectanceSpectrum;
using ReflectanceSpectrumRef = std::shared_ptr<const ReflectanceSpectrum>;
// A dielectric's index over wavelength, kept for the spectral mode (scene/ior_spectrum.h).
struct IorSpectrum;
using IorSpectrumRef = std::shared_ptr<const IorSpectrum>;

// A parameter that is the constant `value`, or Scene::textures[texture] evaluated at the hit.
struct ColorParam {
    Vec3 value{0.5f, 0.5f, 0.5f};
    int texture = -1;
    bool textured() const { return texture >= 0; }
};
struct FloatParam {
    float value = 0.0f;
    int texture = -1;
    bool textured() const { return texture >= 0; }
};

enum class MaterialType {
    Diffuse,             // Lambertian: albedo `color`
    Mirror,              // ideal specular reflection, reflectance `color`
    Dielectric,          // glass of index `ior`; smooth, or rough (Trowbridge-Reitz) when alpha > 0
    Glossy,              // rayproc's GGX with Schlick Fresnel, F0 = `color`, alpha = roughness^2
    Conductor,           // pbrt-v4 conductor: complex Fresnel (eta, k) or an artist's reflectance
    CoatedDiffuse,       // pbrt-v4 coateddiffuse: a dielectric coat over a diffuse base
    CoatedConductor,     // pbrt-v4 coatedconductor: a dielectric coat over a conductor
    ThinDielectric,      // pbrt-v4 thindielectric: a thin slab, reflection + straight transmission
    DiffuseTransmission, // pbrt-v4 diffusetransmission: Lambertian reflection and transmission
    Mix,                 // pbrt-v4 mix: one of two materials, chosen per hit by `amount`
};

// Which engine stages a material needs (raytrace and gi route hits by it; path mode samples the
// whole BSDF whatever the class).
enum class MaterialClass {
    Diffuse,  // a non-delta reflector lit by light sampling, whose indirect light gi gathers
    Glossy,   // a non-delta lobe narrower than diffuse: light sampling + a sampled continuation
    Specular, // only delta lobes (mirror, smooth conductor, smooth dielectric, thin dielectric)
};

struct Material {
    std::string name;
    MaterialType type = MaterialType::Diffuse;
    // Diffuse albedo, mirror reflectance, glossy F0, dielectric tint, conductor reflectance
    // (when useReflectance), coateddiffuse's base reflectance, diffusetransmission's reflectance.
    Vec3 color{0.5f, 0.5f, 0.5f};
    int colorTexture = -1; // replaces `color` when >= 0
    // The constant `color`'s own spectrum where the file gave one (a pbrt-v4 sampled
    // reflectance, an rgb under another colour space): the spectral mode's; RGB mode's is
    // `color`. Likewise DiffuseTransmission's `transmittance` and a coated layer's `albedo`.
    // nullptr: upsampled from the RGB.
    ReflectanceSpectrumRef colorSpectrum, transmittanceSpectrum, albedoSpectrum;
    float ior = 1.5f;      // dielectric, thindielectric, the coated materials' coats
    // Dielectric, ThinDielectric and the coated materials' coats: the index over wavelength
    // where the file gave one that varies (a named glass, sampled pairs): the spectral mode's
    // (dispersion); RGB mode's is `ior`, its value at 587.6 nm. nullptr: `ior` at every
    // wavelength.
    IorSpectrumRef iorSpectrum;
    float roughness = 0.2f; // Glossy only: GGX alpha = roughness^2

    // Trowbridge-Reitz roughness of Conductor, Dielectric and the coated materials' coats
    // (pbrt-v4's interface.roughness for coatedconductor), as pbrt-v4
    // defines it: alpha = remap ? sqrt(r) : r (TrowbridgeReitzDistribution::RoughnessToAlpha);
    // both alphas below 1e-3 mean a perfectly smooth (delta) interface.
    FloatParam uRoughness{0.0f}, vRoughness{0.0f};
    bool remapRoughness = true;

    // Conductor and CoatedConductor's base: complex index of refraction per channel, or `color`
    // as the normal-incidence reflectance (pbrt-v4's "reflectance" parameter, Schlick-like via
    // an equivalent eta/k).
    ColorParam eta{{0.2004f, 0.9240f, 1.1022f}}; // copper (pbrt-v4's default metal)
    ColorParam k{{3.9129f, 2.4528f, 2.1422f}};
    // Constant eta and k's own spectra where the file gave them so (pairs, an rgb under
    // another colour space; clamped to >= 0 only): the spectral mode's, as colorSpectrum.
    ReflectanceSpectrumRef etaSpectrum, kSpectrum;
    bool useReflectance = false;
    // CoatedConductor: the conductor's roughness under the coat (pbrt-v4's
    // conductor.roughness / uroughness / vroughness), remapped as uRoughness.
    FloatParam conductorURoughness{0.0f}, conductorVRoughness{0.0f};

    // DiffuseTransmission: Lambertian transmission; both colours are multiplied by `scale`.
    ColorParam transmittance{{0.25f, 0.25f, 0.25f}};
    float scale = 1.0f;

    // CoatedDiffuse and CoatedConductor: coat thickness, medium albedo and phase asymmetry
    // between the layers, and
    // the random walk's depth and sample count (pbrt-v4's LayeredBxDF).
    FloatParam thickness{0.01f};
    ColorParam albedo{{0.0f, 0.0f, 0.0f}};
    float g = 0.0f;
    int maxDepth = 10;
    int nSamples = 1;
    // How CoatedDiffuse is evaluated: pbrt-v4's stochastic random walk, or the closed form of
    // kernels/coated_analytic.h (its depth-unbounded limit without a scattering medium). Auto:
    // the closed form unless the medium scatters (albedo > 0), which only the walk models.
    enum class CoatModel { Auto, Analytic, RandomWalk };
    CoatModel coatModel = CoatModel::Auto;

    // Mix: Scene::materials[mix[0]] or [mix[1]]: the second with probability `amount`.
    int mix[2] = {-1, -1};
    FloatParam amount{0.5f};

    // Shading normals perturbed as pbrt-v4 does (engine/material_bsdf.h, resolveShading): bump
    // mapping by a float texture of displacement along the normal, or a tangent-space normal
    // map (an RGB image texture, 2 x colour - 1 in the frame (dp/du, ns x dp/du, ns)); Scene::
    // textures indices, -1 for none. A normal map takes precedence, as in pbrt-v4.
    int displacement = -1;
    int normalMap = -1;
};

const char* materialTypeName(MaterialType t);
// A coat model by its name in scenes and on the command line ("auto", "analytic",
// "random-walk"); false for any other name.
bool coatModelNamed(const std::string& name, Material::CoatModel& model);

} // namespace rayproc

namespace rayproc {

// The lobes a hit on materials[index] may have (kernels/bsdf_flags.h), from the material's
// parameters before textures: roughness counts as delta only where it is constant and below
// pbrt-v4's smooth limit (a textured one may vary), a transmittance only where it may be
// non-black; a mix has the lobes of both its components. The engine routes hits by these.
kernels::LobeFlags materialLobes(const std::vector<Material>& materials, int index);

// The class of materials[index]'s lobes: Diffuse with a diffuse lobe, else Glossy with a glossy
// one, else Specular (so a mix is Diffuse if either component is, else Glossy if either is).
MaterialClass materialClass(const std::vector<Material>& materials, int index);

// pbrt-v4's Trowbridge-Reitz alpha of a roughness: sqrt(r) when remapping, else r (negative
// values count as 0).
float roughnessToAlpha(float roughness, bool remap);

// Whether the mix materials[index] contains itself through its components (loaders reject it).
bool mixContainsItself(const std::vector<Material>& materials, int index);

} // namespace rayproc
