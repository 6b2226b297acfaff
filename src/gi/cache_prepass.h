// gi's irradiance cache prepass (Ward, Rubinstein & Clear 1988): camera rays at 1/16, 1/8, 1/4,
// 1/2 and full resolution through the surface stage, whose diffuse hits go to the gather stage
// alone (ShadingPolicy::handlersOnly); where the frozen cache has no usable record, a final
// gather makes one into a request slot (IcRequests). After each level its records, every
// rank's, are inserted sorted by (pixel and path key, position), so the cache depends neither on
// the thread count nor on the ranks (docs/irradiance-cache.md).
//
// Consumes: the photon maps and settings in GiData (its `cache` the cache being filled, read
// frozen during each level). Produces: the cache's records. Shows progress ("gi irradiance
// cache", weighted by each level's pixels) and stops at an interrupt between levels.
#pragma once

#include "engine/engine_settings.h"
#include "engine/stats.h"

#include <cstddef>

namespace rayproc {

class Cluster;
class PhaseLog;
class EmbreeScene;
class IrradianceCache;
struct GiData;
struct LightSet;
struct Scene;

// What the prepass did: the records it inserted, and the levels it traced a second time
// because they wanted more gathers than two a pixel (smooth glass splitting the camera's
// paths; cache_prepass.cpp, traceLevelWhole).
struct CachePrepassCounts {
    std::size_t records = 0;
    int levelsRetraced = 0;
};

// Fills `cache` (gi.cache must point at it) coarse to fine. A collective under MPI: each rank
// gathers for its tiles of each level.
CachePrepassCounts fillIrradianceCache(const Scene& scene, const EmbreeScene& accel,
                                const LightSet& lights, const GiData& gi, IrradianceCache& cache,
                                const EngineSettings& engine, const Cluster& cluster,
                                PhaseLog* phases, Stats& stats);

} // namespace rayproc
