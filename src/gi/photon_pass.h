// One photon pass of gi mode: this rank's share of a pass's photons traced through the ray
// processor (photon emitter -> queue -> intersect -> photon stage), then every rank's photons
// merged in key order, so the map is the one a single process would have built. Used for the
// global map, the caustic map, and each pass of the progressive caustic map.
#pragma once

#include "accel/embree_scene.h"
#include "engine/stats.h"
#include "gi/focus_region.h"
#include "gi/gi_context.h"
#include "gi/photon_map.h"
#include "gi/photon_stage.h"
#include "lighting/light_set.h"
#include "scene/scene.h"

#include <cstdint>
#include <vector>

namespace rayproc {

class Cluster;
class PhaseLog;
class SpectralRender;
struct EngineSettings;

// What to trace: which map, how many photons are emitted (over all ranks), and the random
// stream (tag) they draw from; passes of the progressive caustic map differ only in the tag.
struct PhotonPassSpec {
    bool caustic = false;
    std::uint32_t count = 0;
    std::uint64_t tag = 1;
    const char* label = "gi photons";
    // Rounds (buildPhotonMap): up to maxRounds rounds of `count` photons each, until at least
    // inViewTarget photons of the map the gather reads have landed in view (inside the focus
    // region's bounds when it is active, anywhere otherwise). Round r > 0 draws from the
    // stream hashCombine(tag, r); the powers are divided by the rounds traced.
    int maxRounds = 1;
    std::size_t inViewTarget = 0;
    // Spectral mode: photons carry wavelengths and the map stores their XYZ
    // (gi/photon_stage.h); null: RGB.
    const SpectralRender* spectral = nullptr;
};

// Traces this rank's share of the pass and returns what the photon stage stored, keyed;
// nothing once an interrupt is requested (emission stops, photons in flight finish).
KeyedPhotons tracePhotons(const Scene& scene, const EmbreeScene& accel, const LightSet& lights,
                          const GiSettings& s, const EngineSettings& engine, const Cluster& cluster,
                          PhaseLog* phases, const PhotonPassSpec& pass, const FocusRegion& focus,
                          Stats& stats);

// Every rank's photons in key order, on every rank: the map one process would have traced.
// A collective.
PhotonList mergePhotonShares(const Cluster& cluster, KeyedPhotons mine);

// Whether any rank was interrupted (one process: whether this one was). A collective.
bool stopped(const Cluster& cluster);

// tracePhotons, mergePhotonShares and PhotonMap::build in one, in rounds (PhotonPassSpec): the
// pass's map, left empty when interrupted. With `indirect`, also the map of the photons that
// are not the direct light of a delta light or the sky (PhotonRecord::sampledDirect 0), in the
// same order; it is then the one whose photons in view count. A collective: every rank sees
// the same merged photons, so all stop after the same round.
struct PhotonRounds {
    int rounds = 0;          // traced
    std::size_t inView = 0;  // photons of the gather's map that landed in view
};
PhotonRounds buildPhotonMap(PhotonMap& map, const Scene& scene, const EmbreeScene& accel,
                    const LightSet& lights, const GiSettings& s, const EngineSettings& engine,
                    const Cluster& cluster, PhaseLog* phases, const PhotonPassSpec& pass,
                    const FocusRegion& focus, Stats& stats, PhotonMap* indirect = nullptr);

} // namespace rayproc
