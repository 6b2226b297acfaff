#include "engine/noise_breakdown.h"

#include "core/math.h"

#include <algorithm>

namespace rayproc {

const char* NoiseBreakdown::name(Group g) {
    switch (g) {
    case Direct: return "direct";
    case Caustic: return "caustic";
    case LightSamples: return "light-samples";
    case LightHits: return "light-hits";
    case SkySamples: return "sky-samples";
    case SkyHits: return "sky-hits";
    default: return "total";
    }
}

NoiseBreakdown::Group NoiseBreakdown::groupOf(std::size_t category, std::size_t lightCount,
                                              bool afterBounce) {
    if (category == 0) return afterBounce ? Caustic : Direct;
    const std::size_t light = (category - 1) / 2;
    const bool sample = category % 2 == 1;
    if (light >= lightCount) return sample ? SkySamples : SkyHits;
    return sample ? LightSamples : LightHits;
}

void fileContribution(ThreadStats& stats, NoiseBreakdown* noise, std::size_t lightCount,
                      std::uint32_t pixel, std::size_t category, const Vec3& c,
                      bool afterBounce) {
    stats.addContribution(category, luminance(c));
    if (noise)
        noise->add(pixel, NoiseBreakdown::groupOf(category, lightCount, afterBounce), c, stats);
}

NoiseBreakdown::NoiseBreakdown(int width, int height, int exponent, const SensorMatrix& sensor)
    : m_sensorIdentity(sensor.identity) {
    const Vec3 y(luminance(Vec3(1, 0, 0)), luminance(Vec3(0, 1, 0)), luminance(Vec3(0, 0, 1)));
    for (int j = 0; j < 3; ++j)
        m_weights[j] = y.x * sensor.m[0][j] + y.y * sensor.m[1][j] + y.z * sensor.m[2][j];
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    for (int g = 0; g < kGroups; ++g) m_groups.push_back(std::make_unique<Film>(width, height, exponent));
    m_moments.assign(kGroups + 1, std::vector<double>(2 * pixels, 0.0));
}

void NoiseBreakdown::add(std::uint32_t pixel, Group g, const Vec3& c, ThreadStats& stats) {
    const float y = m_sensorIdentity ? luminance(c) : dot(m_weights, c);
    m_groups[std::size_t(g)]->add(pixel, Vec3(y, 0.0f, 0.0f), stats);
}

void NoiseBreakdown::commitPass() {
    const std::size_t pixels = m_moments[0].size() / 2;
    std::vector<double> total(pixels, 0.0);
    for (std::size_t g = 0; g < m_groups.size(); ++g) {
        m_groups[g]->commitPass(0, &m_pass);
        std::vector<double>& m = m_moments[g];
        for (std::size_t p = 0; p < pixels; ++p) {
            const double x = m_pass[3 * p];
            m[2 * p] += x;
            m[2 * p + 1] += x * x;
            total[p] += x;
        }
    }
    std::vector<double>& m = m_moments[kGroups];
    for (std::size_t p = 0; p < pixels; ++p) {
        m[2 * p] += total[p];
        m[2 * p + 1] += total[p] * total[p];
    }
}

std::vector<NoiseBreakdown::Layer> NoiseBreakdown::layers(
    int width, int height, const std::vector<std::vector<double>>& moments,
    const std::vector<std::uint64_t>& samples) {
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    std::vector<Layer> out;
    const std::vector<double>& total = moments[kGroups];
    for (int g = 0; g <= kGroups && std::size_t(g) < moments.size(); ++g) {
        Layer noise{std::string("noise.") + name(Group(g)), std::vector<float>(pixels, 0.0f)};
        Layer mean{std::string("mean.") + name(Group(g)), std::vector<float>(pixels, 0.0f)};
        for (std::size_t p = 0; p < pixels; ++p) {
            if (samples[p] == 0) continue;
            const double n = double(samples[p]);
            const double s1 = moments[std::size_t(g)][2 * p], s2 = moments[std::size_t(g)][2 * p + 1];
            const double f = total[2 * p] / n;
            const double variance = std::max(0.0, s2 / n - (s1 / n) * (s1 / n));
            noise.values[p] = float(variance / (f * f + 0.01));
            mean.values[p] = float(s1 / n);
        }
        out.push_back(std::move(noise));
        if (g < kGroups) out.push_back(std::move(mean));
    }
    return out;
}

} // namespace rayproc
