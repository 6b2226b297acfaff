// The parameters of every rayproc BSDF as the kernels see them (after textures and mix
// materials are resolved), and the result of sampling one. Conventions: kernels/bsdf_sampling.h.
#pragma once

#include "core/math.h"
#include "kernels/local_bxdfs.h"

#include <cstdint>

namespace rayproc::kernels {

// The kinds follow pbrt-v4's BxDFs (DiffuseBxDF, ConductorBxDF, DielectricBxDF,
// ThinDielectricBxDF, DiffuseTransmissionBxDF, CoatedDiffuseBxDF, CoatedConductorBxDF) plus
// rayproc's Mirror and Glossy (GGX + Schlick). Mix materials are resolved to one of their two
// before this point.
enum class BsdfKind {
    Diffuse,
    Mirror,
    Dielectric, // smooth (delta) when alphaX and alphaY are below kSmoothAlpha, else rough
    Glossy,
    Conductor,  // smooth (delta) or rough like Dielectric
    ThinDielectric,
    DiffuseTransmission,
    CoatedDiffuse,
    CoatedConductor, // pbrt-v4's layered walk over a conductor (kernels/layered.h)
};

struct BsdfParams {
    BsdfKind kind = BsdfKind::Diffuse;
    // Diffuse albedo, mirror reflectance, glossy F0, dielectric transmission tint,
    // diffusetransmission's reflectance, coateddiffuse's base reflectance.
    Vec3 color{0.5f, 0.5f, 0.5f};
    float ior = 1.5f;    // dielectric, thin dielectric, the coats of the coated kinds
    float alpha = 0.04f; // GGX alpha (Glossy)
    // Trowbridge-Reitz alphas along the tangent and the bitangent (Conductor, Dielectric,
    // the coats of the coated kinds).
    float alphaX = 0.0f, alphaY = 0.0f;
    // Conductor and CoatedConductor's base: complex IOR per channel (the base's relative to
    // vacuum; the kernel divides it by the coat's index, as pbrt-v4's material does).
    Vec3 eta{1.0f, 1.0f, 1.0f}, k{0.0f, 0.0f, 0.0f};
    float baseAlphaX = 0.0f, baseAlphaY = 0.0f; // CoatedConductor's conductor roughness
    Vec3 transmittance{0.0f, 0.0f, 0.0f};            // DiffuseTransmission
    // CoatedDiffuse and CoatedConductor (pbrt-v4's LayeredBxDF): coat thickness, albedo and HG
    // asymmetry of the medium between coat and base, maximum random-walk depth and the number
    // of walks that average one evaluation.
    float thickness = 0.01f;
    Vec3 albedo{0.0f, 0.0f, 0.0f};
    float g = 0.0f;
    int maxDepth = 10;
    int nSamples = 1;
    // CoatedDiffuse: true, pbrt-v4's stochastic random walk; false, the closed form of
    // kernels/coated_analytic.h (no scattering medium: albedo is ignored).
    bool coatWalk = true;
    // Per hit: the shading tangent (the x axis of anisotropic roughness; zero: any axis
    // perpendicular to ns) and the random stream of stochastic evaluation (the coat's walk).
    Vec3 tangent{0.0f, 0.0f, 0.0f};
    std::uint64_t key = 0;
};

struct BsdfSample {
    Vec3 wi;
    Vec3 weight;
    float pdf = 0;
    bool delta = false;
    bool transmitted = false;
    bool valid = false;
    // Drawn from a coated surface's coat reflection (mirror or rough), not from its base: gi's
    // caustic photons follow it (light the coat focuses onto other surfaces).
    bool coat = false;
};

// Opaque BSDFs shade the side wo is on; returns the normals turned to that side.
inline void facingSide(const Vec3& wo, const Vec3& ng, const Vec3& ns, Vec3& fg, Vec3& fs) {
    bool front = dot(wo, ng) >= 0;
    fg = front ? ng : -ng;
    fs = front ? ns : -ns;
}

} // namespace rayproc::kernels
