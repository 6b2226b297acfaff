// BSDF maths: Fresnel terms, the GGX microfacet distribution, reflection and refraction.
// Pure functions of directions and parameters; the engine's stages call them per ray.
#pragma once

#include "core/math.h"

#include <cmath>

namespace rayproc::kernels {

inline Vec3 reflect(const Vec3& wo, const Vec3& n) { return n * (2.0f * dot(wo, n)) - wo; }

// Unpolarised Fresnel reflectance of a dielectric interface; cosI > 0 on the side of the
// incident ray, eta = n_transmitted / n_incident.
inline float fresnelDielectric(float cosI, float eta) {
    cosI = std::min(std::max(cosI, 0.0f), 1.0f);
    float sin2T = (1.0f - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0f) return 1.0f; // total internal reflection
    float cosT = std::sqrt(1.0f - sin2T);
    float rs = (cosI - eta * cosT) / (cosI + eta * cosT);
    float rp = (eta * cosI - cosT) / (eta * cosI + cosT);
    return 0.5f * (rs * rs + rp * rp);
}

// Refracts wo (pointing away from the surface, on the side of n) through the interface with
// relative index eta = n_t / n_i. Returns false on total internal reflection.
inline bool refract(const Vec3& wo, const Vec3& n, float eta, Vec3& wt) {
    float cosI = dot(wo, n);
    float sin2T = std::max(0.0f, 1.0f - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0f) return false;
    float cosT = std::sqrt(1.0f - sin2T);
    wt = -wo / eta + n * (cosI / eta - cosT);
    return true;
}

inline Vec3 fresnelSchlick(const Vec3& f0, float cosTheta) {
    float m = std::pow(std::max(0.0f, 1.0f - cosTheta), 5.0f);
    return f0 + (Vec3(1.0f) - f0) * m;
}

// GGX (Trowbridge-Reitz) normal distribution with alpha = roughness^2, in the local frame
// where n = +z.
inline float ggxD(float cosThetaH, float alpha) {
    float a2 = alpha * alpha;
    float c2 = cosThetaH * cosThetaH;
    float d = c2 * (a2 - 1.0f) + 1.0f;
    return a2 / (kPi * d * d);
}

// Smith's separable masking term G1 for GGX.
inline float ggxG1(float cosTheta, float alpha) {
    float c2 = cosTheta * cosTheta;
    float t2 = std::max(0.0f, 1.0f - c2) / std::max(c2, 1e-12f);
    return 2.0f / (1.0f + std::sqrt(1.0f + alpha * alpha * t2));
}

inline float ggxAlpha(float roughness) { return std::max(roughness * roughness, 1e-4f); }

// Samples a half vector from D(h) cos(theta_h) around +z.
inline Vec3 ggxSampleHalf(Vec2 u, float alpha) {
    float phi = 2.0f * kPi * u.x;
    float t2 = alpha * alpha * u.y / std::max(1.0f - u.y, 1e-12f);
    float cosT = 1.0f / std::sqrt(1.0f + t2);
    float sinT = std::sqrt(std::max(0.0f, 1.0f - cosT * cosT));
    return {sinT * std::cos(phi), sinT * std::sin(phi), cosT};
}

// The glossy BRDF value times cos(theta_i): GGX conductor with Schlick Fresnel (F0 = color).
// wo, wi, n in world space, unit length.
inline Vec3 glossyEvalCos(const Vec3& wo, const Vec3& wi, const Vec3& n, const Vec3& f0,
                          float alpha) {
    float cosO = dot(wo, n), cosI = dot(wi, n);
    if (cosO <= 0 || cosI <= 0) return Vec3(0.0f);
    Vec3 h = normalize(wo + wi);
    float d = ggxD(dot(h, n), alpha);
    float g = ggxG1(cosO, alpha) * ggxG1(cosI, alpha);
    Vec3 f = fresnelSchlick(f0, dot(wi, h));
    return f * (d * g / (4.0f * cosO));
}

// Pdf in solid angle of sampling wi by ggxSampleHalf + reflection.
inline float glossyPdf(const Vec3& wo, const Vec3& wi, const Vec3& n, float alpha) {
    if (dot(wo, n) <= 0 || dot(wi, n) <= 0) return 0.0f;
    Vec3 h = normalize(wo + wi);
    float cosH = dot(h, n);
    return ggxD(cosH, alpha) * cosH / (4.0f * std::abs(dot(wo, h)));
}

} // namespace rayproc::kernels
