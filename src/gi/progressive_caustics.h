// Progressive caustics: gi's caustic map traced anew for every render pass, with fresh photons
// and a radius that shrinks from pass to pass, so a caustic sharpens and loses its noise as the
// passes accumulate instead of keeping one map's blur for ever.
//
// Follows Knaus & Zwicker 2011 ("Progressive photon mapping: a probabilistic approach", ACM TOG
// 30(3)): pass i is an independent photon-map estimate with radius r_i,
//   r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1),   i = 1, 2, ...,
// and the image is the average of the passes. This is Hachisuka & Jensen's stochastic
// progressive photon mapping (2009) with its per-pixel statistics replaced by one radius
// sequence: the same reduction (alpha = 2/3 by default), so the estimate's variance and bias
// both vanish as the passes grow (variance falls as i^-alpha, bias as i^(alpha-1)), with the
// memory of one pass's map and nothing kept per pixel. r_1 is the median distance from the
// first map's photons to their causticK-th neighbour: the radius a k-nearest estimate would
// use where the caustic is.
//
// The sequence counts samples per pixel, not render passes: a render pass of s samples (gi's
// fixed-spp renders take up to 16 a pass) stands for s passes of the sequence, with s times the
// photons (at most kMaxPassPhotons) and the radius whose square is the mean of those s passes'
// squared radii (the bias is O(r^2)). Counted by passes, a 256-spp render traced 32 maps and
// stopped shrinking where a 64-spp one did (scenes/caustic-pool.json: the caustic's brightest
// pixels 2.5% dark at both).
//
// With GiSettings::causticPixelRadius (the default) the radius is kept per pixel instead, as
// SPPM keeps it (gi/caustic_pixel_radius.h): the sequence above then gives only the first
// pass's radius, and each pixel's shrinks with the photons its visible points find.
//
// Consumes: the scene and lights (through the photon pass), the pass index.
// Produces: GiData::caustic, GiData::causticRadius and GiData::causticPixels for the pass
// (read by the gather stage).
#pragma once

#include "engine/engine_settings.h"
#include "engine/stats.h"
#include "gi/caustic_pixel_radius.h"
#include "gi/focus_region.h"
#include "gi/gi_context.h"
#include "gi/photon_map.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>

namespace rayproc {

class Cluster;
class PhaseLog;
class EmbreeScene;
struct LightSet;
struct Scene;

// r_i / r_1 for pass index i >= 1 of the sequence above (1 for i = 1).
inline double progressiveRadiusRatio(int pass, double alpha) {
    double ratio2 = 1.0;
    for (int j = 1; j < pass; ++j) ratio2 *= (double(j) + alpha) / double(j + 1);
    return std::sqrt(ratio2);
}

// A render pass's map holds at most this many photons, or the per-sample count when that is
// larger (memory: about 96 bytes per caustic photon while the map is built).
inline constexpr std::uint64_t kMaxPassPhotons = 1000000;
// The photons of a pass of `samples` samples per pixel: `perSample` each, within the cap.
inline std::uint64_t progressivePassPhotons(std::uint64_t perSample, int samples) {
    std::uint64_t cap = std::max(perSample, kMaxPassPhotons);
    return std::min(perSample * std::uint64_t(std::max(samples, 1)), cap);
}
// The largest map a render may trace (its memory estimate): passes take at most 16 samples.
inline std::uint64_t progressiveMaxPassPhotons(std::uint64_t perSample) {
    return progressivePassPhotons(perSample, 16);
}

// The radius sequence by samples: r_1^2 times the mean of (r_i / r_1)^2 over the next s
// indices, advanced incrementally (a render of 10^5 samples must not recount from 1).
class ProgressiveRadius {
public:
    explicit ProgressiveRadius(double alpha) : m_alpha(alpha) {}
    // (r / r_1)^2 for the next `samples` indices of the sequence, and advances past them.
    double next(int samples) {
        double sum = 0;
        int s = std::max(samples, 1);
        for (int k = 0; k < s; ++k) {
            sum += m_ratio2;
            m_ratio2 *= (double(m_index) + m_alpha) / double(m_index + 1);
            ++m_index;
        }
        return sum / double(s);
    }

private:
    double m_alpha;
    double m_ratio2 = 1.0; // (r_i / r_1)^2 at m_index
    int m_index = 1;
};

class ProgressiveCaustics {
public:
    // The first pass's map is traced here (the stream a single caustic map uses); gi's
    // causticRadius is the largest radius any pass may start from.
    ProgressiveCaustics(const Scene& scene, const EmbreeScene& accel, const LightSet& lights,
                        GiData& gi, const EngineSettings& engine, const Cluster& cluster,
                        PhaseLog* phases, const FocusRegion& focus, Stats& stats);
    // Points gi at pass `pass`'s map (0-based render pass, taking `samples` samples per
    // pixel) and radius, tracing it first when it is not the one held. Passes come in order.
    // A collective under MPI (every rank calls it for every pass).
    void beginPass(int pass, int samples);
    const PhotonMap& map() const { return m_map; }
    float firstRadius() const { return m_firstRadius; }
    int passesTraced() const { return m_passesTraced; }
    // The per-pixel radii (null without GiSettings::causticPixelRadius).
    const CausticPixelRadius* pixelRadius() const { return m_pixels.get(); }

private:
    const Scene& m_scene;
    const EmbreeScene& m_accel;
    const LightSet& m_lights;
    GiData& m_gi;
    EngineSettings m_engine;
    const Cluster& m_cluster;
    PhaseLog* m_phases;
    const FocusRegion& m_focus;
    Stats& m_stats;
    PhotonMap m_map;
    int m_mapPass = 0;
    std::uint64_t m_mapPhotons = 0;
    int m_passesTraced = 0;
    ProgressiveRadius m_radius;
    float m_firstRadius = 0;
    std::unique_ptr<CausticPixelRadius> m_pixels;
    int m_lastSamples = 0; // the samples per pixel of the pass before this one
};

} // namespace rayproc
