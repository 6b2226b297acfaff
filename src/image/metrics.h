// Image error metrics against a reference (the paper: "efficient testing requires that image
// quality be quantitatively measured"). Used by `rayproc diff`, the convergence log of
// `render --reference`, and the tests.
#pragma once

#include "image/image.h"

#include <cstddef>
#include <optional>

namespace rayproc {

// A pixel rectangle [x0, x1) x [y0, y1).
struct CropRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

struct ImageMetrics {
    double rmse = 0;   // sqrt(mean over pixels and channels of (a - b)^2)
    double relmse = 0; // mean over pixels and channels of (a - b)^2 / (b^2 + 0.01), b = reference
    double psnr = 0;   // 10 log10(peak^2 / MSE), peak = 1 (radiance 1 = display white); inf if equal
    double mae = 0;    // mean absolute difference
    double maxAbs = 0; // largest absolute difference
    std::size_t pixels = 0;
};

// Throws ImageIoError if the sizes differ or the crop is empty or outside the image.
ImageMetrics compareImages(const Image& test, const Image& reference,
                           const std::optional<CropRect>& crop = std::nullopt);

} // namespace rayproc
