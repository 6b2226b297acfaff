// World-space evaluation and sampling of the pbrt-v4 kinds (Conductor, rough Dielectric,
// ThinDielectric, DiffuseTransmission, CoatedDiffuse, CoatedConductor): the local BxDFs of
// local_bxdfs.h, dielectric_bxdf.h and layered.h in the shading frame of (ns, tangent), plus the
// geometric test every rayproc BSDF makes: a reflection must leave on wo's side of ng and a
// transmission on the other, so shading normals cannot leak light through a surface. Samples
// are re-evaluated with the eval functions, so a sample's pdf and weight are exactly evalBsdf's
// (except the layered kinds, whose weight is their random walk's and whose pdf the stochastic
// estimate).
#pragma once

#include "kernels/bsdf.h"
#include "kernels/bsdf_params.h"
#include "kernels/coated_analytic.h"
#include "kernels/dielectric_bxdf.h"
#include "kernels/layered.h"

namespace rayproc::kernels {

inline bool roughAlphas(const BsdfParams& b) {
    return std::max(b.alphaX, b.alphaY) >= kSmoothAlpha;
}

// Whether wi is on the side of the geometric surface that the lobe (reflection or not) implies.
inline bool geometricSideAgrees(const Vec3& wo, const Vec3& wi, const Vec3& ng, bool reflection) {
    float s = dot(wo, ng) * dot(wi, ng);
    return reflection ? s > 0 : s < 0;
}

inline TrowbridgeReitz microfacetsOf(const BsdfParams& b) { return {b.alphaX, b.alphaY}; }

// --- Conductor: opaque, shades the side wo is on.

inline Vec3 evalConductor(const BsdfParams& b, const Vec3& wo, const Vec3& wi, const Vec3& ng,
                          const Vec3& ns, float& pdf) {
    pdf = 0;
    Vec3 fg, fs;
    facingSide(wo, ng, ns, fg, fs);
    ConductorBxdf c{microfacetsOf(b), b.eta, b.k};
    if (dot(wi, fg) <= 0 || c.smooth()) return Vec3(0.0f);
    ShadingFrame frame(fs, b.tangent);
    Vec3 lo = frame.toLocal(wo), li = frame.toLocal(wi);
    pdf = c.pdf(lo, li);
    return c.f(lo, li) * std::abs(li.z);
}

inline BsdfSample sampleConductor(const BsdfParams& b, const Vec3& wo, const Vec3& ng,
                                  const Vec3& ns, Vec2 u) {
    BsdfSample s;
    Vec3 fg, fs;
    facingSide(wo, ng, ns, fg, fs);
    ConductorBxdf c{microfacetsOf(b), b.eta, b.k};
    ShadingFrame frame(fs, b.tangent);
    Vec3 lo = frame.toLocal(wo);
    if (c.smooth()) {
        // Delta reflection about the shading normal (the geometric one if that would go below,
        // as Mirror does), weighted by the complex Fresnel reflectance.
        Vec3 n = fs;
        s.wi = reflect(wo, n);
        if (dot(s.wi, fg) <= 0) s.wi = reflect(wo, n = fg);
        s.weight = fresnelComplex(std::abs(dot(wo, n)), b.eta, b.k);
        s.delta = true;
        s.valid = true;
        return s;
    }
    LobeSample ls = c.sample(lo, u);
    if (!ls.valid) return s;
    s.wi = normalize(frame.toWorld(ls.wi));
    Vec3 f = evalConductor(b, wo, s.wi, ng, ns, s.pdf);
    if (!(s.pdf > 0) || !std::isfinite(s.pdf)) return s;
    s.weight = f / s.pdf;
    s.valid = isFinite(s.weight);
    return s;
}

// --- Dielectric, rough: the frame's normal and the index follow wo's side of ng, as the smooth
// case's "entering"; the transmission tint `color` applies on entering, as there.

struct RoughDielectricSetup {
    bool entering;
    DielectricBxdf bxdf;
    ShadingFrame frame;
};

inline RoughDielectricSetup roughDielectricSetup(const BsdfParams& b, const Vec3& wo,
                                                 const Vec3& ng, const Vec3& ns) {
    bool entering = dot(wo, ng) > 0;
    return {entering, DielectricBxdf{entering ? b.ior : 1.0f / b.ior, microfacetsOf(b)},
            ShadingFrame(entering ? ns : -ns, b.tangent)};
}

inline Vec3 evalRoughDielectric(const BsdfParams& b, const Vec3& wo, const Vec3& wi,
                                const Vec3& ng, const Vec3& ns, float& pdf) {
    pdf = 0;
    RoughDielectricSetup d = roughDielectricSetup(b, wo, ng, ns);
    Vec3 lo = d.frame.toLocal(wo), li = d.frame.toLocal(wi);
    bool reflect = sameHemisphere(lo, li);
    if (!geometricSideAgrees(wo, wi, ng, reflect)) return Vec3(0.0f);
    pdf = d.bxdf.pdf(lo, li);
    Vec3 f(d.bxdf.f(lo, li, Transport::Radiance) * std::abs(li.z));
    return !reflect && d.entering ? f * b.color : f;
}

inline BsdfSample sampleRoughDielectric(const BsdfParams& b, const Vec3& wo, const Vec3& ng,
                                        const Vec3& ns, Vec2 u, float uc) {
    BsdfSample s;
    RoughDielectricSetup d = roughDielectricSetup(b, wo, ng, ns);
    LobeSample ls = d.bxdf.sample(d.frame.toLocal(wo), uc, u, Transport::Radiance);
    if (!ls.valid) return s;
    s.wi = normalize(d.frame.toWorld(ls.wi));
    s.transmitted = !ls.reflection;
    if (!geometricSideAgrees(wo, s.wi, ng, ls.reflection)) return s;
    if (ls.specular) {
        // An index-matched interface (ior 1): straight through, a delta lobe.
        s.weight = ls.f * (std::abs(ls.wi.z) / ls.pdf);
        if (s.transmitted && d.entering) s.weight *= b.color;
        s.delta = true;
        s.valid = isFinite(s.weight);
        return s;
    }
    Vec3 f = evalRoughDielectric(b, wo, s.wi, ng, ns, s.pdf);
    if (!(s.pdf > 0) || !std::isfinite(s.pdf)) return s;
    s.weight = f / s.pdf;
    s.valid = isFinite(s.weight);
    return s;
}

// --- ThinDielectric: delta reflection with the slab's total reflectance R', else straight
// through (wi = -wo). Either weight is R' / R' = T' / T' = 1.

inline BsdfSample sampleThinDielectric(const BsdfParams& b, const Vec3& wo, const Vec3& ng,
                                       const Vec3& ns, float uc) {
    BsdfSample s;
    s.delta = true;
    s.valid = true;
    s.weight = Vec3(1.0f);
    if (uc < thinDielectricReflectance(dot(wo, ns), b.ior)) {
        Vec3 fg, fs;
        facingSide(wo, ng, ns, fg, fs);
        s.wi = reflect(wo, fs);
        if (dot(s.wi, fg) <= 0) s.wi = reflect(wo, fg);
        return s;
    }
    s.wi = -wo;
    s.transmitted = true;
    return s;
}

// --- DiffuseTransmission: reflectance `color` on wo's side, `transmittance` on the other.

inline Vec3 evalDiffuseTransmission(const BsdfParams& b, const Vec3& wo, const Vec3& wi,
                                    const Vec3& ng, const Vec3& ns, float& pdf) {
    pdf = 0;
    Vec3 fg, fs;
    facingSide(wo, ng, ns, fg, fs);
    ShadingFrame frame(fs, Vec3(0.0f));
    Vec3 lo = frame.toLocal(wo), li = frame.toLocal(wi);
    if (!geometricSideAgrees(wo, wi, ng, sameHemisphere(lo, li))) return Vec3(0.0f);
    DiffuseTransmissionBxdf d{b.color, b.transmittance};
    pdf = d.pdf(lo, li);
    return d.f(lo, li) * std::abs(li.z);
}

inline BsdfSample sampleDiffuseTransmission(const BsdfParams& b, const Vec3& wo, const Vec3& ng,
                                            const Vec3& ns, Vec2 u, float uc) {
    BsdfSample s;
    Vec3 fg, fs;
    facingSide(wo, ng, ns, fg, fs);
    ShadingFrame frame(fs, Vec3(0.0f));
    LobeSample ls = DiffuseTransmissionBxdf{b.color, b.transmittance}.sample(frame.toLocal(wo),
                                                                              u, uc);
    if (!ls.valid) return s;
    s.wi = normalize(frame.toWorld(ls.wi));
    s.transmitted = !ls.reflection;
    Vec3 f = evalDiffuseTransmission(b, wo, s.wi, ng, ns, s.pdf);
    if (!(s.pdf > 0)) return s;
    s.weight = f / s.pdf;
    s.valid = isFinite(s.weight);
    return s;
}

// --- CoatedDiffuse: opaque (the base is), shades the side wo is on. Stochastic: f and pdf are
// estimates from streams keyed by b.key and the directions, deterministic for the same inputs.

// The walk's slab parameters, shared by both layered kinds.
template <class Base>
inline LayeredBxdf<Base> layeredOf(const BsdfParams& b, const Base& base) {
    LayeredBxdf<Base> c;
    c.top = DielectricBxdf{b.ior, microfacetsOf(b)};
    c.base = base;
    c.thickness = std::max(b.thickness, std::numeric_limits<float>::min());
    c.albedo = b.albedo;
    c.g = b.g;
    c.maxDepth = b.maxDepth;
    c.nSamples = std::max(1, b.nSamples);
    return c;
}

inline CoatedDiffuseBxdf coatedDiffuseOf(const BsdfParams& b) {
    return layeredOf(b, LambertBxdf{b.color});
}

// pbrt-v4's CoatedConductorMaterial: the conductor's eta and k are relative to the coat's
// medium, so both are divided by the coat's index (1 gives the bare conductor's Fresnel).
inline CoatedConductorBxdf coatedConductorOf(const BsdfParams& b) {
    return layeredOf(b, ConductorBxdf{TrowbridgeReitz{b.baseAlphaX, b.baseAlphaY}, b.eta / b.ior,
                                      b.k / b.ior});
}

// Whether a coated conductor has only delta lobes: a smooth coat (or an index-matched one) over
// a smooth conductor with nothing scattering between them.
inline bool coatedConductorDelta(const BsdfParams& b) {
    return (!roughAlphas(b) || b.ior == 1.0f) &&
           std::max(b.baseAlphaX, b.baseAlphaY) < kSmoothAlpha && isBlack(b.albedo);
}

inline CoatedAnalytic coatedAnalyticOf(const BsdfParams& b) {
    return CoatedAnalytic{b.ior, microfacetsOf(b), b.color, b.thickness};
}

inline Vec3 evalCoatedDiffuse(const BsdfParams& b, const Vec3& wo, const Vec3& wi,
                              const Vec3& ng, const Vec3& ns, float& pdf) {
    pdf = 0;
    Vec3 fg, fs;
    facingSide(wo, ng, ns, fg, fs);
    if (dot(wi, fg) <= 0) return Vec3(0.0f);
    ShadingFrame frame(fs, b.tangent);
    Vec3 lo = frame.toLocal(wo), li = frame.toLocal(wi);
    if (!b.coatWalk) return coatedAnalyticOf(b).evalCos(lo, li, pdf);
    CoatedDiffuseBxdf c = coatedDiffuseOf(b);
    pdf = c.pdf(lo, li, b.key);
    return c.f(lo, li, b.key) * std::abs(li.z);
}

// --- CoatedConductor: the same walk over a conductor base; opaque, shades wo's side.

inline Vec3 evalCoatedConductor(const BsdfParams& b, const Vec3& wo, const Vec3& wi,
                                const Vec3& ng, const Vec3& ns, float& pdf) {
    pdf = 0;
    Vec3 fg, fs;
    facingSide(wo, ng, ns, fg, fs);
    if (dot(wi, fg) <= 0 || coatedConductorDelta(b)) return Vec3(0.0f);
    ShadingFrame frame(fs, b.tangent);
    Vec3 lo = frame.toLocal(wo), li = frame.toLocal(wi);
    CoatedConductorBxdf c = coatedConductorOf(b);
    pdf = c.pdf(lo, li, b.key);
    return c.f(lo, li, b.key) * std::abs(li.z);
}

// The reflectance gi's photon-map estimates give a diffuse-like surface seen from wo, which
// gi treats as Lambertian (L = albedo E / pi): a coated diffuse surface's is its diffuse
// lobe's directional albedo (the coat's Fresnel and absorption in and out, the
// interreflections under it; the walk model is taken as its closed-form limit); otherwise the
// base colour. The coat's own reflection is not in it: gi traces that separately.
inline Vec3 lambertianAlbedo(const BsdfParams& b, const Vec3& wo, const Vec3& ng, const Vec3& ns) {
    if (b.kind != BsdfKind::CoatedDiffuse) return b.color;
    Vec3 fg, fs;
    facingSide(wo, ng, ns, fg, fs);
    return coatedAnalyticOf(b).diffuseAlbedo(std::clamp(std::abs(dot(wo, fs)), 0.0f, 1.0f));
}

// The coat's reflection alone, sampled for a coated diffuse surface whose base the caller
// lights otherwise (raytrace's shadow rays, gi's gather): a smooth coat's mirror direction
// with weight F (delta), a rough coat's visible-normal sample with weight
// f_spec |cos_i| / pdf_spec. Its expectation is the coat's reflection of the incident light,
// without the base's.
inline BsdfSample sampleCoatReflection(const BsdfParams& b, const Vec3& wo, const Vec3& ng,
                                       const Vec3& ns, Vec2 u) {
    BsdfSample s;
    Vec3 fg, fs;
    facingSide(wo, ng, ns, fg, fs);
    ShadingFrame frame(fs, b.tangent);
    Vec3 lo = frame.toLocal(wo);
    if (lo.z <= 0) return s;
    CoatedAnalytic c = coatedAnalyticOf(b);
    s.coat = true;
    if (c.smooth()) {
        s.wi = normalize(frame.toWorld(Vec3(-lo.x, -lo.y, lo.z)));
        if (dot(s.wi, fg) <= 0) return s;
        s.weight = Vec3(fresnelDielectricSigned(lo.z, c.eta));
        s.delta = true;
        s.valid = isFinite(s.weight);
        return s;
    }
    Vec3 li = reflectAbout(lo, c.mf.sampleVisible(lo, u));
    if (li.z <= 0) return s;
    s.pdf = c.specularPdf(lo, li);
    if (!(s.pdf > 0)) return s;
    s.wi = normalize(frame.toWorld(li));
    if (dot(s.wi, fg) <= 0) return s;
    s.weight = Vec3(c.specular(lo, li) * li.z / s.pdf);
    s.valid = isFinite(s.weight);
    return s;
}

// One sample of a layered walk (wo = lo in `frame`): the weight is the walk's f |cos| / pdf
// (unbiased for f |cos| / p), the pdf evalBsdf's estimate (what MIS needs); an all-delta path
// (a smooth coat's mirror reflection; through a smooth coat onto a smooth conductor and back) is
// a delta sample.
template <class Base>
inline BsdfSample sampleLayeredWalk(const LayeredBxdf<Base>& c, std::uint64_t key,
                                    const ShadingFrame& frame, const Vec3& fg, const Vec3& lo,
                                    Vec2 u, float uc) {
    BsdfSample s;
    LobeSample ls = c.sample(lo, uc, u, key);
    if (!ls.valid || !(ls.pdf > 0)) return s;
    s.wi = normalize(frame.toWorld(ls.wi));
    if (dot(s.wi, fg) <= 0) return s;
    s.weight = ls.f * (std::abs(ls.wi.z) / ls.pdf);
    if (ls.specular) {
        s.delta = true;
    } else {
        s.pdf = c.pdf(lo, frame.toLocal(s.wi), key);
    }
    s.valid = isFinite(s.weight);
    return s;
}

// The coated diffuse surface's sample: the closed form's mixture, or the walk.
inline BsdfSample sampleCoatedDiffuse(const BsdfParams& b, const Vec3& wo, const Vec3& ng,
                                      const Vec3& ns, Vec2 u, float uc) {
    BsdfSample s;
    Vec3 fg, fs;
    facingSide(wo, ng, ns, fg, fs);
    ShadingFrame frame(fs, b.tangent);
    Vec3 lo = frame.toLocal(wo);
    if (!b.coatWalk) {
        // The coat's reflection with the probability specularProbability(), else the base
        // (cosine-weighted); the weight is the whole non-delta f |cos| over the mixture pdf.
        CoatedAnalytic c = coatedAnalyticOf(b);
        if (lo.z <= 0) return s;
        float ps = c.specularProbability(lo);
        Vec3 li;
        s.coat = uc < ps;
        if (s.coat) {
            if (c.smooth()) {
                s.wi = normalize(frame.toWorld(Vec3(-lo.x, -lo.y, lo.z)));
                if (dot(s.wi, fg) <= 0) return s;
                s.weight = Vec3(fresnelDielectricSigned(lo.z, c.eta) / ps);
                s.delta = true;
                s.valid = isFinite(s.weight);
                return s;
            }
            li = reflectAbout(lo, c.mf.sampleVisible(lo, u));
        } else {
            li = cosineHemisphere(u);
        }
        if (li.z <= 0) return s;
        Vec3 f = c.evalCos(lo, li, s.pdf);
        if (!(s.pdf > 0)) return s;
        s.wi = normalize(frame.toWorld(li));
        if (dot(s.wi, fg) <= 0) return s;
        s.weight = f / s.pdf;
        s.valid = isFinite(s.weight);
        return s;
    }
    return sampleLayeredWalk(coatedDiffuseOf(b), b.key, frame, fg, lo, u, uc);
}

inline BsdfSample sampleCoatedConductor(const BsdfParams& b, const Vec3& wo, const Vec3& ng,
                                        const Vec3& ns, Vec2 u, float uc) {
    Vec3 fg, fs;
    facingSide(wo, ng, ns, fg, fs);
    ShadingFrame frame(fs, b.tangent);
    return sampleLayeredWalk(coatedConductorOf(b), b.key, frame, fg, frame.toLocal(wo), u, uc);
}

} // namespace rayproc::kernels
