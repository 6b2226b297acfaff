// The one sample generator of the stages that shade a hit (path vertices, the shadow stage's
// light samples, gi's gather and correction rays): Owen-scrambled Sobol points over a pixel's
// samples, one sequence for every (pixel, depth, branch tag, pair of dimensions), so that at a
// given depth a pixel's samples are stratified at every power-of-two prefix (kernels/sobol.h).
// Every number is a pure function of (seed, pixel, depth, tag, dimension, index): images stay
// bit-identical whatever thread, packet width or MPI rank traces a sample. Without Sobol points
// (--no-stratification, or a lane that is not a pixel's sample) the numbers are independent
// ones of the lane's own stream (its rngKey).
#pragma once

#include "engine/ray_batch.h"
#include "kernels/random.h"
#include "kernels/sobol.h"

#include <cstdint>

namespace rayproc {

// The render seed's key, hashed once per batch.
inline std::uint64_t sampleSeedKey(std::uint64_t seed) {
    return kernels::mix64(seed ^ 0x5851f42d4c957f2dULL);
}

class SampleNumbers {
public:
    // tag: which branch of a pixel's tree of rays at this depth (0 for path mode's one path;
    // the shadow stage passes the incoming ray's kind, so reflected and refracted branches at
    // one depth draw different sequences).
    SampleNumbers(const RayBatch& b, int i, bool sobol, std::uint64_t seedKey,
                  std::uint32_t tag = 0)
        : m_key(sobol ? kernels::mix64(seedKey ^
                                       ((std::uint64_t(b.pixel[i]) << 8 | b.depth[i]) *
                                        0x9e3779b97f4a7c15ULL) ^
                                       (std::uint64_t(tag) * 0xd1342543de82ef95ULL))
                      : b.rngKey[i]),
          m_sample(b.sample[i]), m_reversedSample(kernels::reverseBits(b.sample[i])),
          m_sobol(sobol) {}

    bool sobol() const { return m_sobol; }
    std::uint32_t sample() const { return m_sample; }

    // The pair of dimensions `dim` of this lane's pixel sample.
    Vec2 get2D(std::uint32_t dim) const {
        if (m_sobol)
            return kernels::owenSobol2DReversed(m_reversedSample, pairKey(dim));
        return {kernels::uniform(m_key, dim), kernels::uniform(m_key, dim + 1)};
    }
    // Three pairs at once (a path vertex's): get2D(dims[k]) in out[k], the three Sobol pairs
    // eight lanes wide (kernels::owenSobol2DReversed3).
    void get2D(const std::uint32_t (&dims)[3], Vec2 (&out)[3]) const {
        if (!m_sobol) {
            for (int k = 0; k < 3; ++k) out[k] = get2D(dims[k]);
            return;
        }
        const std::uint64_t keys[3] = {pairKey(dims[0]), pairKey(dims[1]), pairKey(dims[2])};
        kernels::owenSobol2DReversed3(m_reversedSample, keys, out);
    }
    // Sample s of n that this pixel sample takes in the pair `dim` (a hit's n light samples):
    // point sample * n + s of the pair's sequence, so that the n of one pixel sample are an
    // aligned block (a net when n is a power of two) and a pixel's samples together are one
    // sequence. Independent numbers without Sobol points.
    Vec2 get2D(std::uint32_t dim, std::uint32_t s, std::uint32_t n) const {
        if (m_sobol) return kernels::owenSobol2D(m_sample * n + s, pairKey(dim));
        std::uint64_t key = kernels::hashCombine(m_key, dim);
        return {kernels::uniform(key, 2 * s), kernels::uniform(key, 2 * s + 1)};
    }

private:
    std::uint64_t pairKey(std::uint32_t dim) const { return m_key ^ (dim * 0x9e3779b97f4a7c15ULL); }

    std::uint64_t m_key;
    std::uint32_t m_sample, m_reversedSample;
    bool m_sobol;
};

} // namespace rayproc
