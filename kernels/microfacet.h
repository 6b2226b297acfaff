// The anisotropic Trowbridge-Reitz (GGX) microfacet distribution in the local shading frame
// (z = shading normal, x = tangent), with Smith's height-correlated masking-shadowing and
// Heitz's sampling of the visible normals ("Sampling the GGX Distribution of Visible Normals",
// JCGT 2018). The maths follows Walter et al. 2007 and Heitz 2014 ("Understanding the
// Masking-Shadowing Function"); pbrt-v4's TrowbridgeReitzDistribution has the same meaning.
#pragma once

#include "core/math.h"
#include "kernels/sampling.h"

#include <cmath>

namespace rayproc::kernels {

// An orthonormal frame (x, y, n). x is the tangent made perpendicular to n (Gram-Schmidt); when
// the tangent is zero or parallel to n any perpendicular axis does, which only matters for
// anisotropic roughness.
struct ShadingFrame {
    Vec3 x, y, n;

    ShadingFrame(const Vec3& normal, const Vec3& tangent) : n(normal) {
        Vec3 t = tangent - n * dot(tangent, n);
        float len2 = lengthSquared(t);
        if (len2 > 1e-12f * std::max(lengthSquared(tangent), 1e-30f) && len2 > 0) {
            x = t / std::sqrt(len2);
            y = cross(n, x);
        } else {
            orthonormalBasis(n, x, y);
        }
    }
    Vec3 toLocal(const Vec3& w) const { return {dot(w, x), dot(w, y), dot(w, n)}; }
    Vec3 toWorld(const Vec3& l) const { return x * l.x + y * l.y + n * l.z; }
};

inline bool sameHemisphere(const Vec3& a, const Vec3& b) { return a.z * b.z > 0; }

// Mirror reflection about a local normal m: 2 (w.m) m - w.
inline Vec3 reflectAbout(const Vec3& w, const Vec3& m) { return m * (2.0f * dot(w, m)) - w; }

struct TrowbridgeReitz {
    float alphaX = 0, alphaY = 0;

    // Below this both alphas act as a perfectly smooth interface (delta lobes).
    bool smooth(float threshold) const { return std::max(alphaX, alphaY) < threshold; }

    // D(m) = 1 / (pi ax ay cos^4(theta_m) (1 + tan^2(theta_m) (cos^2 phi / ax^2 +
    // sin^2 phi / ay^2))^2); the bracket's second term is (mx^2 / ax^2 + my^2 / ay^2) / mz^2.
    float d(const Vec3& m) const {
        float z2 = m.z * m.z;
        if (z2 <= 0) return 0.0f;
        float e = (m.x * m.x / (alphaX * alphaX) + m.y * m.y / (alphaY * alphaY)) / z2;
        if (!std::isfinite(e)) return 0.0f;
        float denom = kPi * alphaX * alphaY * z2 * z2 * (1.0f + e) * (1.0f + e);
        return 1.0f / denom;
    }

    // Smith's auxiliary function Lambda(w) = (sqrt(1 + alpha(phi)^2 tan^2 theta) - 1) / 2, where
    // alpha(phi)^2 tan^2 theta = (wx^2 ax^2 + wy^2 ay^2) / wz^2.
    float lambda(const Vec3& w) const {
        float z2 = w.z * w.z;
        if (z2 <= 0) return 0.0f;
        float a2t2 = (w.x * w.x * alphaX * alphaX + w.y * w.y * alphaY * alphaY) / z2;
        if (!std::isfinite(a2t2)) return 0.0f;
        return 0.5f * (std::sqrt(1.0f + a2t2) - 1.0f);
    }

    // Masking of one direction and the height-correlated masking-shadowing of the pair.
    float g1(const Vec3& w) const { return 1.0f / (1.0f + lambda(w)); }
    float g(const Vec3& wo, const Vec3& wi) const {
        return 1.0f / (1.0f + lambda(wo) + lambda(wi));
    }

    // The distribution of normals visible from w: D_w(m) = G1(w) / |cos w| D(m) |w.m|.
    float dVisible(const Vec3& w, const Vec3& m) const {
        float c = std::abs(w.z);
        if (c == 0) return 0.0f;
        return g1(w) / c * d(m) * std::abs(dot(w, m));
    }

    // Samples m from D_w (for w below the surface, from the distribution seen from -w, which is
    // the same set of normals mirrored). Heitz 2018: stretch w to the configuration where the
    // roughness is 1, sample the projected area of the unit hemisphere seen from it (a disk whose
    // far half is foreshortened by (1 + cos theta) / 2), lift the point onto the hemisphere and
    // unstretch the normal.
    Vec3 sampleVisible(const Vec3& w, Vec2 u) const {
        Vec3 wh = normalize(Vec3(alphaX * w.x, alphaY * w.y, w.z));
        if (wh.z < 0) wh = -wh;
        Vec3 t1 = wh.z < 0.99999f ? normalize(cross(Vec3(0, 0, 1), wh)) : Vec3(1, 0, 0);
        Vec3 t2 = cross(wh, t1);
        float r = std::sqrt(u.x), phi = 2.0f * kPi * u.y;
        float px = r * std::cos(phi), py = r * std::sin(phi);
        float s = 0.5f * (1.0f + wh.z);
        float h = std::sqrt(std::max(0.0f, 1.0f - px * px));
        py = (1.0f - s) * h + s * py;
        float pz = std::sqrt(std::max(0.0f, 1.0f - px * px - py * py));
        Vec3 nh = t1 * px + t2 * py + wh * pz;
        return normalize(Vec3(alphaX * nh.x, alphaY * nh.y, std::max(1e-6f, nh.z)));
    }
};

} // namespace rayproc::kernels
