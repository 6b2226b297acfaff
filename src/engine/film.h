// Film: per-pixel accumulation that is deterministic whatever the thread count. Contributions
// of a pass are summed in 128-bit fixed point (integer addition is associative, so the order in
// which threads add does not change a bit); at the end of each pass the sums are folded into
// double precision in pixel order. The 128-bit sum is two 64-bit atomics: a low word that
// wraps and a high word that receives the low word's carries, so a pixel's sum cannot wrap
// for any count of contributions a pass can make.
//
// The fixed point's unit follows the scene's brightness (exponentFor): the brightest light's
// radiance is 2^36 to 2^37 units, so a scene's image is the same whether its emission is 1e-30
// or 1e30, and times a power of two it is the image times that power to the bit (a fixed unit
// of 2^-32 rounded the Cornell box's dim pixels by 6.8% at 1e-6 of its emission and to black
// at 1e-15). Every rank and thread uses the same exponent: determinism is unchanged.
#pragma once

#include "core/math.h"
#include "engine/stats.h"
#include "image/image.h"

#include <atomic>
#include <cstdint>
#include <mutex>
#include <vector>

namespace rayproc {

class Film {
public:
    // By default 2^32 units per radiance unit: resolution 2.3e-10. One contribution is clamped
    // to +-2^96 units (by default 2^64 radiance, 1.8e19; the sun's luminance is 1.6e9) and
    // counted; a pixel's pass sum holds 2^31 such contributions before the 128-bit sum could
    // wrap.
    static constexpr int kDefaultExponent = 32;
    static constexpr double kFixedScale = 4294967296.0;
    static constexpr double kFixedLimit = 18446744073709551616.0;

    // 2^exponent units per radiance unit.
    Film(int width, int height, int exponent = kDefaultExponent);
    // The exponent for a scene whose lights give radiance of about `brightest`
    // (LightSet::radianceScale): brightest is 2^36 to 2^37 units (exponent 32 for 16 <=
    // brightest < 32, the Cornell box); resolution 2^-36 of the brightest light, room for 2^59
    // times it in one contribution. kDefaultExponent when there is no light.
    static constexpr int kBrightestExponent = 36;
    static int exponentFor(double brightest);
    int exponent() const { return m_exponent; }
    // The largest |radiance| one contribution may carry; beyond, it is clamped and counted.
    double fixedLimit() const { return m_limit; }
    int width() const { return m_width; }
    int height() const { return m_height; }

    // Adds radiance to a pixel of the current pass; NaN/Inf are counted and discarded.
    void add(std::uint32_t pixel, const Vec3& radiance, ThreadStats& stats);
    // Records that a camera sample of the current pass was emitted for this pixel.
    void addSample(std::uint32_t pixel) {
        m_passSamples[pixel].fetch_add(1, std::memory_order_relaxed);
    }
    // Folds the pass into the totals; call when no ray of the pass is in flight. With half
    // buffers enabled, the pass also goes to half `half` (0 or 1).
    // `passSums`, when given, receives the pass's own sums (3 per pixel).
    void commitPass(int half = 0, std::vector<double>* passSums = nullptr);

    // Two half buffers: passes alternate between them, so each holds an independent estimate
    // made of half the samples. Their difference measures the image's noise without a
    // reference (relMseEstimate). Costs 32 bytes per pixel; call before the first pass.
    void enableHalfBuffers();
    bool hasHalfBuffers() const { return !m_halfSum[0].empty(); }
    // The variance part of the image's relMSE, estimated from the halves A and B: with
    // F = (A + B) / 2, mean over pixels and channels of (A - B)^2 / 4 / (F^2 + 0.01) (each half
    // has twice the variance of F). NaN until both halves hold samples. Bias (gi's photon map
    // and cache) is not in it.
    double relMseEstimate() const;
    // The estimate in parts: per 16x16 tile (row-major tile order) the sum of the per-pixel
    // terms at [2 t] and their count at [2 t + 1]. Distributed renders add the parts of every
    // rank (a tile is one rank's) and take relMseFromParts, which sums them in tile order: the
    // same additions as one process, so the same estimate to the bit.
    std::vector<double> relMseParts() const;
    static double relMseFromParts(const std::vector<double>& parts);
    // One pixel's term of the estimate, averaged over its channels (adaptive sampling weighs
    // pixels by it); NaN while a half holds no sample of it.
    double pixelRelMse(std::size_t pixel) const;

    // The committed totals: 3 sums per pixel and samples per pixel. A distributed render adds
    // every rank's (each pixel has one owner; the others add exact zeros) and resolves them.
    const std::vector<double>& sums() const { return m_sum; }
    const std::vector<std::uint64_t>& sampleCounts() const { return m_samples; }
    static Image resolve(int width, int height, const std::vector<double>& sums,
                         const std::vector<std::uint64_t>& samples);

    // The image so far: each pixel divided by the samples it received; pixels with none black.
    Image resolve() const;
    // The same with the current pass's contributions so far, for display while the pass runs
    // (another thread may call it; tiles appear as they finish). Not for results: a pixel may
    // hold some of its samples' paths and not others'.
    Image resolveInProgress() const;
    std::size_t pixelsWithoutSamples() const;
    std::uint64_t samplesOf(std::uint32_t pixel) const { return m_samples[pixel]; }

private:
    int m_width, m_height;
    int m_exponent;
    double m_scale, m_limit; // 2^exponent, 2^(96 - exponent)
    std::vector<std::atomic<std::uint64_t>> m_passLow;    // 3 per pixel, fixed point, low word
    std::vector<std::atomic<std::int64_t>> m_passHigh;    // 3 per pixel, high word and carries
    std::vector<std::atomic<std::uint32_t>> m_passSamples; // per pixel
    std::vector<double> m_sum;                             // 3 per pixel
    std::vector<std::uint64_t> m_samples;                  // per pixel
    std::vector<double> m_halfSum[2];                      // 3 per pixel, when enabled
    std::vector<std::uint32_t> m_halfSamples[2];           // per pixel, when enabled
    mutable std::mutex m_commitMutex; // commitPass against resolveInProgress
};

} // namespace rayproc
