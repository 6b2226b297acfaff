// Ward & Heckbert's irradiance gradients ("Irradiance Gradients", 1992) from the strata of a
// cosine-weighted stratified final gather (GatherStrata). Derivations in
// docs/irradiance-cache.md; in short, with the frame (u, v, n), theta_j, phi_k the centre of
// stratum (j, k), theta_j- / phi_k- the boundary between strata j-1, j / k-1, k:
//
// Rotation. E(n) = integral of L cos; turning n by a small rotation vector w changes cos by
// w . (n x omega), so gradR = integral of L (n x omega) d omega = integral of L tan(theta)
// v(phi) cos(theta) d omega, with v(phi) = n x u(phi) the base-plane direction phi + pi/2:
//   gradR = pi / (M N) sum_k v(phi_k) sum_j tan_j L_jk,
// tan_j the mean of tan(theta) over ring j (Ward & Heckbert take it at the sample).
//
// Translation. Moving p by delta d moves the directions of what p sees by -(delta / r) d
// (projected), so each boundary between two strata sweeps over a sliver of solid angle that
// changes its radiance from one stratum's to the other's; the closer of the two surfaces,
// min(r), sets the speed. Over the theta boundaries (cones) and the phi boundaries (planes):
//   gradT = sum_k [ u(phi_k) 2 sin(pi / N) sum_{j=1}^{M-1} sin(theta_j-) cos^2(theta_j-)
//                     (L_jk - L_j-1,k) / min(r_jk, r_j-1,k)
//                 + v(phi_k-) sum_j (sin(theta_j+) - sin(theta_j-))
//                     (L_jk - L_j,k-1) / min(r_jk, r_j,k-1) ]
// where 2 sin(pi / N) u(phi_k) is the exact integral of u(phi) over the azimuth of stratum k
// (Ward & Heckbert approximate it by 2 pi / N u(phi_k)).
#include "gi/irradiance_cache.h"

#include "core/error.h"

#include <vector>

namespace rayproc {

namespace {

// 1 / min(r0, r1): the closer surface moves fastest across the boundary. Misses (infinite
// distance) give 0; non-positive distances carry no information and also give 0.
float inverseMinDistance(float r0, float r1) {
    float r = std::min(r0, r1);
    return r > 0 ? 1.0f / r : 0.0f;
}

void addScaled(Vec3 grad[3], const Vec3& direction, const Vec3& perChannel) {
    for (int c = 0; c < 3; ++c) grad[c] += direction * perChannel[c];
}

} // namespace

void IrradianceCache::estimateGradients(const GatherStrata& strata, const Vec3& u, const Vec3& v,
                                        const Vec3& n, Vec3 gradT[3], Vec3 gradR[3]) {
    const int m = strata.thetaCount;
    const int nPhi = strata.phiCount;
    RAYPROC_CHECK(m > 0 && nPhi > 0);
    RAYPROC_CHECK(strata.radiance.size() == std::size_t(m) * std::size_t(nPhi));
    RAYPROC_CHECK(strata.distance.size() == strata.radiance.size());
    auto radiance = [&](int j, int k) -> const Vec3& { return strata.radiance[j * nPhi + k]; };
    auto distance = [&](int j, int k) { return strata.distance[j * nPhi + k]; };
    auto baseDirection = [&](float phi) { return std::cos(phi) * u + std::sin(phi) * v; };

    for (int c = 0; c < 3; ++c) gradT[c] = gradR[c] = Vec3(0.0f);
    const float phiStep = 2.0f * kPi / float(nPhi);
    const float azimuthIntegral = 2.0f * std::sin(kPi / float(nPhi));
    // The mean of tan(theta) over ring j in the cosine-weighted measure (s = sin^2 theta is
    // uniform): M [F(theta_j+) - F(theta_j-)], F(theta) = theta - sin(theta) cos(theta), the
    // antiderivative of tan(theta) in s. Finite in the last ring, where tan at the centre
    // would underestimate the horizon's weight.
    std::vector<float> meanTan(std::size_t(m), 0.0f);
    for (int j = 0; j < m; ++j) {
        auto f = [&](int i) {
            double s2 = double(i) / double(m);
            return std::asin(std::sqrt(s2)) - std::sqrt(s2 * (1.0 - s2));
        };
        meanTan[j] = float(double(m) * (f(j + 1) - f(j)));
    }
    for (int k = 0; k < nPhi; ++k) {
        const float phiCenter = (float(k) + 0.5f) * phiStep;
        const float phiEdge = float(k) * phiStep; // between strata k-1 and k
        const int kPrev = (k + nPhi - 1) % nPhi;

        Vec3 rotation(0.0f), thetaSum(0.0f), phiSum(0.0f);
        for (int j = 0; j < m; ++j) {
            float sinLow = std::sqrt(float(j) / float(m));      // sin(theta_j-)
            float sinHigh = std::sqrt(float(j + 1) / float(m)); // sin(theta_j+)
            rotation += radiance(j, k) * meanTan[j];
            if (j > 0) {
                float cos2Low = 1.0f - float(j) / float(m);
                thetaSum +=
                    (radiance(j, k) - radiance(j - 1, k)) *
                    (sinLow * cos2Low * inverseMinDistance(distance(j, k), distance(j - 1, k)));
            }
            phiSum += (radiance(j, k) - radiance(j, kPrev)) *
                      ((sinHigh - sinLow) * inverseMinDistance(distance(j, k), distance(j, kPrev)));
        }
        Vec3 uCenter = baseDirection(phiCenter);
        Vec3 vCenter = cross(n, uCenter); // n x omega / sin(theta), for either handedness
        Vec3 vEdge = -std::sin(phiEdge) * u + std::cos(phiEdge) * v; // towards increasing phi
        addScaled(gradR, vCenter, rotation);
        addScaled(gradT, uCenter * azimuthIntegral, thetaSum);
        addScaled(gradT, vEdge, phiSum);
    }
    const float strataWeight = kPi / float(m * nPhi); // cosine-weighted solid angle per stratum
    for (int c = 0; c < 3; ++c) gradR[c] *= strataWeight;
}

} // namespace rayproc
