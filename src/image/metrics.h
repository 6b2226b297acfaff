// Image error metrics against a reference (the paper: "efficient testing requires that image
// quality be quantitatively measured"). Used by `rayproc diff`, the convergence log of
// `render --reference`, and the tests.
#pragma once

#include "image/image.h"

#include <cstddef>
#include <optional>
#include <string>

namespace rayproc {

// A pixel rectangle [x0, x1) x [y0, y1).
struct CropRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

struct ImageMetrics {
    double rmse = 0;   // sqrt(mean over pixels and channels of (a - b)^2)
    double relmse = 0; // mean over pixels and channels of (a - b)^2 / (b^2 + 0.01), b = reference
    double psnr = 0; // 10 log10(peak^2 / MSE), peak = 1 (radiance 1 = display white); inf if equal
    double mae = 0;  // mean absolute difference
    double maxAbs = 0;                  // largest absolute difference
    std::size_t pixels = 0;             // pixels compared (finite reference)
    std::size_t referenceNonFinite = 0; // pixels skipped: a reference channel is NaN or Inf

    // The public-scene suite's bias measures (docs/public-scenes.md), over the same pixels.
    // meanRel = max over R, G, B of |mean(a) - mean(b)| / mean(b): the worst channel's relative
    // error of the image mean (inf when a reference channel's mean is 0 and a's is not).
    double meanRel = 0;
    // The same per channel and signed, (mean(a) - mean(b)) / mean(b) for R, G, B: the suite holds
    // a scene whose colours differ from the reference for a known reason to a bar per channel.
    double meanRelRgb[3] = {0, 0, 0};
    // blockRel = mean over kMetricBlock^2-pixel blocks (partial edge blocks included) of
    // |A - B| / B, where A and B are the block's averages of a and b over pixels and channels.
    // Blocks with B < kBlockFloor * (the reference's image mean) are skipped: relative error is
    // meaningless in near-black regions.
    double blockRel = 0;
    std::size_t blocks = 0, blocksSkipped = 0;
};

constexpr int kMetricBlock = 32;
constexpr double kBlockFloor = 1e-3;

// Pixels whose reference has a non-finite channel are left out of every sum.
// relmseDenominator, when given, supplies relMSE's b in b^2 + 0.01 instead of the reference
// (the other metrics are unchanged): a render's noise measured against a converged render of
// the same estimator, in units of the full reference (docs/image-comparison.md); a non-finite
// value there makes relMSE NaN.
// Throws ImageIoError if the sizes differ or the crop is empty or outside the image.
ImageMetrics compareImages(const Image& test, const Image& reference,
                           const std::optional<CropRect>& crop = std::nullopt,
                           const Image* relmseDenominator = nullptr);

// The pixels of a reference with a non-finite channel (compareImages leaves them out). Throws
// ImageIoError naming `what` (the file) when no pixel is finite: every metric would be NaN.
std::size_t nonFiniteReferencePixels(const Image& reference, const std::string& what);

// The reference at 1/factor of its resolution: each output pixel is the average of a
// factor x factor block, over the block's finite pixels (NaN if it has none, so the comparison
// skips it). The size must be divisible by factor.
Image boxDownsample(const Image& image, int factor);

// The integer f >= 1 with reference size = f * test size on both axes, or 0 if there is none.
int downsampleFactor(const Image& test, const Image& reference);

} // namespace rayproc
