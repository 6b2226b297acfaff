// The hits of one batch that a stage must continue: lane indices and their resolved surfaces.
#pragma once

#include "accel/embree_scene.h"
#include "engine/ray_batch.h"

namespace rayproc {

struct HitList {
    int count = 0;
    std::array<int, kBatchSize> lane;
    std::array<SurfaceHit, kBatchSize> hit;
    // Whether the shadow stage light-samples this hit too (the reflection stage's MIS).
    std::array<bool, kBatchSize> lightSampled;
    void add(int i, const SurfaceHit& h, bool sampled = false) {
        lane[count] = i;
        hit[count] = h;
        lightSampled[count] = sampled;
        ++count;
    }
};

} // namespace rayproc
