#include "image/metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace rayproc {

namespace {

bool finitePixel(const float* p) {
    return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

// Sums of a and b over the finite-reference pixels of a rectangle, per channel.
struct Sums {
    std::array<double, 3> a{}, b{};
    std::size_t n = 0;
};

Sums sumsOver(const Image& a, const Image& b, int x0, int y0, int x1, int y1) {
    Sums s;
    for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
            const float* pb = b.at(x, y);
            if (!finitePixel(pb)) continue;
            const float* pa = a.at(x, y);
            for (int c = 0; c < 3; ++c) {
                s.a[c] += pa[c];
                s.b[c] += pb[c];
            }
            ++s.n;
        }
    }
    return s;
}

// |mean a - mean b| / mean b per channel, the worst channel; and the block measure.
void biasMetrics(const Image& a, const Image& b, const CropRect& r, ImageMetrics& m) {
    Sums all = sumsOver(a, b, r.x0, r.y0, r.x1, r.y1);
    if (all.n == 0) {
        m.meanRel = m.blockRel = std::numeric_limits<double>::quiet_NaN();
        for (double& v : m.meanRelRgb) v = std::numeric_limits<double>::quiet_NaN();
        return;
    }
    double refMean = 0; // over pixels and channels
    m.meanRel = 0;
    for (int c = 0; c < 3; ++c) {
        double ma = all.a[c] / double(all.n), mb = all.b[c] / double(all.n);
        m.meanRelRgb[c] = (ma - mb) / mb;
        double rel = std::abs(ma - mb) / mb; // inf or NaN for a black channel: no silent pass
        // A NaN, once seen in any channel, stays (std::max would drop it for a later channel).
        m.meanRel = std::isnan(m.meanRel) || std::isnan(rel) ? std::numeric_limits<double>::quiet_NaN()
                                                             : std::max(m.meanRel, rel);
        refMean += mb / 3.0;
    }
    double sum = 0;
    for (int by = r.y0; by < r.y1; by += kMetricBlock) {
        for (int bx = r.x0; bx < r.x1; bx += kMetricBlock) {
            Sums s = sumsOver(a, b, bx, by, std::min(bx + kMetricBlock, r.x1),
                              std::min(by + kMetricBlock, r.y1));
            double blockA = (s.a[0] + s.a[1] + s.a[2]) / (3.0 * double(s.n));
            double blockB = (s.b[0] + s.b[1] + s.b[2]) / (3.0 * double(s.n));
            if (s.n == 0 || !(blockB >= kBlockFloor * refMean)) {
                ++m.blocksSkipped;
                continue;
            }
            sum += std::abs(blockA - blockB) / blockB;
            ++m.blocks;
        }
    }
    m.blockRel = m.blocks > 0 ? sum / double(m.blocks) : std::numeric_limits<double>::quiet_NaN();
}

} // namespace

std::size_t nonFiniteReferencePixels(const Image& reference, const std::string& what) {
    std::size_t pixels = std::size_t(reference.width) * std::size_t(reference.height), bad = 0;
    for (std::size_t p = 0; p < pixels; ++p) bad += !finitePixel(&reference.pixels[p * 3]);
    if (pixels > 0 && bad == pixels)
        throw ImageIoError(what + ": no pixel of the reference is finite (every one has a NaN or "
                                  "infinite channel): there is nothing to compare against");
    return bad;
}

ImageMetrics compareImages(const Image& a, const Image& b, const std::optional<CropRect>& crop,
                           const Image* relmseDenominator) {
    for (const Image* other : {&b, relmseDenominator})
        if (other && (a.width != other->width || a.height != other->height))
            throw ImageIoError("images differ in size: " + std::to_string(a.width) + "x" +
                               std::to_string(a.height) + " vs " + std::to_string(other->width) +
                               "x" + std::to_string(other->height));
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
    std::size_t n = 0, skipped = 0;
    for (int y = r.y0; y < r.y1; ++y) {
        for (int x = r.x0; x < r.x1; ++x) {
            const float* pa = a.at(x, y);
            const float* pb = b.at(x, y);
            const float* pd = relmseDenominator ? relmseDenominator->at(x, y) : pb;
            if (!finitePixel(pb)) {
                ++skipped;
                continue;
            }
            for (int c = 0; c < 3; ++c) {
                double d = double(pa[c]) - double(pb[c]);
                se += d * d;
                rel += d * d / (double(pd[c]) * pd[c] + 0.01);
                ae += std::abs(d);
                mx = std::isnan(d) || std::isnan(mx) ? std::numeric_limits<double>::quiet_NaN()
                                                     : std::max(mx, std::abs(d));
            }
            ++n;
        }
    }
    ImageMetrics m;
    m.pixels = n;
    m.referenceNonFinite = skipped;
    double count = double(n) * 3.0;
    double mse = se / count;
    m.rmse = std::sqrt(mse);
    m.relmse = rel / count;
    m.mae = ae / count;
    m.maxAbs = mx;
    // Equal images: infinite PSNR; a NaN in the test image (or nothing compared): NaN, not inf.
    m.psnr = mse > 0     ? 10.0 * std::log10(1.0 / mse)
             : mse == 0 ? std::numeric_limits<double>::infinity()
                        : std::numeric_limits<double>::quiet_NaN();
    biasMetrics(a, b, r, m);
    return m;
}

Image boxDownsample(const Image& image, int factor) {
    if (factor < 1 || image.width % factor != 0 || image.height % factor != 0)
        throw ImageIoError("cannot box-downsample a " + std::to_string(image.width) + "x" +
                           std::to_string(image.height) + " image by " + std::to_string(factor));
    Image out(image.width / factor, image.height / factor);
    for (int y = 0; y < out.height; ++y) {
        for (int x = 0; x < out.width; ++x) {
            std::array<double, 3> sum{};
            int n = 0;
            for (int j = 0; j < factor; ++j) {
                for (int i = 0; i < factor; ++i) {
                    const float* p = image.at(x * factor + i, y * factor + j);
                    if (!finitePixel(p)) continue;
                    for (int c = 0; c < 3; ++c) sum[c] += p[c];
                    ++n;
                }
            }
            for (int c = 0; c < 3; ++c)
                out.at(x, y)[c] =
                    n > 0 ? float(sum[c] / n) : std::numeric_limits<float>::quiet_NaN();
        }
    }
    return out;
}

int downsampleFactor(const Image& test, const Image& reference) {
    if (test.width <= 0 || test.height <= 0) return 0;
    if (reference.width % test.width != 0 || reference.height % test.height != 0) return 0;
    int f = reference.width / test.width;
    return reference.height / test.height == f ? f : 0;
}

} // namespace rayproc
