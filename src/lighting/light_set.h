// The lights a render samples, in world space: the scene's point, spot and directional
// lights, every placed emissive shape as an area light, and the environment. Preview mode
// builds a different set from the same scene (a point light per area-light corner).
#pragma once

#include "accel/embree_scene.h"
#include "core/math.h"
#include "lighting/environment.h"
#include "lighting/light_bounds.h"
#include "lighting/light_sampler.h"
#include "image/image.h"
#include "scene/scene.h"

#include <memory>

#include <utility>
#include <vector>

namespace rayproc {

// A light sample as seen from a shading point.
struct LightSample {
    Vec3 wi;          // unit direction towards the light
    float distance;   // to the sampled point; infinity for directional lights
    Vec3 weight;      // incident radiance / pdf (solid angle), or irradiance for delta lights
    float pdf = 0;    // solid-angle pdf of the sample; 0 for delta lights
    bool valid = false;
    // Where the sample lies, for the shadow ray that must stop short of it: the point, its
    // floating-point error bound and the light surface's normal (zero for point and spot
    // lights, which are no surface; unused for directional lights).
    Vec3 point, pointError, normal;
};

class LightSource {
public:
    enum class Kind { Point, Spot, Directional, AreaMesh, AreaSphere, AreaDisk };
    Kind kind = Kind::Point;
    bool delta() const { return kind == Kind::Point || kind == Kind::Spot || kind == Kind::Directional; }

    // Point / spot / directional
    Vec3 position, direction, intensity;
    float cosCone = 1, cosFalloff = 1;
    // A point light that stands for a piece of an area light radiates with a cosine lobe.
    bool lobe = false, lobeTwoSided = false;
    Vec3 lobeNormal;
    // A goniometric light is a point light whose intensity in the emitted direction w is
    // `intensity` times the channel mean of `goniometric` at equalAreaSphereToSquare(toLight w)
    // (nearest pixel, pbrt-v4); `goniometricMean` is that factor's mean over the sphere.
    std::shared_ptr<const Image> goniometric;
    Affine toLight;
    float goniometricMean = 1;
    // The factor by which the intensity varies with the emitted direction (spot falloff,
    // goniometric image; 1 for a plain point light). `wOut` is unit, from the light outwards.
    float directionalFactor(const Vec3& wOut) const;
    // The emission's own spectrum (Light::spectrum, Shape::emissionSpectrum), which the
    // spectral mode renders; nullptr: the RGB illuminant spectrum of the intensity or radiance.
    EmissionSpectrumRef spectrum;
    // Area lights
    Vec3 radiance;
    bool twoSided = false;
    std::vector<Vec3> triangles;   // world-space vertices, 3 per triangle
    std::vector<float> areaCdf;    // cumulative triangle areas, last = total area
    std::vector<Vec3> triangleNormals; // unit normal per triangle (meshLightPoint's, once)
    Vec3 center, normal;           // sphere and disk
    float radius = 0;
    float area = 0;
    // The light's index in the set it was built in: keys its random numbers, so a subset
    // samples each remaining light exactly as the full set does.
    std::uint32_t stream = 0;
    // For choosing among area lights: a bounding sphere and the unit normal of a planar light
    // (zero otherwise).
    Vec3 boundCenter, flatNormal;
    float boundRadius = 0;
    // Where and in which directions the light emits, and how much (LightSampler's bounds);
    // set by LightSet::build for every light with a position.
    LightBounds bounds;
    // The power the bounds weigh the light by (in double: up to float's limit of radiance), and
    // the bounds with it times powerScale (LightSet::buildSampler: 1 / the strongest light's).
    double boundsPower() const;
    LightBounds makeBounds(double powerScale) const;
    // How much this light can give the point p, up to a factor common to all lights
    // (LightBounds::importance): 0 only where none of its points can face p, so choosing
    // lights by it is unbiased.
    float selectionWeight(const Vec3& p) const { return bounds.importance(p); }
    Vec3 placementError; // bound on the rounding of the world-space vertices / centre

    LightSample sample(const Vec3& p, Vec2 u) const;
    // Solid-angle pdf with which sample(p, .) picks the direction towards the point q of
    // this light with normal nq (path mode's multiple importance sampling). 0 for delta lights.
    float pdf(const Vec3& p, const Vec3& q, const Vec3& nq) const;
    Vec3 power() const; // total emitted power (W), for statistics and photon emission
};

// A point on a mesh light, uniform by area (u.x picks the triangle by the area CDF, its
// remainder and u.y the point in it), its rounding error bound and the triangle's unit normal:
// light samples (LightSource::sample) and emitted photons (gi/photon_emitter.cpp) alike.
Vec3 meshLightPoint(const LightSource& l, Vec2 u, Vec3& err, Vec3& n);

struct LightSet {
    std::vector<LightSource> lights;
    EnvironmentLight environment; // the sky; absent when no scene light is an environment
    bool hasEnvironment() const { return environment.present(); }

    // Path mode (and gi's correction rays) pick one light per shading point with `sampler`
    // among the lights and the sky (the sky is choice number lights.size()).
    std::size_t choiceCount() const { return lights.size() + (hasEnvironment() ? 1 : 0); }
    LightSampler sampler;
    // The area light an emissive leaf placement is, or -1.
    int indexOf(const Shape* shape, int instance) const;

    // Raytrace and gi choose among the area lights when there are several, with the same
    // light sampler restricted to them (`areaSampler`: delta lights and the sky take samples of
    // their own there): a shading point takes n samples per area light that matters
    // (areaSamples), each picking one with areaSampler.
    LightSampler areaSampler;
    bool choosesAreaLights() const { return m_areaLights > 1; }
    // Area lights (emissive shapes) among `lights`.
    bool hasAreaLights() const { return m_areaLights > 0; }
    // Point, spot or directional lights among `lights`.
    bool hasDeltaLights() const { return m_areaLights < lights.size(); }
    // The samples a shading point at p takes over the area lights: n per area light that
    // matters there (LightSampler::effectiveChoices, rounded), at least n; 0 where none can
    // light p.
    int areaSamples(const Vec3& p, int n) const;
    // Those samples, and the probability that one of them picks light i.
    struct Choice {
        int samples = 0;
        float probability = 0;
    };
    Choice choiceAt(std::size_t i, const Vec3& p, int n) const;

    // The radiance the lights give, roughly (the film's range follows it: Film::exponentFor):
    // the largest channel of any area light's or the sky's radiance, a directional light's
    // irradiance, a point or spot light's intensity over the squared radius of the scene.
    double radianceScale(const Bounds3& sceneBounds) const;

    // Every scene light as it is: area lights stay area lights.
    static LightSet build(const Scene& scene, const EmbreeScene& accel);
    // The paper's preview approximation: each quad light becomes a point light per corner,
    // each other area light a point light per triangle, sphere or disk at its centre; the
    // emitted power is preserved and shared equally among the points.
    static LightSet buildPreview(const Scene& scene, const EmbreeScene& accel);
    // The lights with keep[i] set (missing entries keep theirs), same sky, same streams.
    LightSet subset(const std::vector<bool>& keep) const;

private:
    // Fills every light's bounds and builds `sampler` over the lights and the sky.
    void buildSampler();
    std::vector<std::pair<std::pair<const Shape*, int>, int>> m_areaIndex; // sorted
    std::size_t m_areaLights = 0;
};

// Radiance a ray sees when it lands on an emissive surface.
inline Vec3 emittedRadiance(const Shape& s, const Vec3& ng, const Vec3& wo) {
    if (!s.isEmissive()) return Vec3(0.0f);
    return (s.twoSided || dot(ng, wo) > 0) ? s.emission : Vec3(0.0f);
}

} // namespace rayproc
