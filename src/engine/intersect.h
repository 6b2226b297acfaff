// The one intersection handler shared by every pass (the paper's "ray-intersection handler").
// It turns a batch into Embree packets of width K (1, 4, 8 or 16) with valid masks, traces
// them, and writes the hits back into the batch. Batches of rays and of photons (RayBatch,
// PhotonBatch: HitBatch) get their closest hits; occlusion batches (ShadowBatch: shadow rays,
// and the kinds a mode routes as such) use occlusion queries.
#pragma once

#include "engine/ray_batch.h"
#include "engine/stats.h"

#include <embree3/rtcore.h>

namespace rayproc {

class RayRecorder;

class Intersector {
public:
    // width: 1 selects single-ray rtcIntersect1 / rtcOccluded1; 4, 8, 16 select packets.
    Intersector(RTCScene scene, int width);
    int width() const { return m_width; }
    // Closest hits of a batch of rays or photons; whether each occlusion ray is blocked
    // (tfar < 0).
    void trace(HitBatch& batch, ThreadStats& stats) const;
    void trace(ShadowBatch& batch, ThreadStats& stats) const;

private:
    RTCIntersectContext begin(WorkBatch& batch, ThreadStats& stats, bool occlusion) const;

    RTCScene m_scene;
    int m_width;
    RayRecorder* m_recorder; // benchmarks only (engine/ray_recorder.h); null otherwise
};

bool isValidPacketWidth(int width);

} // namespace rayproc
