// PhotonMap: building the compact kd-tree and the k-nearest-neighbour query (Jensen 2001,
// ch. 6.3-6.4). The query keeps the k best candidates in a max-heap ordered by (dist2, index)
// and shrinks the search radius to the heap's top once it holds k, so that far subtrees are
// skipped as soon as k close photons are known.
#include "gi/photon_map.h"

#include "core/error.h"
#include "core/ordered_parallel.h"
#include "gi/photon_heap.h"
#include "gi/photon_kdtree.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>

namespace rayproc {

bool PhotonMap::build(PhotonList photons, const std::function<bool()>& stop) {
    m_photons.clear();
    m_photons.shrink_to_fit();
    m_wavelength.clear();
    m_wavelength.shrink_to_fit();
    m_precomputed.clear();
    m_precomputed.shrink_to_fit();
    m_deferred.clear();
    m_deferred.shrink_to_fit();
    m_hasPrecomputed = false;
    RAYPROC_CHECK(photons.size() < (std::size_t(1) << 32));

    kdtree::BuildKeys keys(photons.size());
    std::atomic<bool> finite{true}, oneWavelength{false};
    orderedParallelFor(0, photons.size(), 16384,
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          bool ok = true, one = false;
                          for (std::size_t i = r.begin(); i != r.end(); ++i) {
                              const PhotonRecord& ph = photons[i];
                              ok &= isFinite(ph.power);
                              one |= ph.wavelength > 0;
                              keys[i] = {{ph.position.x, ph.position.y, ph.position.z},
                                         std::uint32_t(i)};
                          }
                          if (!ok) finite = false;
                          if (one) oneWavelength = true;
                      });
    RAYPROC_CHECK(finite.load()); // the powers; kdtree::build checks the positions
    std::vector<std::uint8_t> axis;
    if (!kdtree::build(keys, axis, stop)) return false;

    // Encode each photon into its node.
    std::atomic<bool> stopped{false};
    UnwrittenVector<StoredPhoton> stored(photons.size());
    std::vector<float> wavelength(oneWavelength ? photons.size() : 0);
    orderedParallelFor(0, photons.size(), 4096,
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          if (stopped.load(std::memory_order_relaxed)) return;
                          if (stop && stop()) {
                              stopped = true;
                              return;
                          }
                          // Neighbours in the tree are usually on the same surface: on a flat
                          // one the normal, and so its code, repeats.
                          Vec3 lastNormal(0);
                          std::uint16_t lastCode = encodeNormal(lastNormal);
                          for (std::size_t i = r.begin(); i != r.end(); ++i) {
                              const PhotonRecord& ph = photons[keys[i].index];
                              if (!(ph.normal == lastNormal)) {
                                  lastNormal = ph.normal;
                                  lastCode = encodeNormal(ph.normal);
                              }
                              StoredPhoton& s = stored[i];
                              s.pos[0] = ph.position.x;
                              s.pos[1] = ph.position.y;
                              s.pos[2] = ph.position.z;
                              s.power = encodeRgbe(ph.power);
                              s.direction = encodeDirection(ph.direction);
                              s.normalAxis = std::uint16_t(lastCode | (unsigned(axis[i]) << 14));
                              if (!wavelength.empty()) wavelength[i] = ph.wavelength;
                          }
                      });
    if (stopped) return false;
    m_photons = std::move(stored);
    m_wavelength = std::move(wavelength);
    return true;
}

std::size_t PhotonMap::memoryBytes() const {
    return m_photons.capacity() * sizeof(StoredPhoton) + m_wavelength.capacity() * sizeof(float) +
           m_precomputed.capacity() * sizeof(PrecomputedPhoton) +
           m_deferred.capacity() * sizeof(std::atomic<std::uint64_t>);
}

int PhotonMap::gather(const Vec3& p, int k, float maxDistance, std::uint64_t* keys,
                      float& radius2) const {
    radius2 = 0;
    if (k <= 0 || !(maxDistance > 0)) return 0;
    float limit2 = maxDistance * maxDistance;
    int capacity = int(std::min<std::size_t>(std::size_t(k), m_photons.size()));
    float searchRadius2 = limit2;
    photon_heap::KnnCollector collect{keys, capacity, 0, searchRadius2};
    if (capacity > 0) kdtree::search(m_photons.data(), m_photons.size(), p, searchRadius2, collect);
    radius2 = collect.count == k ? photon_heap::keyDist2(keys[0]) : limit2;
    return collect.count;
}

void PhotonMap::nearest(const Vec3& p, int k, float maxDistance, Neighbours& out) const {
    KeyBuffer buffer(k, m_photons.size());
    std::uint64_t* keys = buffer.data();
    int count = gather(p, k, maxDistance, keys, out.maxDist2);
    std::sort(keys, keys + count); // ascending (dist2, index)
    out.index.resize(std::size_t(count));
    out.dist2.resize(std::size_t(count));
    for (int j = 0; j < count; ++j) {
        out.index[j] = photon_heap::keyIndex(keys[j]);
        out.dist2[j] = photon_heap::keyDist2(keys[j]);
    }
}

PhotonRecord PhotonMap::photon(std::uint32_t i) const {
    const StoredPhoton& s = m_photons[i];
    return {Vec3(s.pos[0], s.pos[1], s.pos[2]), inWatts(decodeRgbe(s.power)), decodeDirection(s.direction),
            decodeNormal(s.normalAxis)};
}

} // namespace rayproc
