// pbrt-v4's LayeredBxDF specialised to its CoatedDiffuse use: a dielectric coat (smooth or rough)
// over a Lambertian base, with a homogeneous slab of unit extinction and `thickness` between
// them (single-scattering albedo `albedo`, Henyey-Greenstein phase with asymmetry g; albedo 0
// means pure attenuation exp(-thickness / |cos|)). Two-sided: wo below the surface is mirrored
// above. Guo et al. 2018 ("Position-Free Monte Carlo Simulation for Arbitrary Layered BSDFs")
// give the estimators; all three are stochastic:
//  - f: a random walk from wo into the slab, with next-event estimation towards wi through a
//    "virtual light" path sampled from wi (importance transport), MIS-weighted against hitting
//    wi by the walk's own sampling when the coat is rough. One deliberate difference from
//    pbrt-v4: when the walk's own sample leaves towards wi, its MIS weight compares against
//    the density with which the virtual-light strategy produces that inner direction,
//    pdf(wi -> -w), where pbrt-v4 uses pdf(-w -> wi). Refraction's pdf is not symmetric, so
//    pbrt-v4's two weights do not sum to one and f comes out ~5% high for rough coats
//    (tests/statistical/coated_diffuse_bsdf_test.cpp measures it against the sampled weights);
//  - pdf: an approximation (the coat's reflection plus an estimate of the transmit-reflect-
//    transmit density), mixed 9:1 with the uniform sphere so that it is never zero;
//  - sample: a random walk whose f / pdf ratio is an unbiased weight (its pdf is not the pdf()
//    above; callers use pdf() for MIS, as pbrt-v4's pdfIsProportional).
// The random numbers come from a counter-based stream keyed by the caller.
#pragma once

#include "kernels/dielectric_bxdf.h"
#include "kernels/mis.h"
#include "kernels/random.h"

#include <algorithm>
#include <cstring>

namespace rayproc::kernels {

// Uniform numbers in [0, 1) from (key, 0), (key, 1), ...
struct HashedStream {
    std::uint64_t key;
    std::uint32_t dim = 0;
    float next() { return uniform(key, dim++); }
    Vec2 next2() {
        float a = next();
        return {a, next()};
    }
};

inline std::uint64_t hashFloats(std::uint64_t key, std::initializer_list<float> values) {
    for (float v : values) {
        std::uint32_t bits;
        std::memcpy(&bits, &v, sizeof bits);
        key = hashCombine(key, bits);
    }
    return key;
}

// Henyey-Greenstein with both directions pointing away from the scattering point: the
// deflection cosine is -dot(wo, wi), p = (1 - g^2) / (4 pi (1 + g^2 + 2 g dot(wo, wi))^1.5).
struct HenyeyGreenstein {
    float g = 0;

    float p(const Vec3& wo, const Vec3& wi) const {
        float denom = 1.0f + g * g + 2.0f * g * dot(wo, wi);
        return (1.0f - g * g) / (4.0f * kPi * denom * std::sqrt(std::max(denom, 1e-12f)));
    }
    // Inverts the CDF of the deflection cosine t:
    //   t = (1 + g^2 - ((1 - g^2) / (1 - g + 2 g u))^2) / (2 g), uniform for g -> 0.
    LobeSample sample(const Vec3& wo, Vec2 u) const {
        float t;
        if (std::abs(g) < 1e-3f) {
            t = 1.0f - 2.0f * u.x;
        } else {
            float q = (1.0f - g * g) / (1.0f - g + 2.0f * g * u.x);
            t = (1.0f + g * g - q * q) / (2.0f * g);
        }
        t = std::clamp(t, -1.0f, 1.0f);
        float sinT = std::sqrt(std::max(0.0f, 1.0f - t * t)), phi = 2.0f * kPi * u.y;
        Vec3 e1, e2, forward = -wo;
        orthonormalBasis(forward, e1, e2);
        LobeSample s;
        s.wi = forward * t + (e1 * std::cos(phi) + e2 * std::sin(phi)) * sinT;
        s.pdf = p(wo, s.wi);
        s.f = Vec3(s.pdf);
        s.valid = s.pdf > 0;
        return s;
    }
};

struct CoatedDiffuseBxdf {
    DielectricBxdf top;
    LambertBxdf base;
    float thickness = 0.01f;
    Vec3 albedo{0.0f};
    float g = 0;
    int maxDepth = 10;
    int nSamples = 1;

    // Attenuation over a vertical distance dz along w (unit extinction).
    static float tr(float dz, const Vec3& w) { return std::exp(-std::abs(dz / w.z)); }

    // Radiance-transport f(wo, wi): the coat's reflection plus nSamples walks through the slab.
    Vec3 f(Vec3 wo, Vec3 wi, std::uint64_t key) const {
        if (wo.z < 0) {
            wo = -wo;
            wi = -wi;
        }
        // The base is opaque: light only leaves through the top, on wo's side.
        if (!sameHemisphere(wo, wi)) return Vec3(0.0f);
        Vec3 sum = Vec3(top.f(wo, wi, Transport::Radiance)) * float(nSamples);
        HashedStream r{hashFloats(key, {wo.x, wo.y, wo.z, wi.x, wi.y, wi.z})};
        const bool exitSpecular = top.smooth();
        const float exitZ = thickness;
        HenyeyGreenstein phase{g};
        for (int s = 0; s < nSamples; ++s) {
            // Into the slab from wo, and the virtual light's path into the slab from wi.
            float uc = r.next();
            LobeSample wos = top.sample(wo, uc, r.next2(), Transport::Radiance, kTransmissionLobes);
            if (!wos.valid || isBlack(wos.f) || wos.pdf == 0 || wos.wi.z == 0) continue;
            uc = r.next();
            LobeSample wis =
                top.sample(wi, uc, r.next2(), Transport::Importance, kTransmissionLobes);
            if (!wis.valid || isBlack(wis.f) || wis.pdf == 0 || wis.wi.z == 0) continue;

            Vec3 beta = wos.f * (std::abs(wos.wi.z) / wos.pdf);
            float z = thickness;
            Vec3 w = wos.wi;
            for (int depth = 0; depth < maxDepth; ++depth) {
                // Russian roulette once the throughput is low.
                if (depth > 3 && maxComponent(beta) < 0.25f) {
                    float q = std::max(0.0f, 1.0f - maxComponent(beta));
                    if (r.next() < q) break;
                    beta = beta / (1.0f - q);
                }
                if (isBlack(albedo)) {
                    // Straight to the other boundary.
                    z = (z == thickness) ? 0.0f : thickness;
                    beta *= tr(thickness, w);
                } else {
                    // A free flight along w: dz ~ exponential with rate 1 / |w.z|.
                    float dz = -std::log(1.0f - r.next()) * std::abs(w.z);
                    float zp = w.z > 0 ? z + dz : z - dz;
                    if (zp == z) continue;
                    if (0 < zp && zp < thickness) {
                        // Scattering in the medium: next-event estimation through wis.
                        float wt = 1.0f;
                        if (!exitSpecular)
                            wt = powerHeuristic(wis.pdf, phase.p(-w, -wis.wi));
                        sum += beta * albedo * wis.f *
                               (phase.p(-w, -wis.wi) * wt * tr(zp - exitZ, wis.wi) / wis.pdf);
                        LobeSample ps = phase.sample(-w, r.next2());
                        if (!ps.valid || ps.wi.z == 0) continue;
                        beta *= albedo * (ps.f.x / ps.pdf);
                        w = ps.wi;
                        z = zp;
                        // The phase sample itself may leave through the rough coat towards wi.
                        if (((z < exitZ && w.z > 0) || (z > exitZ && w.z < 0)) && !exitSpecular) {
                            float fExit = top.f(-w, wi, Transport::Radiance);
                            if (fExit > 0) {
                                float exitPdf = top.pdf(wi, -w, kTransmissionLobes);
                                float wt2 = powerHeuristic(ps.pdf, exitPdf);
                                sum += beta * (tr(zp - exitZ, ps.wi) * fExit * wt2);
                            }
                        }
                        continue;
                    }
                    z = std::clamp(zp, 0.0f, thickness);
                }
                if (z == exitZ) {
                    // Internal reflection at the coat.
                    uc = r.next();
                    LobeSample bs =
                        top.sample(-w, uc, r.next2(), Transport::Radiance, kReflectionLobes);
                    if (!bs.valid || isBlack(bs.f) || bs.pdf == 0 || bs.wi.z == 0) break;
                    beta *= bs.f * (std::abs(bs.wi.z) / bs.pdf);
                    w = bs.wi;
                } else {
                    // At the diffuse base: next-event estimation through wis...
                    float wt = 1.0f;
                    if (!exitSpecular) wt = powerHeuristic(wis.pdf, base.pdf(-w, -wis.wi));
                    sum += beta * base.f(-w, -wis.wi) * wis.f *
                           (std::abs(wis.wi.z) * wt * tr(thickness, wis.wi) / wis.pdf);
                    // ...then a new direction from the base.
                    LobeSample bs = base.sample(-w, r.next2());
                    if (!bs.valid || isBlack(bs.f) || bs.pdf == 0 || bs.wi.z == 0) break;
                    beta *= bs.f * (std::abs(bs.wi.z) / bs.pdf);
                    w = bs.wi;
                    // The base's sample may leave through the rough coat towards wi.
                    if (!exitSpecular) {
                        float fExit = top.f(-w, wi, Transport::Radiance);
                        if (fExit > 0) {
                            float exitPdf = top.pdf(wi, -w, kTransmissionLobes);
                            float wt2 = powerHeuristic(bs.pdf, exitPdf);
                            sum += beta * (tr(thickness, bs.wi) * fExit * wt2);
                        }
                    }
                }
            }
        }
        return sum / float(nSamples);
    }

    // The approximate density of sample(): reflection at the coat plus the
    // transmit-reflect-transmit chain (MIS of its two one-sample estimates when the coat is
    // rough), mixed as 0.9 of it and 0.1 of the uniform sphere.
    float pdf(Vec3 wo, Vec3 wi, std::uint64_t key) const {
        if (wo.z < 0) {
            wo = -wo;
            wi = -wi;
        }
        if (!sameHemisphere(wo, wi)) return 0.0f; // opaque: rayproc gives no density there
        HashedStream r{hashFloats(mix64(key ^ 0x70646621ULL), {wi.x, wi.y, wi.z, wo.x, wo.y, wo.z})};
        float sum = float(nSamples) * top.pdf(wo, wi, kReflectionLobes);
        for (int s = 0; s < nSamples; ++s) {
            float uc = r.next();
            LobeSample wos = top.sample(wo, uc, r.next2(), Transport::Radiance, kTransmissionLobes);
            uc = r.next();
            LobeSample wis =
                top.sample(wi, uc, r.next2(), Transport::Importance, kTransmissionLobes);
            if (!wos.valid || isBlack(wos.f) || !(wos.pdf > 0) || !wis.valid || isBlack(wis.f) ||
                !(wis.pdf > 0))
                continue;
            if (top.smooth()) {
                sum += base.pdf(-wos.wi, -wis.wi);
                continue;
            }
            LobeSample rs = base.sample(-wos.wi, r.next2());
            if (!rs.valid || isBlack(rs.f) || !(rs.pdf > 0)) continue;
            float rPdf = base.pdf(-wos.wi, -wis.wi);
            sum += powerHeuristic(wis.pdf, rPdf) * rPdf;
            float tPdf = top.pdf(-rs.wi, wi, kAllLobes);
            sum += powerHeuristic(rs.pdf, tPdf) * tPdf;
        }
        return 0.1f / (4.0f * kPi) + 0.9f * sum / float(nSamples);
    }

    // A random walk from wo until it leaves through the coat. f and pdf are the walk's products
    // (f already carries the cosines of the internal bounces); f |cos i| / pdf is the weight.
    LobeSample sample(Vec3 wo, float uc, Vec2 u, std::uint64_t key) const {
        LobeSample out;
        bool flip = wo.z < 0;
        if (flip) wo = -wo;
        LobeSample bs = top.sample(wo, uc, u, Transport::Radiance, kAllLobes);
        if (!bs.valid || isBlack(bs.f) || bs.pdf == 0 || bs.wi.z == 0) return out;
        if (bs.reflection) {
            if (flip) bs.wi = -bs.wi;
            return bs;
        }
        Vec3 w = bs.wi;
        bool specularPath = bs.specular;
        HashedStream r{hashFloats(mix64(key ^ 0x73616d70ULL), {wo.x, wo.y, wo.z, uc, u.x, u.y})};
        Vec3 f = bs.f * std::abs(bs.wi.z);
        float pdf = bs.pdf;
        float z = thickness;
        HenyeyGreenstein phase{g};
        for (int depth = 0; depth < maxDepth; ++depth) {
            float rrBeta = maxComponent(f) / pdf;
            if (depth > 3 && rrBeta < 0.25f) {
                float q = std::max(0.0f, 1.0f - rrBeta);
                if (r.next() < q) return out;
                pdf *= 1.0f - q;
            }
            if (w.z == 0) return out;
            if (!isBlack(albedo)) {
                float dz = -std::log(1.0f - r.next()) * std::abs(w.z);
                float zp = w.z > 0 ? z + dz : z - dz;
                if (zp == z) return out;
                if (0 < zp && zp < thickness) {
                    LobeSample ps = phase.sample(-w, r.next2());
                    if (!ps.valid || ps.wi.z == 0) return out;
                    f *= albedo * ps.f.x;
                    pdf *= ps.pdf;
                    specularPath = false;
                    w = ps.wi;
                    z = zp;
                    continue;
                }
                z = std::clamp(zp, 0.0f, thickness);
            } else {
                z = (z == thickness) ? 0.0f : thickness;
                f *= tr(thickness, w);
            }
            LobeSample is;
            float uci = r.next();
            Vec2 ui = r.next2();
            if (z == 0)
                is = base.sample(-w, ui);
            else
                is = top.sample(-w, uci, ui, Transport::Radiance, kAllLobes);
            if (!is.valid || isBlack(is.f) || is.pdf == 0 || is.wi.z == 0) return out;
            f *= is.f;
            pdf *= is.pdf;
            specularPath = specularPath && is.specular;
            w = is.wi;
            if (z != 0 && !is.reflection) {
                // Out through the coat: the walk's direction is the sample.
                out.wi = flip ? -w : w;
                out.f = f;
                out.pdf = pdf;
                out.specular = specularPath;
                out.reflection = true;
                out.valid = true;
                return out;
            }
            f *= std::abs(is.wi.z);
        }
        return out;
    }
};

} // namespace rayproc::kernels
