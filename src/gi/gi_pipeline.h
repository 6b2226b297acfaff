// gi's own place in the engine: its ray kinds, stage ids, counters and ray flag, in the slots
// the engine leaves to a mode (engine/ray_batch.h, engine/stats.h). The kinds keep the values
// they have always had: a kind's value keys its stages' sample numbers.
#pragma once

#include "engine/ray_batch.h"
#include "engine/stats.h"

namespace rayproc {

// Ray kinds.
constexpr RayKind kPhotonRay = modeRayKind(0);  // photons from the photon emitter, their bounces
constexpr RayKind kGatherRay = modeRayKind(1);  // final-gather rays from a diffuse hit
constexpr RayKind kGatherShadowRay = modeRayKind(2); // occlusion rays of a gather hit's light samples
constexpr RayKind kCorrectionRay = modeRayKind(3); // one per first diffuse hit: corrects the map's bias
constexpr RayKind kCorrectionPathRay = modeRayKind(4); // the path traced on from a correction ray's far end

// Their queues (engine/pipeline.h): names for --stats, and the batches each travels in.
constexpr RayRoute kPhotonQueue{kPhotonRay, "photon", BatchType::Photons};
constexpr RayRoute kGatherQueue{kGatherRay, "gather", BatchType::Rays};
constexpr RayRoute kGatherShadowQueue{kGatherShadowRay, "gather-shadow", BatchType::Shadow};
constexpr RayRoute kCorrectionQueue{kCorrectionRay, "correction", BatchType::Rays};
constexpr RayRoute kCorrectionPathQueue{kCorrectionPathRay, "correction-path", BatchType::Rays};

// A gather ray of an irradiance-cache record (its pixel is the record's request slot).
constexpr std::uint8_t kFlagGatherRecord = kFlagModeBit;

// Stages, for --stats.
constexpr StageId kPhotonStageId = modeStage(0);     // photons emitted and scattered (out), hits (in)
constexpr StageId kGatherStageId = modeStage(1);     // final-gather rays spawned (out), resolved (in)
constexpr StageId kCorrectionStageId = modeStage(2); // correction rays spawned (out), resolved (in)

// Counters (ThreadStats::modeCounters).
enum GiCounter : int {
    kGiPhotonsStored,
    kGiCacheLookups,
    kGiCacheHits,
    kGiCausticLookups,
    kGiGlobalLookups,
    kGiCounterCount
};
static_assert(kGiCounterCount <= ThreadStats::kModeCounterCount);
inline std::uint64_t& giCounter(ThreadStats& s, GiCounter c) { return s.modeCounters[c]; }
inline std::uint64_t giCounter(const ThreadStats& s, GiCounter c) { return s.modeCounters[c]; }

} // namespace rayproc
