#include "lighting/environment.h"

#include "kernels/sampling.h"
#include "lighting/environment_map.h"
#include "lighting/sphere_mapping.h"

#include <algorithm>

namespace rayproc {

namespace {

float channelMean(const Vec3& c) { return std::max(0.0f, (c.x + c.y + c.z) / 3.0f); }

Vec3 uniformSphere(Vec2 u) {
    float z = 1.0f - 2.0f * u.x, r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    float phi = 2.0f * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

} // namespace

void EnvironmentLight::add(const Light& light) {
    m_present = true;
    if (!light.image) {
        m_constantSpectrum =
            sumOfEmissions(m_constant, m_constantSpectrum, light.intensity, light.spectrum);
        m_constant += light.intensity;
    } else if (light.image->width > 0 && light.image->height > 0) {
        auto map = std::make_shared<const Map>(light);
        if (map->distribution.valid()) m_images.push_back(std::move(map)); // else black
    }
    updatePick();
}

void EnvironmentLight::updatePick() {
    m_pick.clear();
    if (m_images.empty()) return;
    float total = channelMean(m_constant);
    m_pick.push_back(total);
    for (const auto& m : m_images) m_pick.push_back(total += channelMean(m->average));
    for (float& p : m_pick) p /= total;
    m_pick.back() = 1.0f;
}

Vec3 EnvironmentLight::radiance(const Vec3& dir) const {
    Vec3 L = m_constant;
    for (const auto& m : m_images) L += m->radiance(dir);
    return L;
}

float EnvironmentLight::mixturePdf(const Vec3& dir, bool compensated) const {
    float pdf = m_pick[0] / (4 * kPi);
    for (std::size_t i = 0; i < m_images.size(); ++i)
        pdf += (m_pick[i + 1] - m_pick[i]) * m_images[i]->pdf(dir, compensated);
    return pdf;
}

EnvironmentSample EnvironmentLight::sample(Vec2 u, const Vec3& n, bool compensated) const {
    EnvironmentSample s;
    if (m_images.empty()) { // constant sky: cosine-weighted about n
        s.wi = kernels::toWorld(kernels::cosineHemisphere(u), n);
        s.pdf = dot(s.wi, n) * kInvPi;
        if (!(s.pdf > 0)) return s;
        s.weight = m_constant / s.pdf;
        s.valid = true;
        return s;
    }
    // Pick a component with u.x and reuse its remainder for the component's own sample.
    std::size_t c = std::size_t(std::upper_bound(m_pick.begin(), m_pick.end(), u.x) - m_pick.begin());
    c = std::min(c, m_pick.size() - 1);
    float lo = c == 0 ? 0.0f : m_pick[c - 1], width = m_pick[c] - lo;
    if (!(width > 0)) return s;
    Vec2 v{std::min((u.x - lo) / width, 0.99999994f), u.y};
    if (c == 0) {
        s.wi = uniformSphere(v);
    } else {
        float pdf;
        Vec3 L;
        s.wi = m_images[c - 1]->sample(v, pdf, L, compensated);
        if (!(pdf > 0)) return s;
        if (m_images.size() == 1 && m_pick[0] == 0) { // the common case: one image alone
            s.pdf = pdf;
            s.weight = L / pdf;
            s.valid = isFinite(s.weight);
            return s;
        }
    }
    s.pdf = mixturePdf(s.wi, compensated);
    if (!(s.pdf > 0)) return s;
    s.weight = radiance(s.wi) / s.pdf;
    s.valid = isFinite(s.weight);
    return s;
}

float EnvironmentLight::pdf(const Vec3& dir, const Vec3& n, bool compensated) const {
    if (m_images.empty()) return std::max(0.0f, dot(dir, n)) * kInvPi;
    return mixturePdf(dir, compensated);
}

Vec3 EnvironmentLight::average() const {
    Vec3 a = m_constant;
    for (const auto& m : m_images) a += m->average;
    return a;
}

EnvironmentSample EnvironmentLight::sampleSphere(Vec2 u) const {
    if (!m_images.empty()) return sample(u, Vec3(0, 0, 1)); // independent of n
    EnvironmentSample s;
    s.wi = uniformSphere(u);
    s.pdf = 1.0f / (4.0f * kPi);
    s.weight = m_constant / s.pdf;
    s.valid = true;
    return s;
}

// pbrt-v4 sums luminance * cos theta over the pixels of the upper hemisphere and multiplies by
// 2 pi / N, where a pixel covers 4 pi / N: its estimate is half the true illuminance, so a sky
// given "illuminance" E renders with illuminance 2E. We reproduce the estimate, not the
// physics, so that imported scenes render as in pbrt-v4.
float equalAreaIlluminanceScale(const Image& image, float target) {
    const int w = image.width, h = image.height;
    double sum = 0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            Vec3 d = equalAreaSquareToSphere({(float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h)});
            if (d.z <= 0) continue;
            const float* p = image.at(x, y);
            sum += double(luminance({p[0], p[1], p[2]})) * d.z;
        }
    }
    double e = sum * 2 * kPi / (double(w) * h);
    return e > 0 ? float(target / e) : 1.0f;
}

} // namespace rayproc
