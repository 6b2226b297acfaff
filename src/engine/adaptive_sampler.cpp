#include "engine/adaptive_sampler.h"

#include <algorithm>
#include <cmath>

namespace rayproc {

namespace {
constexpr int kTile = 16; // the film's and the camera emitter's tiles
// The need of a pixel follows the largest smoothed noise within this many pixels (in its tile).
constexpr int kDilation = 2;
} // namespace

AdaptiveSampler::AdaptiveSampler(int width, int height, Settings settings)
    : m_width(width), m_height(height), m_settings(settings),
      m_sqrtV(std::size_t(width) * std::size_t(height), -1.0f),
      m_mask(std::size_t(width) * std::size_t(height), 1) {}

std::vector<double> AdaptiveSampler::measure(const Film& film) {
    const int tilesX = (m_width + kTile - 1) / kTile, tilesY = (m_height + kTile - 1) / kTile;
    std::vector<double> parts(std::size_t(tilesX) * std::size_t(tilesY) * 3, 0.0);
    // Noise per sample of each pixel (NaN without an estimate).
    std::vector<double> v(m_sqrtV.size());
    for (std::size_t p = 0; p < v.size(); ++p)
        v[p] = film.pixelRelMse(p) * double(film.samplesOf(std::uint32_t(p)));
    std::vector<float> smooth(m_sqrtV.size(), -1.0f);
    for (int ty = 0; ty < tilesY; ++ty)
        for (int tx = 0; tx < tilesX; ++tx) {
            const int x0 = tx * kTile, y0 = ty * kTile;
            const int x1 = std::min(x0 + kTile, m_width), y1 = std::min(y0 + kTile, m_height);
            // The square root of the mean over the 3x3 window (within the tile)...
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) {
                    const std::size_t p = std::size_t(y) * std::size_t(m_width) + std::size_t(x);
                    if (std::isnan(v[p])) continue;
                    double sum = 0;
                    int n = 0;
                    for (int wy = std::max(y - 1, y0); wy <= std::min(y + 1, y1 - 1); ++wy)
                        for (int wx = std::max(x - 1, x0); wx <= std::min(x + 1, x1 - 1); ++wx) {
                            double w = v[std::size_t(wy) * std::size_t(m_width) + std::size_t(wx)];
                            if (std::isnan(w)) continue;
                            sum += w;
                            ++n;
                        }
                    smooth[p] = float(std::sqrt(sum / n)); // n >= 1: the pixel itself
                }
            // ...then the largest of those within kDilation pixels: a pixel whose own samples
            // have not yet met a rare bright path (a firefly) a neighbour met keeps sampling.
            double sumSqrt = 0, count = 0, samples = 0;
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) {
                    const std::size_t p = std::size_t(y) * std::size_t(m_width) + std::size_t(x);
                    if (smooth[p] < 0) {
                        m_sqrtV[p] = -1.0f;
                        continue;
                    }
                    float s = smooth[p];
                    for (int wy = std::max(y - kDilation, y0); wy <= std::min(y + kDilation, y1 - 1); ++wy)
                        for (int wx = std::max(x - kDilation, x0); wx <= std::min(x + kDilation, x1 - 1);
                             ++wx)
                            s = std::max(s, smooth[std::size_t(wy) * std::size_t(m_width) + std::size_t(wx)]);
                    m_sqrtV[p] = s;
                    sumSqrt += double(s);
                    count += 1;
                    samples += double(film.samplesOf(std::uint32_t(p)));
                }
            const std::size_t t = std::size_t(ty) * std::size_t(tilesX) + std::size_t(tx);
            parts[3 * t] = sumSqrt;
            parts[3 * t + 1] = count;
            parts[3 * t + 2] = samples;
        }
    return parts;
}

namespace {
// Sums per-tile parts (`stride` values per tile) over the ranks, then folds them in tile
// order: the same additions on any number of ranks.
std::vector<double> foldParts(std::vector<double> parts, std::size_t stride,
                              const AdaptiveSampler::SumAll& sumAll) {
    if (sumAll) sumAll(parts);
    std::vector<double> total(stride, 0.0);
    for (std::size_t t = 0; t + stride <= parts.size(); t += stride)
        for (std::size_t i = 0; i < stride; ++i) total[i] += parts[t + i];
    return total;
}
} // namespace

double AdaptiveSampler::refineScale(double k, const SumAll& sumAll) const {
    // The needs clamp(k s_p, lo, hi): with some pixels at a bound, the scale that meets the
    // budget (or the target) is found again over the pixels between the bounds.
    const double lo = m_settings.minSpp, hi = m_settings.maxSpp;
    const int tilesX = (m_width + kTile - 1) / kTile, tilesY = (m_height + kTile - 1) / kTile;
    std::vector<double> parts(std::size_t(tilesX) * std::size_t(tilesY) * 2, 0.0);
    for (int y = 0; y < m_height; ++y)
        for (int x = 0; x < m_width; ++x) {
            const float s = m_sqrtV[std::size_t(y) * std::size_t(m_width) + std::size_t(x)];
            if (s < 0) continue;
            const std::size_t t = std::size_t(y / kTile) * std::size_t(tilesX) + std::size_t(x / kTile);
            const double need = k * double(s);
            if (need > lo && need < hi) {
                parts[2 * t] += double(s);
            } else {
                const double bound = need <= lo ? lo : hi;
                // What the pixel takes of the budget, or gives to the target's relMSE.
                parts[2 * t + 1] += m_settings.targetRelMse > 0 ? double(s) * double(s) / bound
                                                                : bound;
            }
        }
    std::vector<double> total = foldParts(std::move(parts), 2, sumAll);
    if (!(total[0] > 0)) return k;
    const double pixels = m_pixelsMeasured;
    if (m_settings.targetRelMse > 0) {
        const double left = m_settings.targetRelMse * pixels - total[1];
        return left > 0 ? total[0] / left : 1e30; // the bounds alone miss it: all at most
    }
    const double left = double(m_settings.meanSpp) * pixels - total[1];
    return left > 0 ? left / total[0] : k;
}

AdaptiveSampler::Decision AdaptiveSampler::update(const Film& film, const SumAll& sumAll) {
    std::vector<double> total = foldParts(measure(film), 3, sumAll);
    const double sumSqrt = total[0], pixels = total[1], samples = total[2];
    m_pixelsMeasured = pixels;
    Decision d;
    d.pixels = std::uint64_t(pixels);
    d.meanSpp = pixels > 0 ? samples / pixels : 0;
    const double meanSqrt = pixels > 0 ? sumSqrt / pixels : 0;
    double k = 0;
    if (meanSqrt > 0 && std::isfinite(meanSqrt)) {
        k = m_settings.targetRelMse > 0 ? meanSqrt / m_settings.targetRelMse
                                        : double(m_settings.meanSpp) / meanSqrt;
        for (int i = 0; i < kRefinements; ++i) k = refineScale(k, sumAll);
    }
    std::uint64_t active = 0;
    for (std::size_t p = 0; p < m_mask.size(); ++p) {
        const std::uint64_t n = film.samplesOf(std::uint32_t(p));
        bool on;
        if (m_sqrtV[p] < 0 || !(k > 0)) {
            on = true; // no estimate yet (or no noise anywhere): sample as before
        } else {
            double need = std::clamp(k * double(m_sqrtV[p]), double(m_settings.minSpp),
                                     double(m_settings.maxSpp));
            on = double(n) < need;
        }
        m_mask[p] = on ? 1 : 0;
        // Only pixels this rank renders count (the others have no samples here).
        if (on && n > 0) ++active;
    }
    std::vector<double> counted{double(active)};
    if (sumAll) sumAll(counted);
    d.activePixels = std::uint64_t(counted[0]);
    if (d.activePixels == 0) {
        std::fill(m_mask.begin(), m_mask.end(), std::uint8_t(1));
        d.activePixels = d.pixels;
    }
    const double activeShare = d.pixels > 0 ? double(d.activePixels) / double(d.pixels) : 0;
    d.done = d.meanSpp >= m_settings.meanSpp || d.activePixels == 0;
    double perPass = double(m_settings.passSpp) / std::max(2 * activeShare, 1e-9);
    if (m_settings.targetRelMse <= 0)
        perPass = std::min(perPass, (m_settings.meanSpp - d.meanSpp) / std::max(2 * activeShare, 1e-9));
    d.passSamples = int(std::clamp(std::ceil(perPass), 1.0, double(m_settings.maxPassSpp)));
    return d;
}

} // namespace rayproc
