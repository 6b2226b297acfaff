// Where each pixel's noise comes from (path mode's --debug-view noise): every film contribution
// of path mode is also filed, by pixel, under the strategy that made it, and the per-sample
// moments of each group give its share of the pixel's variance.
//
// Groups: emission or sky seen from the camera through delta lobes only (`direct`); the same
// reached through delta lobes after a diffuse or glossy bounce (`caustic`: a BSDF-sampled path
// that found a light through glass or a mirror); light samples of the lights with a position
// or direction (`light-samples`) and of the sky (`sky-samples`); BSDF rays that found a light
// (`light-hits`) or the sky (`sky-hits`).
//
// The render's passes are of one sample per pixel, so a pass's sum of a group's contributions
// at a pixel is that sample's value X_g (the luminance of everything the group gave it); the
// breakdown keeps S1 = sum X_g and S2 = sum X_g^2 over the samples. Group g's noise at pixel p
// is its variance per sample over the relMSE's weight: (S2 / n - (S1 / n)^2) / (F^2 + 0.01),
// n the pixel's samples, F its mean luminance. `total` is the same of the whole sample (the sum
// of the groups): it is the pixel's relMSE times its spp (in luminance), and the groups add up
// to it but for the covariances between groups of one path (a light sample and the BSDF ray
// that leaves the same vertex share its throughput). Pass sums are kept as the film keeps
// radiance (engine/film.h: 128-bit fixed point), so the breakdown too is the same whatever the
// thread count. A contribution's luminance is that of its colour through the film's sensor
// (engine/film_sensor.h), so the layers describe the image the render hands out: iso 200
// doubles the means and leaves the noise (a relative variance) nearly as it was.
#pragma once

#include "engine/film.h"
#include "engine/film_sensor.h"
#include "image/image.h"

#include <memory>
#include <string>
#include <vector>

namespace rayproc {

class NoiseBreakdown {
public:
    enum Group { Direct, Caustic, LightSamples, LightHits, SkySamples, SkyHits, kGroups };
    static const char* name(Group g);
    // The group of a contribution of path mode's category (engine/stats.h: 0 delta-reached
    // emission, 1 + 2k light k's samples, 2 + 2k BSDF hits of light k; k == lightCount the sky);
    // `afterBounce`: a delta-reached contribution whose path had a non-delta bounce.
    static Group groupOf(std::size_t category, std::size_t lightCount, bool afterBounce);

    NoiseBreakdown(int width, int height, int exponent, const SensorMatrix& sensor = {});
    // Files the luminance of the contribution `c` (the film's RGB) through the sensor.
    void add(std::uint32_t pixel, Group g, const Vec3& c, ThreadStats& stats);
    // With the film's commitPass; the pass must be of (at most) one sample per pixel.
    void commitPass();

    using Layer = ImageLayer;
    // The moments S1, S2 per pixel (2 per pixel) of each group and then of the total; a
    // distributed render sums them over ranks (each pixel is one rank's).
    std::vector<std::vector<double>> moments() const { return m_moments; }
    // "noise.<group>" and "mean.<group>" (its mean luminance per sample) per group, then
    // "noise.total", from the summed moments and the image's samples per pixel.
    static std::vector<Layer> layers(int width, int height,
                                     const std::vector<std::vector<double>>& moments,
                                     const std::vector<std::uint64_t>& samples);

private:
    std::vector<std::unique_ptr<Film>> m_groups; // the current pass's sums (channel 0)
    std::vector<std::vector<double>> m_moments;  // kGroups + 1, each S1, S2 per pixel
    std::vector<double> m_pass;
    // luminance(M c) = weights . c for the sensor's matrix M; unused for the identity.
    bool m_sensorIdentity = true;
    Vec3 m_weights{0, 0, 0};
};

// Files one of path mode's contributions `c` (the film's RGB): its luminance under its
// category for --stats, and, when `noise` is set (--debug-view noise), under its group at its
// pixel. `afterBounce` as in groupOf.
void fileContribution(ThreadStats& stats, NoiseBreakdown* noise, std::size_t lightCount,
                      std::uint32_t pixel, std::size_t category, const Vec3& c,
                      bool afterBounce);

} // namespace rayproc
