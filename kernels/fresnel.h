// Interface optics for the pbrt-v4 BSDF kinds: dielectric Fresnel reflectance for either side of
// the interface, the conductors' complex Fresnel reflectance, refraction about a normal that may
// face either way, and the thin slab's reflectance summed over its internal reflections.
// kernels/bsdf.h keeps the one-sided forms the older kinds use.
#pragma once

#include "core/math.h"

#include <algorithm>
#include <cmath>

namespace rayproc::kernels {

// Unpolarised Fresnel reflectance of a dielectric interface with relative index eta (inside over
// outside, the normal pointing outside). cosI < 0 means the ray arrives from inside: the index
// inverts. With cosT from Snell's law sinT = sinI / eta:
//   r_par = (eta cosI - cosT) / (eta cosI + cosT), r_perp = (cosI - eta cosT) / (cosI + eta cosT),
//   F = (r_par^2 + r_perp^2) / 2, and F = 1 beyond the critical angle.
inline float fresnelDielectricSigned(float cosI, float eta) {
    cosI = std::clamp(cosI, -1.0f, 1.0f);
    if (cosI < 0) {
        eta = 1.0f / eta;
        cosI = -cosI;
    }
    float sin2T = (1.0f - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0f) return 1.0f;
    float cosT = std::sqrt(std::max(0.0f, 1.0f - sin2T));
    float rPar = (eta * cosI - cosT) / (eta * cosI + cosT);
    float rPerp = (cosI - eta * cosT) / (cosI + eta * cosT);
    return 0.5f * (rPar * rPar + rPerp * rPerp);
}

// The same formula for a conductor, whose index eta + i k is complex: cosT becomes complex and
// the reflectances are the squared moduli. Written out in real arithmetic (the moduli expanded,
// as in pbrt-v3's FrConductor): with s2 = sin^2 I, t0 = eta^2 - k^2 - s2 and
// a^2 + b^2 = sqrt(t0^2 + 4 eta^2 k^2), a = sqrt((a^2 + b^2 + t0) / 2),
//   R_perp = (a^2 + b^2 + cos^2 I - 2 a cosI) / (a^2 + b^2 + cos^2 I + 2 a cosI),
//   R_par  = R_perp (cos^2 I (a^2 + b^2) + s2^2 - 2 a cosI s2)
//                 / (cos^2 I (a^2 + b^2) + s2^2 + 2 a cosI s2),
// F = (R_par + R_perp) / 2; at normal incidence ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2).
// Through std::complex<float> (libgcc's __divsc3 division, csqrtf) it cost 15 times as much
// (bench/shading_bench.cpp) and a tenth of a gi render of a scene with metal in it.
inline float fresnelComplex(float cosI, float eta, float k) {
    cosI = std::clamp(cosI, 0.0f, 1.0f);
    float cos2 = cosI * cosI, sin2 = 1.0f - cos2;
    float eta2 = eta * eta, k2 = k * k;
    float t0 = eta2 - k2 - sin2;
    float a2b2 = std::sqrt(t0 * t0 + 4.0f * eta2 * k2);
    float a = std::sqrt(std::max(0.0f, 0.5f * (a2b2 + t0)));
    float t1 = a2b2 + cos2, t2 = 2.0f * cosI * a;
    if (!(t1 + t2 > 0)) return 1.0f; // grazing on an index of 1: the limit
    float rPerp = (t1 - t2) / (t1 + t2);
    float t3 = cos2 * a2b2 + sin2 * sin2, t4 = t2 * sin2;
    float rPar = rPerp * (t3 - t4) / (t3 + t4);
    return 0.5f * (rPar + rPerp);
}

// Per RGB channel.
inline Vec3 fresnelComplex(float cosI, const Vec3& eta, const Vec3& k) {
    return {fresnelComplex(cosI, eta.x, k.x), fresnelComplex(cosI, eta.y, k.y),
            fresnelComplex(cosI, eta.z, k.z)};
}

// Refracts w (pointing away, on either side of n) through an interface of relative index eta
// (the side n points to is outside). When w is inside, the normal and the index flip. etap
// receives the index ratio the ray actually crossed (eta or 1 / eta). False on total internal
// reflection. Snell's law in vector form: wt = -w / etap + (cosI / etap - cosT) n.
inline bool refractSigned(const Vec3& w, Vec3 n, float eta, float& etap, Vec3& wt) {
    float cosI = dot(n, w);
    if (cosI < 0) {
        eta = 1.0f / eta;
        cosI = -cosI;
        n = -n;
    }
    float sin2T = std::max(0.0f, 1.0f - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0f) return false;
    float cosT = std::sqrt(1.0f - sin2T);
    wt = -w / eta + n * (cosI / eta - cosT);
    etap = eta;
    return true;
}

// A thin dielectric slab (two parallel interfaces, no absorption): light bounces between the
// faces, so the total reflectance is the geometric series
//   R' = R + T^2 R (1 + R^2 + R^4 + ...) = R + T^2 R / (1 - R^2),  T' = 1 - R'.
inline float thinDielectricReflectance(float cosI, float eta) {
    float r = fresnelDielectricSigned(std::abs(cosI), eta);
    if (r >= 1.0f) return 1.0f;
    float t = 1.0f - r;
    return r + t * t * r / (1.0f - r * r);
}

} // namespace rayproc::kernels
