#include "engine/film.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace rayproc {

namespace {

// Pixels per task of a commit: a 512x512 film is 64 tasks.
constexpr std::size_t kCommitGrain = 4096;

// A pixel's mean in float: one beyond float's range (a light of 3.4e38 and a little more) is
// the largest float of its sign, never Inf.
float toPixel(double v) {
    constexpr double kLargest = std::numeric_limits<float>::max();
    return float(std::clamp(v, -kLargest, kLargest));
}

// The fixed-point value of a sample (an integer-valued double, |x| <= 2^96) as the two words
// of a signed 128-bit integer. Below 2^63 (every ordinary sample) one 64-bit conversion gives
// the same words as the 128-bit one, which is a library call.
void splitFixed(double x, std::uint64_t& low, std::int64_t& high) {
    if (std::abs(x) < 0x1p63) {
        auto fixed = static_cast<std::int64_t>(x);
        low = static_cast<std::uint64_t>(fixed);
        high = fixed < 0 ? -1 : 0;
        return;
    }
    auto fixed = static_cast<__int128>(x);
    low = static_cast<std::uint64_t>(fixed);
    high = static_cast<std::int64_t>(fixed >> 64);
}

// The signed 128-bit integer of two words as a double, rounded to nearest as the 128-bit
// conversion rounds; a value that fits 64 bits takes the one-instruction conversion (the same
// rounding, so the same double).
double joinFixed(std::uint64_t low, std::int64_t high) {
    if (high == (static_cast<std::int64_t>(low) >> 63)) return double(static_cast<std::int64_t>(low));
    __int128 v = (static_cast<__int128>(high) << 64) | static_cast<__int128>(low);
    return double(v);
}

} // namespace

Film::Film(int width, int height, int exponent)
    : m_width(width), m_height(height), m_exponent(exponent), m_scale(std::ldexp(1.0, exponent)),
      m_limit(std::ldexp(1.0, 96 - exponent)), m_passLow(std::size_t(width) * height * 3),
      m_passHigh(std::size_t(width) * height * 3),
      m_passSamples(std::size_t(width) * height), m_sum(std::size_t(width) * height * 3, 0.0),
      m_samples(std::size_t(width) * height, 0) {}

int Film::exponentFor(double brightest) {
    if (!(brightest > 0) || !std::isfinite(brightest)) return kDefaultExponent;
    // 2^e <= brightest < 2^(e+1) maps to [2^36, 2^37) units: 36 - e = 32 for 16 <= brightest
    // < 32 (the Cornell box's 17).
    return kBrightestExponent - std::ilogb(brightest);
}

void Film::add(std::uint32_t pixel, const Vec3& radiance, ThreadStats& stats) {
    if (!isFinite(radiance)) {
        ++stats.invalidSamples;
        return;
    }
    for (int c = 0; c < 3; ++c) {
        double v = double(radiance[c]);
        if (v == 0.0) continue;
        if (std::abs(v) > m_limit) {
            ++stats.clampedSamples;
            v = std::copysign(m_limit, v);
        }
        // |v| * 2^exponent <= 2^96 fits a signed 128-bit integer; beyond 2^53 the double is
        // already an integer, below it rounding to nearest is the fixed-point quantisation.
        std::uint64_t low;
        std::int64_t high;
        splitFixed(std::nearbyint(v * m_scale), low, high);
        std::size_t i = std::size_t(pixel) * 3 + c;
        std::uint64_t before = m_passLow[i].fetch_add(low, std::memory_order_relaxed);
        if (before + low < before) ++high; // the low word wrapped: carry into the high word
        if (high != 0) m_passHigh[i].fetch_add(high, std::memory_order_relaxed);
    }
}

void Film::enableHalfBuffers() {
    for (int h = 0; h < 2; ++h) {
        m_halfSum[h].assign(m_sum.size(), 0.0);
        m_halfSamples[h].assign(m_samples.size(), 0);
    }
}

double Film::relMseEstimate() const { return relMseFromParts(relMseParts()); }

std::vector<double> Film::relMseParts() const {
    if (!hasHalfBuffers()) return {};
    constexpr int kTile = 16;
    int tilesX = (m_width + kTile - 1) / kTile, tilesY = (m_height + kTile - 1) / kTile;
    std::vector<double> parts(std::size_t(tilesX) * std::size_t(tilesY) * 2, 0.0);
    for (int ty = 0; ty < tilesY; ++ty)
        for (int tx = 0; tx < tilesX; ++tx) {
            double sum = 0, count = 0;
            for (int y = ty * kTile; y < std::min((ty + 1) * kTile, m_height); ++y)
                for (int x = tx * kTile; x < std::min((tx + 1) * kTile, m_width); ++x) {
                    std::size_t p = std::size_t(y) * std::size_t(m_width) + std::size_t(x);
                    double e = pixelRelMse(p);
                    if (std::isnan(e)) continue;
                    sum += e;
                    count += 1;
                }
            std::size_t t = std::size_t(ty) * std::size_t(tilesX) + std::size_t(tx);
            parts[2 * t] = sum;
            parts[2 * t + 1] = count;
        }
    return parts;
}

double Film::pixelRelMse(std::size_t p) const {
    std::uint32_t na = m_halfSamples[0][p], nb = m_halfSamples[1][p];
    if (na == 0 || nb == 0) return std::numeric_limits<double>::quiet_NaN();
    double sum = 0;
    for (int c = 0; c < 3; ++c) {
        double a = m_halfSum[0][p * 3 + c] / na, b = m_halfSum[1][p * 3 + c] / nb;
        double f = 0.5 * (a + b);
        sum += 0.25 * (a - b) * (a - b) / (f * f + 0.01);
    }
    return sum / 3;
}

double Film::relMseFromParts(const std::vector<double>& parts) {
    double sum = 0, count = 0;
    for (std::size_t t = 0; t + 1 < parts.size(); t += 2) {
        sum += parts[t];
        count += parts[t + 1];
    }
    return count > 0 ? sum / count : std::numeric_limits<double>::quiet_NaN();
}

void Film::commitPass(int half, std::vector<double>* passSums) {
    std::lock_guard<std::mutex> lk(m_commitMutex);
    if (passSums) passSums->assign(m_sum.size(), 0.0);
    const bool halves = hasHalfBuffers();
    // Each pixel folds alone, so splitting the pixels over threads gives the same sums to the
    // bit. The commit runs between passes while no worker has work: done on one thread, it was
    // the largest serial phase of path and raytrace renders (docs/performance.md, "Phases and
    // scaling").
    // Isolated: while it waits, this thread (holding the mutex) takes no unrelated task that
    // could want the mutex too.
    // No sample is added during a commit (the contract above), so each accumulator is read and
    // cleared by a plain load and store: an atomic exchange, a locked instruction, made seven
    // per pixel the commit's whole cost.
    auto take = [](auto& a) {
        auto v = a.load(std::memory_order_relaxed);
        a.store(0, std::memory_order_relaxed);
        return v;
    };
    auto fold = [&](std::size_t begin, std::size_t end) {
        for (std::size_t p = begin; p < end; ++p) {
            std::uint32_t passSamples = take(m_passSamples[p]);
            m_samples[p] += passSamples;
            if (halves) m_halfSamples[half][p] += passSamples;
            for (int c = 0; c < 3; ++c) {
                std::uint64_t low = take(m_passLow[p * 3 + c]);
                std::int64_t high = take(m_passHigh[p * 3 + c]);
                double v = joinFixed(low, high) / m_scale;
                m_sum[p * 3 + c] += v;
                if (passSums) (*passSums)[p * 3 + c] = v;
                if (halves) m_halfSum[half][p * 3 + c] += v;
            }
        }
    };
    tbb::this_task_arena::isolate([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, m_samples.size(), kCommitGrain),
                          [&](const tbb::blocked_range<std::size_t>& r) { fold(r.begin(), r.end()); });
    });
}

Image Film::resolve() const { return resolve(m_width, m_height, m_sum, m_samples); }

Image Film::resolveInProgress() const {
    std::lock_guard<std::mutex> lk(m_commitMutex);
    Image img(m_width, m_height);
    for (std::size_t p = 0; p < m_samples.size(); ++p) {
        std::uint64_t n = m_samples[p] + m_passSamples[p].load(std::memory_order_relaxed);
        if (n == 0) continue;
        for (int c = 0; c < 3; ++c) {
            std::size_t i = p * 3 + std::size_t(c);
            double pass = joinFixed(m_passLow[i].load(std::memory_order_relaxed),
                                    m_passHigh[i].load(std::memory_order_relaxed));
            img.pixels[i] = toPixel((m_sum[i] + pass / m_scale) / double(n));
        }
    }
    return img;
}

Image Film::resolve(int width, int height, const std::vector<double>& sums,
                    const std::vector<std::uint64_t>& samples) {
    Image img(width, height);
    for (std::size_t p = 0; p < samples.size(); ++p) {
        if (samples[p] == 0) continue;
        double inv = 1.0 / double(samples[p]);
        for (int c = 0; c < 3; ++c) img.pixels[p * 3 + c] = toPixel(sums[p * 3 + c] * inv);
    }
    return img;
}

std::size_t Film::pixelsWithoutSamples() const {
    std::size_t n = 0;
    for (auto s : m_samples) n += s == 0;
    return n;
}

} // namespace rayproc
