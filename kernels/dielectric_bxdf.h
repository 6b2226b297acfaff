// The dielectric interface in the local shading frame with pbrt-v4's meaning (DielectricBxDF):
// smooth (delta reflection and refraction) or rough (Trowbridge-Reitz microfacets, Walter et al.
// 2007 "Microfacet Models for Refraction through Rough Surfaces"). eta is the relative index of
// the side z < 0 over the side z > 0; wo may be on either side.
//
// Rough transmission uses the generalised half vector m = normalize(wo + etap wi) (etap the
// index ratio crossed), whose Jacobian is dm/dwi = |wi.m| / (wi.m + wo.m / etap)^2, giving
//   f_t = D(m) (1 - F) G |wi.m wo.m| / (|cos i cos o| (wi.m + wo.m / etap)^2),
// divided by etap^2 for radiance (radiance is compressed into the smaller solid angle). The
// sampling routine draws m from the visible normals and chooses reflection with probability F.
#pragma once

#include "kernels/local_bxdfs.h"

namespace rayproc::kernels {

struct DielectricBxdf {
    float eta = 1.5f;
    TrowbridgeReitz mf;

    // An index-matched interface only lets light through, as a smooth one.
    bool smooth() const { return eta == 1.0f || mf.smooth(kSmoothAlpha); }

    // The generalised half vector of (wo, wi), facing +z; false for configurations no microfacet
    // produces (grazing, or the microfacet seen from behind by either direction).
    bool halfVector(const Vec3& wo, const Vec3& wi, Vec3& m, float& etap, bool& reflect) const {
        float cosO = wo.z, cosI = wi.z;
        reflect = cosI * cosO > 0;
        etap = reflect ? 1.0f : (cosO > 0 ? eta : 1.0f / eta);
        m = wi * etap + wo;
        if (cosI == 0 || cosO == 0 || lengthSquared(m) == 0) return false;
        m = normalize(m);
        if (m.z < 0) m = -m;
        return dot(m, wi) * cosI >= 0 && dot(m, wo) * cosO >= 0;
    }

    float f(const Vec3& wo, const Vec3& wi, Transport mode) const {
        if (smooth()) return 0.0f;
        Vec3 m;
        float etap;
        bool reflect;
        if (!halfVector(wo, wi, m, etap, reflect)) return 0.0f;
        float fr = fresnelDielectricSigned(dot(wo, m), eta);
        float dg = mf.d(m) * mf.g(wo, wi);
        if (reflect) return dg * fr / std::abs(4.0f * wi.z * wo.z);
        float s = dot(wi, m) + dot(wo, m) / etap;
        float denom = s * s * wi.z * wo.z;
        if (denom == 0) return 0.0f;
        float ft = dg * (1.0f - fr) * std::abs(dot(wi, m) * dot(wo, m) / denom);
        return mode == Transport::Radiance ? ft / (etap * etap) : ft;
    }

    // The density of sample(wo, ...) restricted to `lobes` (the lobe probabilities renormalised).
    float pdf(const Vec3& wo, const Vec3& wi, LobeMask lobes = kAllLobes) const {
        if (smooth()) return 0.0f;
        Vec3 m;
        float etap;
        bool reflect;
        if (!halfVector(wo, wi, m, etap, reflect)) return 0.0f;
        float r = fresnelDielectricSigned(dot(wo, m), eta);
        float pr = (lobes & kReflectionLobes) ? r : 0.0f;
        float pt = (lobes & kTransmissionLobes) ? 1.0f - r : 0.0f;
        if (pr + pt <= 0) return 0.0f;
        if (reflect) {
            float c = std::abs(dot(wo, m));
            return c > 0 ? mf.dVisible(wo, m) / (4.0f * c) * pr / (pr + pt) : 0.0f;
        }
        float s = dot(wi, m) + dot(wo, m) / etap;
        if (s == 0) return 0.0f;
        return mf.dVisible(wo, m) * std::abs(dot(wi, m)) / (s * s) * pt / (pr + pt);
    }

    LobeSample sample(const Vec3& wo, float uc, Vec2 u, Transport mode,
                      LobeMask lobes = kAllLobes) const {
        LobeSample s;
        if (wo.z == 0) return s;
        if (smooth()) return sampleSmooth(wo, uc, mode, lobes);
        Vec3 m = mf.sampleVisible(wo, u);
        float r = fresnelDielectricSigned(dot(wo, m), eta);
        float pr = (lobes & kReflectionLobes) ? r : 0.0f;
        float pt = (lobes & kTransmissionLobes) ? 1.0f - r : 0.0f;
        if (pr + pt <= 0) return s;
        if (uc < pr / (pr + pt)) {
            s.wi = reflectAbout(wo, m);
            if (!sameHemisphere(wo, s.wi)) return s;
            s.reflection = true;
        } else {
            float etap;
            if (!refractSigned(wo, m, eta, etap, s.wi)) return s;
            if (sameHemisphere(wo, s.wi) || s.wi.z == 0) return s;
        }
        // The value and density of the direction drawn, as f() and pdf() give them.
        s.f = Vec3(f(wo, s.wi, mode));
        s.pdf = pdf(wo, s.wi, lobes);
        s.valid = s.pdf > 0 && std::isfinite(s.pdf);
        return s;
    }

private:
    // Delta lobes: the mirror direction with probability F, the refracted one with 1 - F; the
    // value is (F or (1 - F) / etap^2) / |cos i|.
    LobeSample sampleSmooth(const Vec3& wo, float uc, Transport mode, LobeMask lobes) const {
        LobeSample s;
        float r = fresnelDielectricSigned(wo.z, eta);
        float pr = (lobes & kReflectionLobes) ? r : 0.0f;
        float pt = (lobes & kTransmissionLobes) ? 1.0f - r : 0.0f;
        if (pr + pt <= 0) return s;
        s.specular = true;
        if (uc < pr / (pr + pt)) {
            s.wi = {-wo.x, -wo.y, wo.z};
            s.f = Vec3(r / std::abs(s.wi.z));
            s.pdf = pr / (pr + pt);
            s.reflection = true;
            s.valid = true;
            return s;
        }
        float etap;
        if (!refractSigned(wo, Vec3(0, 0, 1), eta, etap, s.wi) || s.wi.z == 0) return s;
        float ft = (1.0f - r) / std::abs(s.wi.z);
        s.f = Vec3(mode == Transport::Radiance ? ft / (etap * etap) : ft);
        s.pdf = pt / (pr + pt);
        s.valid = true;
        return s;
    }
};

} // namespace rayproc::kernels
