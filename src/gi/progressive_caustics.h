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
// Consumes: the scene and lights (through the photon pass), the pass index.
// Produces: GiData::caustic and GiData::causticRadius for the pass (read by the gather stage).
#pragma once

#include "engine/stats.h"
#include "gi/focus_region.h"
#include "gi/gi_context.h"
#include "gi/photon_map.h"
#include "modes/render_job.h"

#include <cstdint>

namespace rayproc {

class Cluster;

// r_i / r_1 for pass index i >= 1 of the sequence above (1 for i = 1).
inline double progressiveRadiusRatio(int pass, double alpha) {
    double ratio2 = 1.0;
    for (int j = 1; j < pass; ++j) ratio2 *= (double(j) + alpha) / double(j + 1);
    return std::sqrt(ratio2);
}

class ProgressiveCaustics {
public:
    // The first pass's map is traced here (the stream a single caustic map uses); gi's
    // causticRadius is the largest radius any pass may start from.
    ProgressiveCaustics(const Scene& scene, const EmbreeScene& accel, const LightSet& lights,
                        GiData& gi, const EngineSettings& engine, const Cluster& cluster,
                        const FocusRegion& focus, Stats& stats);
    // Points gi at pass `pass`'s map (0-based render pass) and radius, tracing it first when
    // it is not the one held. A collective under MPI (every rank calls it for every pass).
    void beginPass(int pass);
    const PhotonMap& map() const { return m_map; }
    float firstRadius() const { return m_firstRadius; }
    int passesTraced() const { return m_passesTraced; }

private:
    const Scene& m_scene;
    const EmbreeScene& m_accel;
    const LightSet& m_lights;
    GiData& m_gi;
    EngineSettings m_engine;
    const Cluster& m_cluster;
    const FocusRegion& m_focus;
    Stats& m_stats;
    PhotonMap m_map;
    int m_mapPass = 0;
    int m_passesTraced = 0;
    float m_firstRadius = 0;
};

} // namespace rayproc
