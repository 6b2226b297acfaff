// Adaptive sampling: after a uniform start, the camera's passes go where the noise is.
//
// Each pixel's noise per sample is read from the film's two half buffers (passes alternate
// between them): v_p = n_p * e_p, with e_p the pixel's term of the image's relMSE estimate
// (Film::pixelRelMse), averaged over the 3x3 window around it, and then the largest such value
// within 2 pixels is taken (a dilation, as Cycles dilates its unconverged pixels); both windows
// stay within the pixel's 16x16 tile, so that a distributed render's ranks, each of which holds
// whole tiles, decide alike. The image's relMSE
// is the mean over pixels of v_p / n_p; for a given count of samples it is least when n_p is
// proportional to sqrt(v_p) (Lagrange), so each pixel is given the need
//     need_p = clamp(K sqrt(v_p), minSpp, maxSpp)
// where K makes the mean of v_p / need_p the target relMSE T (K = M / T, M the mean of
// sqrt(v_p) over the image) or, without a target, the mean need the asked samples per pixel
// N (K = N / M). A pair of passes (one into each half, so the halves stay equal) samples the
// pixels with n_p < need_p; decisions are made between pairs from committed sums only, so the
// image is the same whatever the thread count, and the same on any number of ranks (the image
// means M and the counts are summed over ranks in tile order, as Film::relMseParts).
//
// Like Cycles' adaptive sampling, deciding on a pixel's own samples biases the image's mean:
// a pixel that met a rare bright path (a firefly) takes more samples, which bring its value
// down towards its mean, while a pixel that has not met one yet stays below its mean; with
// uniform sampling the two balance. The dilation samples the region of a firefly, not the
// pixel alone, so its neighbours meet theirs: on the classroom at 64 spp the image mean is
// 0.7% low with it (1.6% without; veach-mis: no change measurable). Windows that leave the
// pixel itself out remove the bias but also the gain on fireflies (docs/performance.md,
// "Adaptive sampling").
#pragma once

#include "engine/film.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace rayproc {

class AdaptiveSampler {
public:
    struct Settings {
        int minSpp = 16;        // every pixel takes at least this many samples first
        int maxSpp = 1 << 20;   // and at most this many
        double targetRelMse = 0; // > 0: the need aims at this relMSE
        // The mean samples per pixel asked (the need aims at it without a target); the render
        // ends once the image's mean reaches it, under a target too.
        int meanSpp = 0;
        // The render's uniform passes' samples per pixel, and the most a pass of a pair takes.
        int passSpp = 1;
        int maxPassSpp = 16;
    };
    AdaptiveSampler(int width, int height, Settings settings);

    // Sums a vector over every rank of a distributed render (Cluster::sumAll); identity alone.
    using SumAll = std::function<void(std::vector<double>&)>;
    struct Decision {
        double meanSpp = 0;            // samples per pixel taken so far, over the whole image
        std::uint64_t activePixels = 0; // pixels the next pair samples, over the whole image
        std::uint64_t pixels = 0;
        // The samples per pixel of each pass of the next pair: about half the image's samples
        // a pass while few pixels are left (a pass has a cost of its own), no more than the
        // mean asked leaves without a target.
        int passSamples = 1;
        bool done = false; // the mean asked is reached, or no pixel is left
    };
    // Reads the film and decides which of this rank's pixels the next pair of passes samples.
    // Every rank calls it at once (it sums over ranks twice). When no pixel of the image falls
    // short of its need, every pixel is sampled (the window's estimate may still say the image
    // is short of its target).
    Decision update(const Film& film, const SumAll& sumAll);
    // Per pixel: 1 when the next pair samples it (every pixel before the first update).
    const std::vector<std::uint8_t>& activeMask() const { return m_mask; }
    const Settings& settings() const { return m_settings; }

private:
    int m_width, m_height;
    Settings m_settings;
    std::vector<float> m_sqrtV;   // per pixel; -1 where it has no estimate yet
    std::vector<std::uint8_t> m_mask;
    // Fills m_sqrtV; per 16x16 tile (row-major) the sum of sqrt(v_p) over its pixels with an
    // estimate, their count and the samples they took.
    std::vector<double> measure(const Film& film);
    // One step towards the scale k of the needs clamp(k sqrt(v_p), minSpp, maxSpp) that meets
    // the budget (mean need = meanSpp) or the target (mean v_p / need_p = targetRelMse).
    double refineScale(double k, const SumAll& sumAll) const;
    static constexpr int kRefinements = 3;
    double m_pixelsMeasured = 0; // over every rank, at the last measure
};

} // namespace rayproc
