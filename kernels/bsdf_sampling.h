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

enum class BsdfKind { Diffuse, Mirror, Dielectric, Glossy };

struct BsdfParams {
    BsdfKind kind = BsdfKind::Diffuse;
    Vec3 color{0.5f, 0.5f, 0.5f}; // albedo, reflectance, F0, or transmission tint
    float ior = 1.5f;
    float alpha = 0.04f; // GGX alpha (glossy)
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
