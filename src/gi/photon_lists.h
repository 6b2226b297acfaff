// The photon lists between tracing and the kd-tree, made on every thread: the stored photons
// of a pass in key order, the rounds of a pass joined, and the scattered photons picked out.
// Each gives the same elements in the same order as the one-thread loop it replaces, so the
// maps, and the images, do not depend on the thread count (issue 35: the serial phases of gi).
#pragma once

#include "gi/photon_map.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace rayproc {

// A stored photon and its key, unique in a pass: (photon index << 8) | bounce.
using KeyedPhoton = std::pair<std::uint64_t, PhotonRecord>;
// A list of them that vector(n) leaves unwritten (as PhotonList).
using KeyedPhotons = UnwrittenVector<KeyedPhoton>;

// Every run's photons in one array in key order; the runs are emptied. Keys are photon-index
// major and dense over the pass's index range, so equal key ranges hold about equal counts:
// each run is scattered into buckets of equal key ranges at offsets from a prefix sum, then
// each bucket is sorted alone (keys are unique: one order is possible).
KeyedPhotons keyedInOrder(std::vector<std::vector<KeyedPhoton>*> runs);

// The rounds' photons one after the other, each photon's power divided by `divisor` (a
// round alone carries the lights' whole power); the rounds are emptied.
PhotonList joinRounds(std::vector<PhotonList>& rounds, float divisor);

// The photons that are not a delta light's or the sky's direct light (sampledDirect == 0),
// in their order.
PhotonList scatteredPhotons(const PhotonList& photons);

} // namespace rayproc
