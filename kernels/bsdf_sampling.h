// Sampling and evaluation of every rayproc BSDF, as pure functions of directions and material
// parameters: what path mode (and the chi-square tests) use. Conventions: all vectors are unit
// and in world space, wo and wi point away from the surface, ng is the geometric normal as the
// shape defines it (outward / by winding), ns the shading normal on the same side as ng.
// `weight` is f * |cos(wi, ns)| / pdf; delta lobes report pdf = 0 and delta = true.
#pragma once

#include "core/math.h"
#include "kernels/bsdf.h"
#include "kernels/sampling.h"

namespace rayproc::kernels {

// The kinds follow pbrt-v4's BxDFs (DiffuseBxDF, ConductorBxDF, DielectricBxDF,
// ThinDielectricBxDF, DiffuseTransmissionBxDF, CoatedDiffuseBxDF) plus rayproc's Mirror and
// Glossy (GGX + Schlick). Mix materials are resolved to one of their two before this point.
enum class BsdfKind {
    Diffuse,
    Mirror,
    Dielectric, // smooth (delta) when alphaX and alphaY are below kSmoothAlpha, else rough
    Glossy,
    Conductor,  // smooth (delta) or rough like Dielectric
    ThinDielectric,
    DiffuseTransmission,
    CoatedDiffuse,
};

// Trowbridge-Reitz alphas below this are treated as perfectly smooth (pbrt-v4's
// EffectivelySmooth).
constexpr float kSmoothAlpha = 1e-3f;

struct BsdfParams {
    BsdfKind kind = BsdfKind::Diffuse;
    // Diffuse albedo, mirror reflectance, glossy F0, dielectric transmission tint,
    // diffusetransmission's reflectance, coateddiffuse's base reflectance.
    Vec3 color{0.5f, 0.5f, 0.5f};
    float ior = 1.5f;    // dielectric, thin dielectric, coateddiffuse's coat
    float alpha = 0.04f; // GGX alpha (Glossy)
    // Trowbridge-Reitz alphas along the tangent and the bitangent (Conductor, Dielectric,
    // CoatedDiffuse's coat).
    float alphaX = 0.0f, alphaY = 0.0f;
    Vec3 eta{1.0f, 1.0f, 1.0f}, k{0.0f, 0.0f, 0.0f}; // Conductor: complex IOR per channel
    Vec3 transmittance{0.0f, 0.0f, 0.0f};            // DiffuseTransmission
    // CoatedDiffuse (pbrt-v4's LayeredBxDF): coat thickness, albedo and HG asymmetry of the
    // medium between coat and base, maximum random-walk depth and the number of walks that
    // average one evaluation.
    float thickness = 0.01f;
    Vec3 albedo{0.0f, 0.0f, 0.0f};
    float g = 0.0f;
    int maxDepth = 10;
    int nSamples = 1;
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
};

// Opaque BSDFs shade the side wo is on; returns the normals turned to that side.
inline void facingSide(const Vec3& wo, const Vec3& ng, const Vec3& ns, Vec3& fg, Vec3& fs) {
    bool front = dot(wo, ng) >= 0;
    fg = front ? ng : -ng;
    fs = front ? ns : -ns;
}

// f * |cos| and the solid-angle pdf of sampling wi, for the non-delta lobes (0 for delta).
inline Vec3 evalBsdf(const BsdfParams& b, const Vec3& wo, const Vec3& wi, const Vec3& ng,
                     const Vec3& ns, float& pdf) {
    pdf = 0;
    Vec3 fg, fs;
    facingSide(wo, ng, ns, fg, fs);
    if (dot(wi, fg) <= 0) return Vec3(0.0f); // the other side: opaque
    float c = dot(wi, fs);
    if (c <= 0) return Vec3(0.0f);
    switch (b.kind) {
    case BsdfKind::Diffuse:
        pdf = c * kInvPi;
        return b.color * (c * kInvPi);
    case BsdfKind::Glossy:
        pdf = glossyPdf(wo, wi, fs, b.alpha);
        return glossyEvalCos(wo, wi, fs, b.color, b.alpha);
    default: return Vec3(0.0f); // delta lobes have no density
    }
}

// u: two uniform numbers for the direction, uc: one for choosing a lobe.
inline BsdfSample sampleBsdf(const BsdfParams& b, const Vec3& wo, const Vec3& ng, const Vec3& ns,
                             Vec2 u, float uc) {
    BsdfSample s;
    switch (b.kind) {
    case BsdfKind::Diffuse: {
        Vec3 fg, fs;
        facingSide(wo, ng, ns, fg, fs);
        s.wi = toWorld(cosineHemisphere(u), fs);
        float c = dot(s.wi, fs);
        if (c <= 0 || dot(s.wi, fg) <= 0) return s;
        s.pdf = c * kInvPi;
        s.weight = b.color;
        s.valid = true;
        return s;
    }
    case BsdfKind::Glossy: {
        Vec3 fg, fs;
        facingSide(wo, ng, ns, fg, fs);
        Vec3 h = toWorld(ggxSampleHalf(u, b.alpha), fs);
        s.wi = reflect(wo, h);
        if (dot(s.wi, fg) <= 0) return s;
        s.pdf = glossyPdf(wo, s.wi, fs, b.alpha);
        if (!(s.pdf > 0) || !std::isfinite(s.pdf)) return s;
        s.weight = glossyEvalCos(wo, s.wi, fs, b.color, b.alpha) / s.pdf;
        s.valid = isFinite(s.weight);
        return s;
    }
    case BsdfKind::Mirror: {
        Vec3 fg, fs;
        facingSide(wo, ng, ns, fg, fs);
        s.wi = reflect(wo, fs);
        if (dot(s.wi, fg) <= 0) s.wi = reflect(wo, fg);
        s.weight = b.color;
        s.delta = true;
        s.valid = true;
        return s;
    }
    case BsdfKind::Dielectric: {
        // The front side of a closed dielectric is its outside. One lobe is chosen with the
        // Fresnel reflectance as probability, so the weight of either is 1 (times the tint on
        // entering).
        bool entering = dot(wo, ng) > 0;
        Vec3 n = entering ? ns : -ns;
        Vec3 g = entering ? ng : -ng;
        float eta = entering ? b.ior : 1.0f / b.ior;
        float f = fresnelDielectric(dot(wo, n), eta);
        s.delta = true;
        if (uc < f) {
            s.wi = reflect(wo, n);
            if (dot(s.wi, g) <= 0) s.wi = reflect(wo, g);
            s.weight = Vec3(1.0f);
            s.valid = true;
            return s;
        }
        Vec3 wt;
        if (!refract(wo, n, eta, wt) || dot(wt, g) >= 0) return s;
        s.wi = wt;
        s.transmitted = true;
        s.weight = entering ? b.color : Vec3(1.0f);
        s.valid = true;
        return s;
    }
    }
    return s;
}

// Veach's power heuristic with beta = 2.
// Written as 1 / (1 + (pb/pa)^2) so that huge pdfs (a near-delta glossy lobe) cannot overflow
// the squares into inf / inf = NaN.
inline float powerHeuristic(float pa, float pb) {
    if (!(pa > 0)) return 0.0f;
    if (!(pb > 0) || std::isinf(pa)) return std::isinf(pb) ? 0.5f : 1.0f;
    if (std::isinf(pb)) return 0.0f;
    float r = pb / pa;
    return 1.0f / (1.0f + r * r);
}

} // namespace rayproc::kernels
