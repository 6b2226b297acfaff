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
    // Spectral mode: whether the path reached this hit with all its wavelengths, so that where
    // it hit does not depend on its hero wavelength, though a dispersive material here (a
    // coat) has since left it that one alone. false where the path crossed a dispersive
    // interface before, and where the stage that made the list does not say.
    std::array<bool, kBatchSize> arrivedWhole;
    void add(int i, const SurfaceHit& h, bool sampled = false, bool whole = false) {
        lane[count] = i;
        hit[count] = h;
        lightSampled[count] = sampled;
        arrivedWhole[count] = whole;
        ++count;
    }
};

} // namespace rayproc
