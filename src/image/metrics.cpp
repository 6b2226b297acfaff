#include "image/metrics.h"

#include <cmath>
#include <limits>
#include <string>

namespace rayproc {

ImageMetrics compareImages(const Image& a, const Image& b, const std::optional<CropRect>& crop) {
    if (a.width != b.width || a.height != b.height)
        throw ImageIoError("images differ in size: " + std::to_string(a.width) + "x" +
                           std::to_string(a.height) + " vs " + std::to_string(b.width) + "x" +
                           std::to_string(b.height));
    CropRect r{0, 0, a.width, a.height};
    if (crop) {
        r = *crop;
        if (r.x0 < 0 || r.y0 < 0 || r.x1 > a.width || r.y1 > a.height || r.x0 >= r.x1 ||
            r.y0 >= r.y1)
            throw ImageIoError("crop " + std::to_string(r.x0) + " " + std::to_string(r.y0) + " " +
                               std::to_string(r.x1) + " " + std::to_string(r.y1) +
                               " is empty or outside the " + std::to_string(a.width) + "x" +
                               std::to_string(a.height) + " image");
    }
    double se = 0, rel = 0, ae = 0, mx = 0;
    std::size_t n = 0;
    for (int y = r.y0; y < r.y1; ++y) {
        for (int x = r.x0; x < r.x1; ++x) {
            const float* pa = a.at(x, y);
            const float* pb = b.at(x, y);
            for (int c = 0; c < 3; ++c) {
                double d = double(pa[c]) - double(pb[c]);
                se += d * d;
                rel += d * d / (double(pb[c]) * pb[c] + 0.01);
                ae += std::abs(d);
                mx = std::max(mx, std::abs(d));
            }
            ++n;
        }
    }
    ImageMetrics m;
    m.pixels = n;
    double count = double(n) * 3.0;
    double mse = se / count;
    m.rmse = std::sqrt(mse);
    m.relmse = rel / count;
    m.mae = ae / count;
    m.maxAbs = mx;
    m.psnr = mse > 0 ? 10.0 * std::log10(1.0 / mse) : std::numeric_limits<double>::infinity();
    return m;
}

} // namespace rayproc
