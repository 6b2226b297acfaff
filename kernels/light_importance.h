// The importance of lights' bounds at a shading point (LightBounds, src/lighting/light_bounds.h):
// phi cos(theta') / max(d^2, r^2), theta' = max(0, thetaW - thetaO - thetaB), 0 past thetaE.
// One light at a time, and eight at a time with AVX2 over bounds stored by component; both do
// the same IEEE operations in the same order, so they agree to the bit (the light sampler's
// choice and its pmf may use either).
#pragma once

#include <immintrin.h>

#include <algorithm>
#include <cmath>

namespace rayproc::kernels {

// The cases, in order of the selects: p inside the bound or the cone (a full-sphere cone has
// cosO = -1), or the bound reaching into the cone: theta' = 0; else cos(theta') from the angle
// differences' cosines and sines (no inverse trigonometry), and 0 at or past thetaE.
inline float boundsImportance(float px, float py, float pz, float cx, float cy, float cz,
                              float r2, float phi, float ax, float ay, float az, float cosO,
                              float sinO, float cosE, float twoSided) {
    float dx = px - cx, dy = py - cy, dz = pz - cz;
    float dist2 = dx * dx + dy * dy + dz * dz;
    float clamped = std::max(std::max(dist2, r2), 1e-30f);
    float safe = std::max(dist2, 1e-30f);
    float cosW = (ax * dx + ay * dy + az * dz) * (1.0f / std::sqrt(safe));
    if (twoSided > 0) cosW = std::abs(cosW);
    cosW = std::min(std::max(cosW, -1.0f), 1.0f);
    float sinW = std::sqrt(std::max(0.0f, 1 - cosW * cosW));
    float cosWO = cosW * cosO + sinW * sinO, sinWO = sinW * cosO - cosW * sinO;
    float sinB2 = std::min(r2 / safe, 1.0f);
    float cosB = std::sqrt(1 - sinB2), sinB = std::sqrt(sinB2);
    bool inside = dist2 <= r2 || cosW >= cosO || cosWO >= cosB;
    float cosT = inside ? 1.0f : cosWO * cosB + sinWO * sinB;
    float weight = phi * cosT / clamped;
    return (inside || cosT > cosE) && phi > 0 ? weight : 0.0f;
}

// Bounds by component, eight lanes at index k of each array.
struct BoundsLanes {
    const float *cx, *cy, *cz, *r2, *phi, *ax, *ay, *az, *cosO, *sinO, *cosE, *twoSided;
};

inline void boundsImportance8(float px, float py, float pz, const BoundsLanes& b, int k,
                              float* out) {
    const __m256 one = _mm256_set1_ps(1.0f), zero = _mm256_setzero_ps();
    const __m256 tiny = _mm256_set1_ps(1e-30f);
    __m256 dx = _mm256_sub_ps(_mm256_set1_ps(px), _mm256_loadu_ps(b.cx + k));
    __m256 dy = _mm256_sub_ps(_mm256_set1_ps(py), _mm256_loadu_ps(b.cy + k));
    __m256 dz = _mm256_sub_ps(_mm256_set1_ps(pz), _mm256_loadu_ps(b.cz + k));
    __m256 dist2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)),
                                 _mm256_mul_ps(dz, dz));
    __m256 r2 = _mm256_loadu_ps(b.r2 + k);
    __m256 clamped = _mm256_max_ps(_mm256_max_ps(dist2, r2), tiny);
    __m256 safe = _mm256_max_ps(dist2, tiny);
    __m256 dot = _mm256_add_ps(
        _mm256_add_ps(_mm256_mul_ps(_mm256_loadu_ps(b.ax + k), dx),
                      _mm256_mul_ps(_mm256_loadu_ps(b.ay + k), dy)),
        _mm256_mul_ps(_mm256_loadu_ps(b.az + k), dz));
    __m256 cosW = _mm256_mul_ps(dot, _mm256_div_ps(one, _mm256_sqrt_ps(safe)));
    __m256 absW = _mm256_andnot_ps(_mm256_set1_ps(-0.0f), cosW);
    __m256 two = _mm256_cmp_ps(_mm256_loadu_ps(b.twoSided + k), zero, _CMP_GT_OQ);
    cosW = _mm256_blendv_ps(cosW, absW, two);
    cosW = _mm256_min_ps(_mm256_max_ps(cosW, _mm256_set1_ps(-1.0f)), one);
    __m256 sinW = _mm256_sqrt_ps(_mm256_max_ps(zero, _mm256_sub_ps(one, _mm256_mul_ps(cosW, cosW))));
    __m256 cosO = _mm256_loadu_ps(b.cosO + k), sinO = _mm256_loadu_ps(b.sinO + k);
    __m256 cosWO = _mm256_add_ps(_mm256_mul_ps(cosW, cosO), _mm256_mul_ps(sinW, sinO));
    __m256 sinWO = _mm256_sub_ps(_mm256_mul_ps(sinW, cosO), _mm256_mul_ps(cosW, sinO));
    __m256 sinB2 = _mm256_min_ps(_mm256_div_ps(r2, safe), one);
    __m256 cosB = _mm256_sqrt_ps(_mm256_sub_ps(one, sinB2)), sinB = _mm256_sqrt_ps(sinB2);
    __m256 inside = _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(dist2, r2, _CMP_LE_OQ),
                                              _mm256_cmp_ps(cosW, cosO, _CMP_GE_OQ)),
                                 _mm256_cmp_ps(cosWO, cosB, _CMP_GE_OQ));
    __m256 cosT = _mm256_blendv_ps(
        _mm256_add_ps(_mm256_mul_ps(cosWO, cosB), _mm256_mul_ps(sinWO, sinB)), one, inside);
    __m256 phi = _mm256_loadu_ps(b.phi + k);
    __m256 weight = _mm256_div_ps(_mm256_mul_ps(phi, cosT), clamped);
    __m256 keep = _mm256_and_ps(
        _mm256_or_ps(inside, _mm256_cmp_ps(cosT, _mm256_loadu_ps(b.cosE + k), _CMP_GT_OQ)),
        _mm256_cmp_ps(phi, zero, _CMP_GT_OQ));
    _mm256_storeu_ps(out, _mm256_and_ps(weight, keep));
}

} // namespace rayproc::kernels
