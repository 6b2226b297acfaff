// BxDFs in the local shading frame (z = shading normal, x = tangent), with pbrt-v4's meaning:
// the rough or smooth conductor, the Lambertian reflector and the diffuse transmitter. Each
// gives f(wo, wi) (without the cosine), the pdf of its own sampling routine and the sample.
// Directions point away from the surface; "reflection" means wo and wi in the same hemisphere.
// kernels/pbrt_bsdfs.h maps them to world space; kernels/layered.h stacks them.
#pragma once

#include "core/math.h"
#include "kernels/fresnel.h"
#include "kernels/microfacet.h"
#include "kernels/sampling.h"

#include <cstdint>

namespace rayproc::kernels {

// Trowbridge-Reitz alphas below this are treated as perfectly smooth (pbrt-v4's
// EffectivelySmooth).
constexpr float kSmoothAlpha = 1e-3f;

// Which quantity a path carries: radiance (camera paths) or importance (light paths, and the
// "virtual light" half of the layered estimator). Only refraction's 1 / eta^2 differs.
enum class Transport { Radiance, Importance };

// The lobes a sampling routine may choose from.
enum LobeMask : std::uint8_t { kReflectionLobes = 1, kTransmissionLobes = 2, kAllLobes = 3 };

struct LobeSample {
    Vec3 wi;
    Vec3 f;          // the BxDF value (no cosine)
    float pdf = 0;   // for specular samples: the discrete probability of the lobe
    bool specular = false;
    bool reflection = false;
    bool valid = false;
};

struct ConductorBxdf {
    TrowbridgeReitz mf;
    Vec3 eta, k;

    bool smooth() const { return mf.smooth(kSmoothAlpha); }

    // Torrance-Sparrow: f = D(m) F(wo.m) G(wo, wi) / (4 |cos o| |cos i|), m the half vector.
    Vec3 f(const Vec3& wo, const Vec3& wi) const {
        if (!sameHemisphere(wo, wi) || smooth()) return Vec3(0.0f);
        float cosO = std::abs(wo.z), cosI = std::abs(wi.z);
        Vec3 m = wi + wo;
        if (cosI == 0 || cosO == 0 || lengthSquared(m) == 0) return Vec3(0.0f);
        m = normalize(m);
        Vec3 fr = fresnelComplex(std::abs(dot(wo, m)), eta, k);
        return fr * (mf.d(m) * mf.g(wo, wi) / (4.0f * cosI * cosO));
    }

    // Visible-normal sampling then reflection: p(wi) = D_wo(m) / (4 |wo.m|), the Jacobian of
    // the reflection map.
    float pdf(const Vec3& wo, const Vec3& wi) const {
        if (!sameHemisphere(wo, wi) || smooth()) return 0.0f;
        Vec3 m = wo + wi;
        if (lengthSquared(m) == 0) return 0.0f;
        m = normalize(m);
        if (m.z < 0) m = -m;
        float c = std::abs(dot(wo, m));
        return c > 0 ? mf.dVisible(wo, m) / (4.0f * c) : 0.0f;
    }

    LobeSample sample(const Vec3& wo, Vec2 u) const {
        LobeSample s;
        if (wo.z == 0) return s;
        if (smooth()) {
            s.wi = {-wo.x, -wo.y, wo.z};
            float c = std::abs(s.wi.z);
            s.f = fresnelComplex(c, eta, k) / c;
            s.pdf = 1.0f;
            s.specular = s.reflection = s.valid = true;
            return s;
        }
        Vec3 m = mf.sampleVisible(wo, u);
        s.wi = reflectAbout(wo, m);
        if (!sameHemisphere(wo, s.wi)) return s;
        s.f = f(wo, s.wi);
        s.pdf = pdf(wo, s.wi);
        s.reflection = true;
        s.valid = s.pdf > 0 && std::isfinite(s.pdf);
        return s;
    }
};

// Lambertian reflection R / pi on wo's side, sampled by the cosine.
struct LambertBxdf {
    Vec3 r;

    Vec3 f(const Vec3& wo, const Vec3& wi) const {
        return sameHemisphere(wo, wi) ? r * kInvPi : Vec3(0.0f);
    }
    float pdf(const Vec3& wo, const Vec3& wi) const {
        return sameHemisphere(wo, wi) ? std::abs(wi.z) * kInvPi : 0.0f;
    }
    LobeSample sample(const Vec3& wo, Vec2 u) const {
        LobeSample s;
        s.wi = cosineHemisphere(u);
        if (wo.z < 0) s.wi.z = -s.wi.z;
        s.pdf = std::abs(s.wi.z) * kInvPi;
        s.f = r * kInvPi;
        s.reflection = true;
        s.valid = s.pdf > 0;
        return s;
    }
};

// Lambertian reflection R / pi on wo's side and transmission T / pi on the other. The lobe is
// chosen with probability proportional to the largest channel of R and of T.
struct DiffuseTransmissionBxdf {
    Vec3 r, t;

    float reflectProbability() const {
        float pr = maxComponent(r), pt = maxComponent(t);
        return pr + pt > 0 ? pr / (pr + pt) : 0.0f;
    }
    Vec3 f(const Vec3& wo, const Vec3& wi) const {
        return (sameHemisphere(wo, wi) ? r : t) * kInvPi;
    }
    float pdf(const Vec3& wo, const Vec3& wi) const {
        if (maxComponent(r) + maxComponent(t) <= 0) return 0.0f;
        float pr = reflectProbability();
        return (sameHemisphere(wo, wi) ? pr : 1.0f - pr) * std::abs(wi.z) * kInvPi;
    }
    LobeSample sample(const Vec3& wo, Vec2 u, float uc) const {
        LobeSample s;
        if (wo.z == 0 || maxComponent(r) + maxComponent(t) <= 0) return s;
        s.wi = cosineHemisphere(u);
        s.reflection = uc < reflectProbability();
        // Reflection stays on wo's side, transmission goes to the other.
        if ((wo.z < 0) == s.reflection) s.wi.z = -s.wi.z;
        s.f = f(wo, s.wi);
        s.pdf = pdf(wo, s.wi);
        s.valid = s.pdf > 0;
        return s;
    }
};

} // namespace rayproc::kernels
