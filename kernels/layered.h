// pbrt-v4's LayeredBxDF as its CoatedDiffuse and CoatedConductor use it: a dielectric coat
// (smooth or rough) over an opaque base (Lambertian or a Trowbridge-Reitz conductor; one walk,
// a template on the base), with a homogeneous slab of unit extinction and `thickness` between
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

// Whether every lobe of a base is a delta (pbrt-v4's IsSpecular(bottom.Flags())): the walk then
// has no next-event estimate through it, and its samples leave through a rough coat with MIS
// weight 1.
inline bool isSpecularBase(const LambertBxdf&) { return false; }
inline bool isSpecularBase(const ConductorBxdf& c) { return c.smooth(); }

// pbrt-v4's LayeredBxDF<DielectricBxDF, Base, twoSided = true> over an opaque base: Lambert
// (CoatedDiffuse) or Trowbridge-Reitz conductor (CoatedConductor, whose eta and k are relative
// to the coat: the material divides them by the coat's index). Base provides f(wo, wi),
// pdf(wo, wi) and sample(wo, u) in the local frame, and an isSpecularBase overload.
template <class Base>
struct LayeredBxdf {
    DielectricBxdf top;
    Base base;
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
        for (int s = 0; s < nSamples; ++s) walkF(wo, wi, r, sum);
        return sum / float(nSamples);
    }

    // The approximate density of sample(): reflection at the coat plus the
    // transmit-reflect-transmit chain (MIS of its two one-sample estimates when both the coat
    // and the base are rough), mixed as 0.9 of it and 0.1 of the uniform sphere.
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
            if (rs.specular) {
                // A mirror base: only the coat's transmission density remains.
                sum += top.pdf(-rs.wi, wi, kAllLobes);
                continue;
            }
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
        HashedStream r{hashFloats(mix64(key ^ 0x73616d70ULL), {wo.x, wo.y, wo.z, uc, u.x, u.y})};
        SampleWalk p{bs.f * std::abs(bs.wi.z), bs.pdf, thickness, bs.wi, bs.specular};
        for (int depth = 0; depth < maxDepth; ++depth) {
            float rrBeta = maxComponent(p.f) / p.pdf;
            if (depth > 3 && rrBeta < 0.25f) {
                float q = std::max(0.0f, 1.0f - rrBeta);
                if (r.next() < q) return out;
                p.pdf *= 1.0f - q;
            }
            if (p.w.z == 0) return out;
            int step = sampleStep(p, r);
            if (step < 0) return out;
            if (step == 0) continue;
            if (p.z != 0 && p.left) {
                // Out through the coat: the walk's direction is the sample.
                out.wi = flip ? -p.w : p.w;
                out.f = p.f;
                out.pdf = p.pdf;
                out.specular = p.specular;
                out.reflection = true;
                out.valid = true;
                return out;
            }
        }
        return out;
    }

private:
    // The state of f's walk: throughput, height and direction inside the slab.
    struct Walk {
        Vec3 beta;
        float z;
        Vec3 w;
    };
    // The state of sample's walk: the path's f and pdf products, height, direction, whether
    // every vertex so far was a delta, and whether the last interface event left the slab.
    struct SampleWalk {
        Vec3 f;
        float pdf;
        float z;
        Vec3 w;
        bool specular;
        bool left = false;
    };

    // One walk of f: into the slab from wo, and the virtual light's path into it from wi.
    void walkF(const Vec3& wo, const Vec3& wi, HashedStream& r, Vec3& sum) const {
        float uc = r.next();
        LobeSample wos = top.sample(wo, uc, r.next2(), Transport::Radiance, kTransmissionLobes);
        if (!wos.valid || isBlack(wos.f) || wos.pdf == 0 || wos.wi.z == 0) return;
        uc = r.next();
        LobeSample wis = top.sample(wi, uc, r.next2(), Transport::Importance, kTransmissionLobes);
        if (!wis.valid || isBlack(wis.f) || wis.pdf == 0 || wis.wi.z == 0) return;

        Walk p{wos.f * (std::abs(wos.wi.z) / wos.pdf), thickness, wos.wi};
        for (int depth = 0; depth < maxDepth; ++depth) {
            // Russian roulette once the throughput is low.
            if (depth > 3 && maxComponent(p.beta) < 0.25f) {
                float q = std::max(0.0f, 1.0f - maxComponent(p.beta));
                if (r.next() < q) break;
                p.beta = p.beta / (1.0f - q);
            }
            if (isBlack(albedo)) {
                // Straight to the other boundary.
                p.z = (p.z == thickness) ? 0.0f : thickness;
                p.beta *= tr(thickness, p.w);
            } else {
                // A free flight along w: dz ~ exponential with rate 1 / |w.z|.
                float dz = -std::log(1.0f - r.next()) * std::abs(p.w.z);
                float zp = p.w.z > 0 ? p.z + dz : p.z - dz;
                if (zp == p.z) continue;
                if (0 < zp && zp < thickness) {
                    scatterInSlab(p, zp, wi, wis, r, sum);
                    continue;
                }
                p.z = std::clamp(zp, 0.0f, thickness);
            }
            if (p.z == thickness) {
                // Internal reflection at the coat.
                uc = r.next();
                LobeSample bs =
                    top.sample(-p.w, uc, r.next2(), Transport::Radiance, kReflectionLobes);
                if (!bs.valid || isBlack(bs.f) || bs.pdf == 0 || bs.wi.z == 0) break;
                p.beta *= bs.f * (std::abs(bs.wi.z) / bs.pdf);
                p.w = bs.wi;
            } else if (!bounceAtBase(p, wi, wis, r, sum)) {
                break;
            }
        }
    }

    // f's walk scatters in the medium at height zp: next-event estimation through wis, then a
    // phase-function sample, which may itself leave through a rough coat towards wi.
    void scatterInSlab(Walk& p, float zp, const Vec3& wi, const LobeSample& wis, HashedStream& r,
                       Vec3& sum) const {
        const bool exitSpecular = top.smooth();
        const float exitZ = thickness;
        HenyeyGreenstein phase{g};
        float wt = 1.0f;
        if (!exitSpecular) wt = powerHeuristic(wis.pdf, phase.p(-p.w, -wis.wi));
        sum += p.beta * albedo * wis.f *
               (phase.p(-p.w, -wis.wi) * wt * tr(zp - exitZ, wis.wi) / wis.pdf);
        LobeSample ps = phase.sample(-p.w, r.next2());
        if (!ps.valid || ps.wi.z == 0) return;
        p.beta *= albedo * (ps.f.x / ps.pdf);
        p.w = ps.wi;
        p.z = zp;
        if (((p.z < exitZ && p.w.z > 0) || (p.z > exitZ && p.w.z < 0)) && !exitSpecular) {
            float fExit = top.f(-p.w, wi, Transport::Radiance);
            if (fExit > 0) {
                float exitPdf = top.pdf(wi, -p.w, kTransmissionLobes);
                float wt2 = powerHeuristic(ps.pdf, exitPdf);
                sum += p.beta * (tr(zp - exitZ, ps.wi) * fExit * wt2);
            }
        }
    }

    // f's walk at the base: next-event estimation through wis (not for a delta base), then a
    // new direction from the base, which may leave through a rough coat towards wi. False when
    // the base's sample fails (the walk ends).
    bool bounceAtBase(Walk& p, const Vec3& wi, const LobeSample& wis, HashedStream& r,
                      Vec3& sum) const {
        const bool exitSpecular = top.smooth();
        if (!isSpecularBase(base)) {
            float wt = 1.0f;
            if (!exitSpecular) wt = powerHeuristic(wis.pdf, base.pdf(-p.w, -wis.wi));
            sum += p.beta * base.f(-p.w, -wis.wi) * wis.f *
                   (std::abs(wis.wi.z) * wt * tr(thickness, wis.wi) / wis.pdf);
        }
        LobeSample bs = base.sample(-p.w, r.next2());
        if (!bs.valid || isBlack(bs.f) || bs.pdf == 0 || bs.wi.z == 0) return false;
        p.beta *= bs.f * (std::abs(bs.wi.z) / bs.pdf);
        p.w = bs.wi;
        if (!exitSpecular) {
            float fExit = top.f(-p.w, wi, Transport::Radiance);
            if (fExit > 0) {
                float wt2 = 1.0f;
                if (!bs.specular) {
                    float exitPdf = top.pdf(wi, -p.w, kTransmissionLobes);
                    wt2 = powerHeuristic(bs.pdf, exitPdf);
                }
                sum += p.beta * (tr(thickness, bs.wi) * fExit * wt2);
            }
        }
        return true;
    }

    // One step of sample's walk: a scattering in the medium (0: continue), or arrival at a
    // boundary and its interface's sample (1, p.left when it left through the coat), or the
    // end of the walk (-1).
    int sampleStep(SampleWalk& p, HashedStream& r) const {
        if (!isBlack(albedo)) {
            float dz = -std::log(1.0f - r.next()) * std::abs(p.w.z);
            float zp = p.w.z > 0 ? p.z + dz : p.z - dz;
            if (zp == p.z) return -1;
            if (0 < zp && zp < thickness) {
                HenyeyGreenstein phase{g};
                LobeSample ps = phase.sample(-p.w, r.next2());
                if (!ps.valid || ps.wi.z == 0) return -1;
                p.f *= albedo * ps.f.x;
                p.pdf *= ps.pdf;
                p.specular = false;
                p.w = ps.wi;
                p.z = zp;
                return 0;
            }
            p.z = std::clamp(zp, 0.0f, thickness);
        } else {
            p.z = (p.z == thickness) ? 0.0f : thickness;
            p.f *= tr(thickness, p.w);
        }
        LobeSample is;
        float uci = r.next();
        Vec2 ui = r.next2();
        if (p.z == 0)
            is = base.sample(-p.w, ui);
        else
            is = top.sample(-p.w, uci, ui, Transport::Radiance, kAllLobes);
        if (!is.valid || isBlack(is.f) || is.pdf == 0 || is.wi.z == 0) return -1;
        p.f *= is.f;
        p.pdf *= is.pdf;
        p.specular = p.specular && is.specular;
        p.w = is.wi;
        p.left = p.z != 0 && !is.reflection;
        if (!p.left) p.f *= std::abs(is.wi.z);
        return 1;
    }
};

using CoatedDiffuseBxdf = LayeredBxdf<LambertBxdf>;
using CoatedConductorBxdf = LayeredBxdf<ConductorBxdf>;

} // namespace rayproc::kernels
