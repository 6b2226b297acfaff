// A closed-form coated diffuse BSDF: a dielectric coat of index eta (smooth, or Trowbridge-Reitz
// rough) over a Lambertian base of reflectance R, with every internal reflection between coat and
// base summed as a geometric series (Weidlich & Wilkie 2007; the "plastic" of Mitsuba and
// Tungsten). It is the limit of pbrt-v4's layered random walk (kernels/layered.h) without a
// scattering medium when the walk's depth goes to infinity: noise-free, and without the energy
// the walk's maxdepth truncates (about 7% of a white base at maxdepth 10).
//   specular: the coat's reflection, F(cos_o) (a mirror) or D G F / (4 cos_o cos_i) (rough);
//   diffuse:  f_d = (1 - F(cos_i)) (1 - F(cos_o)) T_i T_o R / (pi eta^2 (1 - R F_int T_d^2)),
// F_int the coat's internal diffuse reflectance (Egan & Hilgeman's fit), T_i, T_o the coat
// medium's transmittance exp(-thickness / cos) along the refracted directions (pbrt-v4's unit
// extinction), T_d = exp(-2 thickness) its mean for diffuse light. With R = 1 and thickness 0
// the albedo is exactly 1 for a smooth coat. A rough coat keeps the smooth transmission
// factors: an approximation whose error grows with alpha (tests/kernels/coated_analytic_test.cpp
// measures it against the walk).
#pragma once

#include "kernels/bsdf_params.h"
#include "kernels/fresnel.h"
#include "kernels/microfacet.h"

#include <algorithm>
#include <cmath>

namespace rayproc::kernels {

struct CoatedAnalytic {
    float eta = 1.5f;
    TrowbridgeReitz mf;
    Vec3 base{0.5f, 0.5f, 0.5f};
    float thickness = 0.01f;

    bool smooth() const { return mf.smooth(kSmoothAlpha); }

    // Internal diffuse reflectance of the coat seen from inside (Egan & Hilgeman 1979).
    float internalDiffuseReflectance() const {
        return -1.4399f / (eta * eta) + 0.7099f / eta + 0.6681f + 0.0636f * eta;
    }
    // Transmittance of the coat medium along a direction of cosine cosOut outside, refracted.
    float transmittance(float cosOut) const {
        float sin2 = std::max(0.0f, 1.0f - cosOut * cosOut) / (eta * eta);
        float cosIn = std::sqrt(std::max(0.0f, 1.0f - sin2));
        return std::exp(-thickness / std::max(cosIn, 1e-4f));
    }
    // Diffuse part of f (no cosine), local frame, both directions above.
    Vec3 diffuse(const Vec3& wo, const Vec3& wi) const {
        return diffuse(fresnelDielectricSigned(wo.z, eta), wo, wi);
    }
    // The same with fo = F(cos_o) given (evalCos computes it once for this and the lobe choice).
    Vec3 diffuse(float fo, const Vec3& wo, const Vec3& wi) const {
        float fi = fresnelDielectricSigned(wi.z, eta);
        float td = std::exp(-2.0f * thickness);
        float fint = internalDiffuseReflectance();
        float k = (1 - fo) * (1 - fi) * transmittance(wo.z) * transmittance(wi.z) /
                  (kPi * eta * eta);
        Vec3 r;
        for (int c = 0; c < 3; ++c) r[c] = k * base[c] / (1.0f - base[c] * fint * td * td);
        return r;
    }
    // The diffuse lobe's directional albedo, the integral of f_d(wo, wi) cos_i over the
    // hemisphere: what the base returns of uniform incident light, seen from wo. f_d is
    // separable, so this is (1 - F(cos_o)) T_o R / (eta^2 (1 - R F_int T_d^2)) times the mean
    // of (1 - F(cos_i)) T_i over cosine-weighted directions (midpoint rule in sin^2 theta,
    // the variable in which that density is uniform; 16 strata: within 0.4% of the integral,
    // tests/kernels/coated_analytic_test.cpp).
    Vec3 diffuseAlbedo(float cosO) const {
        constexpr int kStrata = 16;
        float mean = 0;
        for (int j = 0; j < kStrata; ++j) {
            float s2 = (float(j) + 0.5f) / float(kStrata);
            float cosI = std::sqrt(1.0f - s2);
            mean += (1 - fresnelDielectricSigned(cosI, eta)) * transmittance(cosI);
        }
        mean /= float(kStrata);
        float td = std::exp(-2.0f * thickness);
        float fint = internalDiffuseReflectance();
        float k = (1 - fresnelDielectricSigned(cosO, eta)) * transmittance(cosO) * mean / (eta * eta);
        Vec3 r;
        for (int c = 0; c < 3; ++c) r[c] = k * base[c] / (1.0f - base[c] * fint * td * td);
        return r;
    }
    // The coat's rough reflection (no cosine).
    float specular(const Vec3& wo, const Vec3& wi) const {
        Vec3 h = wo + wi;
        if (lengthSquared(h) == 0) return 0.0f;
        h = normalize(h);
        return mf.d(h) * mf.g(wo, wi) * fresnelDielectricSigned(dot(wo, h), eta) /
               (4.0f * wo.z * wi.z);
    }
    // Probability of sampling the coat's reflection rather than the base: the Fresnel weight
    // against the diffuse albedo the base can return.
    float specularProbability(const Vec3& wo) const {
        return specularProbability(fresnelDielectricSigned(wo.z, eta));
    }
    // The same from f = F(cos_o).
    float specularProbability(float f) const {
        float d = (1 - f) * std::max(base.x, std::max(base.y, base.z));
        return std::clamp(f / std::max(f + d, 1e-6f), 0.05f, 0.95f);
    }
    float specularPdf(const Vec3& wo, const Vec3& wi) const {
        Vec3 h = normalize(wo + wi);
        float woh = dot(wo, h);
        if (woh <= 0) return 0.0f;
        return mf.dVisible(wo, h) / (4.0f * woh);
    }
    // f |cos i| and the pdf (lobe choice included) of the non-delta lobes. The same operations
    // as diffuse() + specular() and specularProbability(), specularPdf(), with what they share
    // (F(cos_o), the half vector, D(h), Lambda(wo)) computed once: the same bits, less work.
    Vec3 evalCos(const Vec3& wo, const Vec3& wi, float& pdf) const {
        pdf = 0;
        if (wo.z <= 0 || wi.z <= 0) return Vec3(0.0f);
        float fo = fresnelDielectricSigned(wo.z, eta);
        float ps = specularProbability(fo);
        Vec3 f = diffuse(fo, wo, wi);
        pdf = (1 - ps) * wi.z * kInvPi;
        if (!smooth()) {
            // Both directions above: wo + wi is never zero (specular()'s guard).
            Vec3 h = normalize(wo + wi);
            float dh = mf.d(h), lambdaO = mf.lambda(wo), woh = dot(wo, h);
            float g = 1.0f / (1.0f + lambdaO + mf.lambda(wi));
            f += Vec3(dh * g * fresnelDielectricSigned(woh, eta) / (4.0f * wo.z * wi.z));
            // specularPdf: dVisible(wo, h) / (4 wo.h), G1(wo) = 1 / (1 + Lambda(wo)).
            float g1 = 1.0f / (1.0f + lambdaO);
            pdf += ps * (woh > 0 ? g1 / std::abs(wo.z) * dh * std::abs(woh) / (4.0f * woh) : 0.0f);
        }
        return f * wi.z;
    }
};

} // namespace rayproc::kernels
