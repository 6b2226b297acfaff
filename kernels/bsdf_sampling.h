// Sampling and evaluation of every rayproc BSDF, as pure functions of directions and material
// parameters: what path mode (and the chi-square tests) use. Conventions: all vectors are unit
// and in world space, wo and wi point away from the surface, ng is the geometric normal as the
// shape defines it (outward / by winding), ns the shading normal on the same side as ng.
// `weight` is f * |cos(wi, ns)| / pdf; delta lobes report pdf = 0 and delta = true.
// Transmissive kinds (Dielectric, ThinDielectric, DiffuseTransmission) return values for wi on
// either side of ng, opaque ones 0 on the other side. CoatedDiffuse (its walk model) and
// CoatedConductor are stochastic (pbrt-v4's LayeredBxDF): f and pdf are estimates seeded by
// BsdfParams::key, and a sample's weight is its random walk's (unbiased, not f / pdf of
// evalBsdf). Rough Dielectric transmission carries
// radiance (f / eta^2), as pbrt-v4's TransportMode::Radiance.
#pragma once

#include "core/math.h"
#include "kernels/bsdf.h"
#include "kernels/bsdf_flags.h"
#include "kernels/bsdf_params.h"
#include "kernels/mis.h"
#include "kernels/pbrt_bsdfs.h"
#include "kernels/sampling.h"

namespace rayproc::kernels {

// A smooth dielectric interface's two delta lobes at wo (the front side of a closed dielectric
// is its outside): the mirror direction, taken about the geometric normal where the shading
// normal's would leave below the surface, the Fresnel reflectance, and the refracted direction
// unless the light is totally reflected. sampleBsdf picks one lobe by the reflectance;
// raytrace's and gi's refraction stage traces both.
struct SmoothInterface {
    bool entering = false; // wo on the front (outer) side
    Vec3 g;                // the geometric normal on wo's side
    float reflectance = 1.0f;
    Vec3 reflected;
    bool transmits = false;
    Vec3 transmitted;
};

inline SmoothInterface smoothInterface(const BsdfParams& b, const Vec3& wo, const Vec3& ng,
                                       const Vec3& ns) {
    SmoothInterface s;
    s.entering = dot(wo, ng) > 0;
    const Vec3 n = s.entering ? ns : -ns;
    s.g = s.entering ? ng : -ng;
    const float eta = s.entering ? b.ior : 1.0f / b.ior;
    s.reflectance = fresnelDielectric(dot(wo, n), eta);
    s.reflected = reflect(wo, n);
    if (dot(s.reflected, s.g) <= 0) s.reflected = reflect(wo, s.g);
    s.transmits = refract(wo, n, eta, s.transmitted) && dot(s.transmitted, s.g) < 0;
    return s;
}

// f * |cos| and the solid-angle pdf of sampling wi, for the non-delta lobes (0 for delta).
inline Vec3 evalBsdf(const BsdfParams& b, const Vec3& wo, const Vec3& wi, const Vec3& ng,
                     const Vec3& ns, float& pdf) {
    pdf = 0;
    // The pbrt-v4 kinds (kernels/pbrt_bsdfs.h); the older four continue below.
    switch (b.kind) {
    case BsdfKind::Conductor: return evalConductor(b, wo, wi, ng, ns, pdf);
    case BsdfKind::Dielectric:
        if (roughAlphas(b)) return evalRoughDielectric(b, wo, wi, ng, ns, pdf);
        break;
    case BsdfKind::DiffuseTransmission: return evalDiffuseTransmission(b, wo, wi, ng, ns, pdf);
    case BsdfKind::CoatedDiffuse: return evalCoatedDiffuse(b, wo, wi, ng, ns, pdf);
    case BsdfKind::CoatedConductor: return evalCoatedConductor(b, wo, wi, ng, ns, pdf);
    default: break;
    }
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
    switch (b.kind) {
    case BsdfKind::Conductor: return sampleConductor(b, wo, ng, ns, u);
    case BsdfKind::Dielectric:
        if (roughAlphas(b)) return sampleRoughDielectric(b, wo, ng, ns, u, uc);
        break;
    case BsdfKind::ThinDielectric: return sampleThinDielectric(b, wo, ng, ns, uc);
    case BsdfKind::DiffuseTransmission: return sampleDiffuseTransmission(b, wo, ng, ns, u, uc);
    case BsdfKind::CoatedDiffuse: return sampleCoatedDiffuse(b, wo, ng, ns, u, uc);
    case BsdfKind::CoatedConductor: return sampleCoatedConductor(b, wo, ng, ns, u, uc);
    default: break;
    }
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
        // One lobe is chosen with the Fresnel reflectance as probability, so the weight of
        // either is 1 (times the tint on entering).
        const SmoothInterface i = smoothInterface(b, wo, ng, ns);
        s.delta = true;
        if (uc < i.reflectance) {
            s.wi = i.reflected;
            s.weight = Vec3(1.0f);
            s.valid = true;
            return s;
        }
        if (!i.transmits) return s;
        s.wi = i.transmitted;
        s.transmitted = true;
        s.weight = i.entering ? b.color : Vec3(1.0f);
        s.valid = true;
        return s;
    }
    default: break; // the pbrt-v4 kinds returned above
    }
    return s;
}

// The non-delta lobe that raytrace's and gi's reflection stage samples after light sampling
// (multiple importance sampling of those two strategies): f * |cos| of that lobe alone and the
// pdf with which the stage's sampler picks wi. A coated surface's rough coat (the stage samples
// it alone, kernels::sampleCoatReflection; its base is lit by light samples only); a rough
// conductor's or rough dielectric's whole BSDF, a coated conductor's whole BSDF (its walk's
// estimate) and rayproc's glossy lobe (sampleBsdf). Zero
// with pdf 0 for every other kind: no sampled ray of theirs collects emission.
inline Vec3 sampledLobeEvalCos(const BsdfParams& b, const Vec3& wo, const Vec3& wi, const Vec3& ng,
                               const Vec3& ns, float& pdf) {
    pdf = 0;
    switch (b.kind) {
    case BsdfKind::CoatedDiffuse: {
        Vec3 fg, fs;
        facingSide(wo, ng, ns, fg, fs);
        if (dot(wi, fg) <= 0) return Vec3(0.0f);
        CoatedAnalytic c = coatedAnalyticOf(b);
        if (c.smooth()) return Vec3(0.0f);
        ShadingFrame frame(fs, b.tangent);
        Vec3 lo = frame.toLocal(wo), li = frame.toLocal(wi);
        if (lo.z <= 0 || li.z <= 0) return Vec3(0.0f);
        pdf = c.specularPdf(lo, li);
        return Vec3(c.specular(lo, li) * li.z);
    }
    case BsdfKind::Conductor:
    case BsdfKind::Dielectric:
        if (!roughAlphas(b)) return Vec3(0.0f);
        return evalBsdf(b, wo, wi, ng, ns, pdf);
    case BsdfKind::CoatedConductor:
    case BsdfKind::Glossy: return evalBsdf(b, wo, wi, ng, ns, pdf);
    default: return Vec3(0.0f);
    }
}

// The lobes of the BSDF (kernels/bsdf_flags.h). A smooth or index-matched dielectric and a
// smooth conductor are delta, rough ones glossy; a coated diffuse surface is its diffuse base
// and its coat's reflection (delta or glossy); a coated conductor is delta only when its coat,
// its conductor and the medium between them are all clear and smooth (over a rough conductor
// a smooth coat adds its mirror reflection to the glossy light from below).
inline LobeFlags bsdfFlags(const BsdfParams& b) {
    const LobeFlags width = roughAlphas(b) ? kLobeGlossy : kLobeSpecular;
    switch (b.kind) {
    case BsdfKind::Diffuse: return kLobeReflection | kLobeDiffuse;
    case BsdfKind::Mirror: return kLobeReflection | kLobeSpecular;
    case BsdfKind::Glossy: return kLobeReflection | kLobeGlossy;
    case BsdfKind::Dielectric:
        if (b.ior == 1.0f) return kLobeTransmission | kLobeSpecular; // passes straight through
        return kLobeReflection | kLobeTransmission | width;
    case BsdfKind::Conductor: return kLobeReflection | width;
    case BsdfKind::ThinDielectric:
        return kLobeReflection | kLobeTransmission | kLobeSpecular | kLobeStraight;
    case BsdfKind::DiffuseTransmission:
        return kLobeReflection | kLobeDiffuse | (isBlack(b.transmittance) ? 0 : kLobeTransmission);
    case BsdfKind::CoatedDiffuse: return kLobeReflection | kLobeDiffuse | width;
    case BsdfKind::CoatedConductor:
        // A smooth coat reflects as a mirror over whatever the conductor beneath does.
        if (coatedConductorDelta(b)) return kLobeReflection | kLobeSpecular;
        return kLobeReflection | kLobeGlossy | (roughAlphas(b) ? 0 : kLobeSpecular);
    }
    return kLobeReflection | kLobeDiffuse;
}

// True when every lobe is a delta (evalBsdf is zero everywhere; light sampling cannot help).
inline bool isDeltaBsdf(const BsdfParams& b) { return onlySpecular(bsdfFlags(b)); }

// True when the BSDF can send light to the other side of the surface.
inline bool hasTransmission(const BsdfParams& b) {
    return hasLobe(bsdfFlags(b), kLobeTransmission);
}

} // namespace rayproc::kernels
