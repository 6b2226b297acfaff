#include "gi/caustic_pixel_radius.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace rayproc {

namespace {
constexpr double kSeedUnit = 65536.0; // the seed's fixed point: r^2 / maxRadius^2 in 2^-16
// Saturating add: a sum that would pass 2^32 stays at its largest value.
void addSaturating(std::atomic<std::uint32_t>& a, std::uint32_t v) {
    std::uint32_t old = a.load(std::memory_order_relaxed);
    std::uint32_t next;
    do {
        next = old > 0xffffffffu - v ? 0xffffffffu : old + v;
    } while (!a.compare_exchange_weak(old, next, std::memory_order_relaxed));
}
} // namespace

CausticPixelRadius::CausticPixelRadius(std::size_t pixels, float maxRadius, double alpha)
    : m_maxRadius(maxRadius), m_alpha(alpha), m_radius(pixels, maxRadius), m_count(pixels, 0.0f),
      m_lookups(new std::atomic<std::uint32_t>[pixels]),
      m_sum(new std::atomic<std::uint32_t>[pixels]),
      m_seedPhotons(new std::atomic<std::uint32_t>[pixels]) {
    for (std::size_t j = 0; j < pixels; ++j) {
        m_lookups[j].store(0, std::memory_order_relaxed);
        m_sum[j].store(0, std::memory_order_relaxed);
        m_seedPhotons[j].store(0, std::memory_order_relaxed);
    }
}

void CausticPixelRadius::seed(std::uint32_t pixel, float radius2, std::uint32_t photons) {
    if (pixel >= m_radius.size()) return;
    addSaturating(m_seedPhotons[pixel], photons);
    double r2 = double(m_maxRadius) * double(m_maxRadius);
    double unit = std::clamp(double(radius2) / r2, 0.0, 1.0);
    addSaturating(m_sum[pixel], std::uint32_t(std::lround(unit * kSeedUnit)));
    addSaturating(m_lookups[pixel], 1);
}

void CausticPixelRadius::found(std::uint32_t pixel, std::uint32_t photons) {
    if (pixel >= m_radius.size()) return;
    addSaturating(m_sum[pixel], photons);
    addSaturating(m_lookups[pixel], 1);
}

void CausticPixelRadius::endPass(int samples) {
    const int s = std::max(samples, 1);
    const bool seeding = m_seeding;
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, m_radius.size(), 4096),
        [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t j = range.begin(); j < range.end(); ++j) {
                const std::uint32_t lookups = m_lookups[j].exchange(0, std::memory_order_relaxed);
                const double sum = double(m_sum[j].exchange(0, std::memory_order_relaxed));
                const double seedPhotons =
                    double(m_seedPhotons[j].exchange(0, std::memory_order_relaxed));
                if (lookups == 0) continue;
                if (seeding) {
                    // R_j^2: the mean of the visible points' k-th neighbour distances squared.
                    // At least one step of the fixed point (1/256 of the largest radius): never 0.
                    double unit = std::max(sum / (kSeedUnit * double(lookups)), 1.0 / kSeedUnit);
                    m_radius[j] = float(double(m_maxRadius) * std::sqrt(std::min(unit, 1.0)));
                    m_count[j] = float(seedPhotons / (double(lookups) * double(s)));
                    continue;
                }
                // Photons per sample of the map and per lookup; s steps of the SPPM update.
                const double m = sum / (double(lookups) * double(s));
                if (!(m > 0)) continue;
                double n = double(m_count[j]), r2 = double(m_radius[j]) * double(m_radius[j]);
                for (int k = 0; k < s; ++k) {
                    r2 *= (n + m_alpha * m) / (n + m);
                    n += m_alpha * m;
                }
                m_radius[j] = float(std::sqrt(r2));
                m_count[j] = float(n);
            }
        });
    m_seeding = false;
}

double CausticPixelRadius::meanRadius() const {
    double sum = 0;
    std::size_t n = 0;
    for (std::size_t j = 0; j < m_radius.size(); ++j)
        if (m_count[j] > 0) {
            sum += double(m_radius[j]);
            ++n;
        }
    return n ? sum / double(n) : 0.0;
}

} // namespace rayproc
