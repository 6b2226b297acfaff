#include "engine/film.h"

#include <cmath>

namespace rayproc {

Film::Film(int width, int height)
    : m_width(width), m_height(height), m_pass(std::size_t(width) * height * 3),
      m_passSamples(std::size_t(width) * height), m_sum(std::size_t(width) * height * 3, 0.0),
      m_samples(std::size_t(width) * height, 0) {}

void Film::add(std::uint32_t pixel, const Vec3& radiance, ThreadStats& stats) {
    if (!isFinite(radiance)) {
        ++stats.invalidSamples;
        return;
    }
    for (int c = 0; c < 3; ++c) {
        double v = double(radiance[c]);
        if (v == 0.0) continue;
        if (std::abs(v) >= kFixedLimit) {
            ++stats.clampedSamples;
            v = std::copysign(std::nextafter(kFixedLimit, 0.0), v); // 2^63 overflows int64
        }
        auto fixed = std::int64_t(std::llround(v * kFixedScale));
        m_pass[std::size_t(pixel) * 3 + c].fetch_add(fixed, std::memory_order_relaxed);
    }
}

void Film::commitPass() {
    std::size_t n = m_samples.size();
    for (std::size_t p = 0; p < n; ++p) {
        m_samples[p] += m_passSamples[p].exchange(0, std::memory_order_relaxed);
        for (int c = 0; c < 3; ++c) {
            std::int64_t v = m_pass[p * 3 + c].exchange(0, std::memory_order_relaxed);
            m_sum[p * 3 + c] += double(v) / kFixedScale;
        }
    }
}

Image Film::resolve() const {
    Image img(m_width, m_height);
    for (std::size_t p = 0; p < m_samples.size(); ++p) {
        if (m_samples[p] == 0) continue;
        double inv = 1.0 / double(m_samples[p]);
        for (int c = 0; c < 3; ++c) img.pixels[p * 3 + c] = float(m_sum[p * 3 + c] * inv);
    }
    return img;
}

std::size_t Film::pixelsWithoutSamples() const {
    std::size_t n = 0;
    for (auto s : m_samples) n += s == 0;
    return n;
}

} // namespace rayproc
