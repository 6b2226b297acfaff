#include "lighting/environment.h"

#include "kernels/sampling.h"

namespace rayproc {

struct EnvironmentLight::Map {};

void EnvironmentLight::add(const Light& light) {
    m_present = true;
    m_constant += light.intensity;
}

Vec3 EnvironmentLight::radiance(const Vec3& dir) const { return m_constant; }

EnvironmentSample EnvironmentLight::sample(Vec2 u, const Vec3& n) const {
    EnvironmentSample s;
    s.wi = kernels::toWorld(kernels::cosineHemisphere(u), n);
    s.pdf = dot(s.wi, n) * kInvPi;
    if (!(s.pdf > 0)) return s;
    s.weight = m_constant / s.pdf;
    s.valid = true;
    return s;
}

float EnvironmentLight::pdf(const Vec3& dir, const Vec3& n) const {
    return std::max(0.0f, dot(dir, n)) * kInvPi;
}

Vec3 EnvironmentLight::average() const { return m_constant; }

EnvironmentSample EnvironmentLight::sampleSphere(Vec2 u) const {
    EnvironmentSample s;
    float z = 1.0f - 2.0f * u.x, r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    float phi = 2.0f * kPi * u.y;
    s.wi = {r * std::cos(phi), r * std::sin(phi), z};
    s.pdf = 1.0f / (4.0f * kPi);
    s.weight = m_constant / s.pdf;
    s.valid = true;
    return s;
}

} // namespace rayproc
