// One image of an environment light: radiance lookup (nearest pixel, as pbrt-v4's image
// infinite light does, so the piecewise-constant sampling density is exactly proportional to
// the channel mean of what is returned) and direction sampling by that density.
#pragma once

#include "lighting/distribution_2d.h"
#include "lighting/environment.h"
#include "image/image.h"

namespace rayproc {

struct EnvironmentLight::Map {
    std::shared_ptr<const Image> image;
    Vec3 scale{1, 1, 1};
    EnvironmentMapping mapping = EnvironmentMapping::EqualArea;
    Affine toWorld, toLight;
    Distribution2D distribution;
    // For light samples combined by MIS with BSDF samples (pbrt-v4's allowIncompletePDF):
    // density in proportion to max(0, channel mean - its mean over the sphere), so the light
    // samples go where the sky is brighter than its average and the BSDF samples, which see
    // the rest, take the even part. The plain distribution when nothing is above the mean.
    Distribution2D compensated;
    Vec3 average{0, 0, 0}; // mean radiance over the sphere (solid-angle weighted)

    explicit Map(const Light& light);
    // The pixel a light-space direction falls in.
    void pixelOf(const Vec3& dirLight, int& x, int& y) const;
    Vec3 pixelRadiance(int x, int y) const;
    Vec3 radiance(const Vec3& dirWorld) const;
    float solidAnglePdf(float pdfUv, const Vec3& dirLight) const;
    // Solid-angle density of sample() for a world direction.
    float pdf(const Vec3& dirWorld, bool compensated = false) const;
    // A world direction, its solid-angle pdf (0: invalid) and its radiance.
    Vec3 sample(Vec2 u, float& pdf, Vec3& radiance, bool compensated = false) const;
};

} // namespace rayproc
