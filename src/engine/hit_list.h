// The hits of one batch that a stage must continue: lane indices and their resolved surfaces.
#pragma once

#include "accel/embree_scene.h"
#include "engine/ray_batch.h"

namespace rayproc {

struct HitList {
    int count = 0;
    std::array<int, kBatchSize> lane;
    std::array<SurfaceHit, kBatchSize> hit;
    void add(int i, const SurfaceHit& h) {
        lane[count] = i;
        hit[count] = h;
        ++count;
    }
};

} // namespace rayproc
