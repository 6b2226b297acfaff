// The environment ("infinite") light: radiance arriving from every direction that escapes the
// scene, constant or given by an image (pbrt-v4's equal-area octahedral square, or lat-long),
// sampled in proportion to its luminance so small bright skies (a sun in the map) converge.
// Several scene environment lights add up into one.
#pragma once

#include "core/math.h"
#include "scene/scene.h"

#include <memory>
#include <vector>

namespace rayproc {

struct EnvironmentSample {
    Vec3 wi;            // unit world direction towards the sky
    Vec3 weight;        // radiance / pdf
    float pdf = 0;      // solid angle
    bool valid = false;
};

class EnvironmentLight {
public:
    bool present() const { return m_present; }
    // Adds a scene light of type Environment (constant or image).
    void add(const Light& light);
    // Radiance arriving along -dir, i.e. seen by a ray travelling in direction `dir`.
    Vec3 radiance(const Vec3& dir) const;
    // A direction to the sky for a shading point with facing shading normal n: cosine-weighted
    // about n for a constant sky, luminance-importance-sampled for an image. `compensated`
    // (only where BSDF samples combined by MIS see the sky too: path mode): an image is
    // sampled by its excess over its mean (Map::compensated); directions darker than the mean
    // get no light samples, so the estimate needs the BSDF's.
    EnvironmentSample sample(Vec2 u, const Vec3& n, bool compensated = false) const;
    // The solid-angle pdf with which sample(., n, compensated) returns `dir`.
    float pdf(const Vec3& dir, const Vec3& n, bool compensated = false) const;
    // Whether sample() depends on n (constant skies: cosine-weighted) or not (image skies).
    bool cosineSampled() const { return m_images.empty(); }
    // Mean radiance over the sphere (preview's unshadowed ambient term, photon power).
    Vec3 average() const;
    // The constant sky's own spectrum (Light::spectrum; scene/emission_spectrum.h), or nullptr:
    // only where the sky has no image, so that its radiance is the constant's in every
    // direction (an image sky's texels are RGB illuminant spectra).
    const EmissionSpectrum* constantSpectrum() const {
        return m_images.empty() ? m_constantSpectrum.get() : nullptr;
    }
    // Samples a direction from the whole sphere by the sky's luminance (photon emission):
    // the direction light arrives from, and its solid-angle pdf.
    EnvironmentSample sampleSphere(Vec2 u) const;

    // The mean of the channels of an image map's radiance over the sphere and its pdf for a
    // world direction (tests; `index` in the order of add()).
    std::size_t imageCount() const { return m_images.size(); }

    struct Map; // an image, its frame and its sampling distribution (environment_map.cpp)

private:
    // With an image, sample() is a mixture: component i (the constant part uniformly over
    // the sphere, then each image by its distribution) is chosen with probability
    // m_pick[i] - m_pick[i-1], proportional to its mean radiance; pdf() is the mixture's.
    void updatePick();
    float mixturePdf(const Vec3& dir, bool compensated) const;

    bool m_present = false;
    Vec3 m_constant{0.0f, 0.0f, 0.0f};
    EmissionSpectrumRef m_constantSpectrum;
    std::vector<std::shared_ptr<const Map>> m_images;
    std::vector<float> m_pick; // cumulative: constant, then each image; last = 1
};

// The radiance scale that gives an equal-area image sky the upper-hemisphere (+z in light space)
// illuminance `target`, by pbrt-v4's estimate: 2 pi / N times the sum over the upper-hemisphere
// pixels of luminance * cos theta (pbrt_lights.cpp explains the factor).
float equalAreaIlluminanceScale(const Image& image, float target);

} // namespace rayproc
