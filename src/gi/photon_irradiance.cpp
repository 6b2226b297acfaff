// Irradiance from the photon map: Jensen's density estimate with the cone filter (Jensen 2001,
// ch. 7.2) and Christensen's precomputed irradiance (Christensen 1999, "Faster photon map global
// illumination", JGT 4(3)).
//
// Density estimation: the k nearest photons lie in a disc of radius r around p, so the flux per
// unit area arriving at p is E ~ sum(power_i) / (pi r^2). The cone filter weights photon i by
// w_i = 1 - d_i / (kConeK r); for photons spread uniformly over the disc the mean weight is
//   (1/(pi r^2)) int_0^r (1 - d/(k r)) 2 pi d dd = 1 - 2/(3k),
// which is the normalisation, so a uniform density is estimated without bias while photons
// close to p count more (sharper caustic edges).
//
// Precomputation: the estimate at every stride-th photon, stored as RGBE in a kd-tree of those
// photons alone; a lookup is then one 1-nearest search instead of a k-nearest search and a sum.
#include "gi/photon_heap.h"
#include "gi/photon_kdtree.h"
#include "gi/photon_map.h"

#include "cluster/cluster.h"
#include "core/error.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <type_traits>

namespace rayproc {

namespace {

// The cone-filtered flux of the photons within `radius` of p that lie on the query's surface
// (stored normal within kNormalCos of n, inside Jensen's disc) and arrive from above.
class ConeSum {
public:
    ConeSum(const Vec3& p, const Vec3& n, float radius, float radius2)
        : m_p(p), m_n(n), m_radius2(radius2), m_invConeRadius(1.0f / (PhotonMap::kConeK * radius)),
          m_slab(PhotonMap::kDiscThickness * radius) {}
    // `weight`: a factor of the photon's power (the BSDF value of a radiance estimate).
    void add(const PhotonMap::StoredPhoton& s, float dist2, const Vec3& weight = Vec3(1.0f)) {
        if (counts(s)) addCounted(decodeRgbe(s.power) * weight, dist2);
    }
    // Whether photon s lies on the query's surface and arrives from above.
    bool counts(const PhotonMap::StoredPhoton& s) const {
        if (!withinCone(decodeNormalRaw(s.normalAxis), m_n, PhotonMap::kNormalCos)) return false;
        if (std::abs(dot(Vec3(s.pos[0], s.pos[1], s.pos[2]) - m_p, m_n)) > m_slab) return false;
        return dot(decodeDirectionRaw(s.direction), m_n) > 0;
    }
    // A counted photon's weighted power.
    void addCounted(const Vec3& power, float dist2) {
        m_sum += power * (1.0f - std::sqrt(dist2) * m_invConeRadius);
        ++m_count;
    }
    std::uint32_t count() const { return m_count; }
    Vec3 irradiance() const {
        constexpr float kConeNorm = 1.0f - 2.0f / (3.0f * PhotonMap::kConeK);
        return m_sum / (kConeNorm * kPi * m_radius2);
    }

private:
    Vec3 m_p, m_n;
    float m_radius2, m_invConeRadius, m_slab;
    Vec3 m_sum{0.0f};
    std::uint32_t m_count = 0;
};

} // namespace

template <class Weight>
Vec3 PhotonMap::coneEstimate(const Vec3& p, const Vec3& n, int k, float maxDistance,
                             const Weight& weight) const {
    KeyBuffer buffer(k, m_photons.size());
    std::uint64_t* keys = buffer.data();
    float radius2 = 0;
    int count = gather(p, k, maxDistance, keys, radius2);
    if (count == 0 || !(radius2 > 0)) return Vec3(0);

    ConeSum sum(p, n, std::sqrt(radius2), radius2);
    for (int j = 0; j < count; ++j) {
        const StoredPhoton& s = m_photons[photon_heap::keyIndex(keys[j])];
        sum.add(s, photon_heap::keyDist2(keys[j]), weight(s));
    }
    return sum.irradiance();
}

Vec3 PhotonMap::irradiance(const Vec3& p, const Vec3& n, int k, float maxDistance) const {
    return inWatts(
        coneEstimate(p, n, k, maxDistance, [](const StoredPhoton&) { return Vec3(1.0f); }));
}

Vec3 PhotonMap::radiance(const Vec3& p, const Vec3& n, int k, float maxDistance,
                         const std::function<Vec3(const Vec3& wi)>& f) const {
    return inWatts(coneEstimate(
        p, n, k, maxDistance, [&](const StoredPhoton& s) { return f(decodeDirection(s.direction)); }));
}

Vec3 PhotonMap::luminanceRadiance(const Vec3& p, const Vec3& n, int k, float maxDistance,
                                  int channel, const std::function<Vec3(const Vec3& wi)>& f,
                                  Vec3& irradiance) const {
    irradiance = Vec3(0.0f);
    KeyBuffer buffer(k, m_photons.size());
    std::uint64_t* keys = buffer.data();
    float radius2 = 0;
    int count = gather(p, k, maxDistance, keys, radius2);
    if (count == 0 || !(radius2 > 0)) return Vec3(0);
    ConeSum radiance(p, n, std::sqrt(radius2), radius2), all(p, n, std::sqrt(radius2), radius2);
    for (int j = 0; j < count; ++j) {
        const StoredPhoton& s = m_photons[photon_heap::keyIndex(keys[j])];
        if (!radiance.counts(s)) continue;
        const Vec3 power = decodeRgbe(s.power);
        const float d2 = photon_heap::keyDist2(keys[j]);
        radiance.addCounted(f(decodeDirection(s.direction)) * power[channel], d2);
        all.addCounted(power, d2);
    }
    irradiance = inWatts(all.irradiance());
    return inWatts(radiance.irradiance());
}

Vec3 PhotonMap::irradianceWithin(const Vec3& p, const Vec3& n, float radius,
                                 std::uint32_t* counted) const {
    if (counted) *counted = 0;
    if (m_photons.empty() || !(radius > 0)) return Vec3(0);
    float radius2 = radius * radius;
    ConeSum sum(p, n, radius, radius2);
    kdtree::search(m_photons.data(), m_photons.size(), p, radius2,
                   [&](std::size_t i, float d2) { sum.add(m_photons[i], d2); });
    if (counted) *counted = sum.count();
    return inWatts(sum.irradiance());
}

PhotonMap::WavelengthSplit PhotonMap::irradianceSplit(
    const Vec3& p, const Vec3& n, float radius,
    const std::function<float(float, const Vec3&)>& oneWavelength, std::uint32_t* counted) const {
    if (counted) *counted = 0;
    WavelengthSplit out;
    if (m_photons.empty() || !(radius > 0)) return out;
    float radius2 = radius * radius;
    ConeSum others(p, n, radius, radius2), one(p, n, radius, radius2);
    kdtree::search(m_photons.data(), m_photons.size(), p, radius2, [&](std::size_t i, float d2) {
        const StoredPhoton& s = m_photons[i];
        const float lambda = m_wavelength.empty() ? 0.0f : m_wavelength[i];
        if (!others.counts(s)) return;
        if (lambda > 0)
            one.addCounted(Vec3(oneWavelength(lambda, decodeRgbe(s.power)), 0.0f, 0.0f), d2);
        else
            others.addCounted(decodeRgbe(s.power), d2);
    });
    if (counted) *counted = others.count() + one.count();
    out.others = inWatts(others.irradiance());
    out.oneWavelength = inWatts(one.irradiance()).x;
    return out;
}

float PhotonMap::neighbourRadius2(const Vec3& p, int k, float maxDistance,
                                 std::uint32_t* found) const {
    if (found) *found = 0;
    if (m_photons.empty() || k <= 0) return maxDistance * maxDistance;
    KeyBuffer buffer(k, m_photons.size());
    float radius2 = 0;
    int count = gather(p, k, maxDistance, buffer.data(), radius2);
    if (found) *found = std::uint32_t(count);
    return count < k ? maxDistance * maxDistance : radius2;
}

float PhotonMap::medianNeighbourRadius(int k, float maxDistance, int samples) const {
    if (m_photons.empty() || samples <= 0) return 0.0f;
    std::size_t n = std::min(m_photons.size(), std::size_t(samples));
    std::vector<float> radii(n);
    KeyBuffer buffer(k, m_photons.size());
    std::uint64_t* keys = buffer.data();
    for (std::size_t j = 0; j < n; ++j) {
        const StoredPhoton& s = m_photons[j * m_photons.size() / n];
        float radius2 = 0;
        gather(Vec3(s.pos[0], s.pos[1], s.pos[2]), k, maxDistance, keys, radius2);
        radii[j] = std::sqrt(radius2);
    }
    std::nth_element(radii.begin(), radii.begin() + n / 2, radii.end());
    return radii[n / 2];
}

bool PhotonMap::precomputeIrradiance(int k, float maxDistance, int stride,
                                     std::atomic<std::size_t>* done,
                                     const std::function<bool()>& stop,
                                     const Cluster* cluster) {
    RAYPROC_CHECK(stride >= 1);
    std::size_t step = std::size_t(stride);
    std::size_t count = precomputeCount(stride);
    std::atomic<bool> stopped{false};
    std::uint64_t first = 0, last = count;
    if (cluster) shareOf(count, cluster->rank(), cluster->size(), first, last);

    // The estimates, in subset order j (photon j * stride); each slot is written by one task.
    std::vector<PrecomputedPhoton> subset(count);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(first, last, 256),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          if (stopped.load(std::memory_order_relaxed)) return;
                          if (stop && stop()) {
                              stopped = true;
                              return;
                          }
                          for (std::size_t j = r.begin(); j != r.end(); ++j) {
                              PrecomputedPhoton& out = subset[j];
                              out = subsetPhoton(m_photons[j * step]);
                              out.irradiance = subsetEstimate(out, k, maxDistance);
                          }
                          if (done) done->fetch_add(r.size(), std::memory_order_relaxed);
                      });
    if (cluster && cluster->distributed()) {
        // The shares are contiguous in rank order: their concatenation is the whole subset.
        static_assert(std::is_trivially_copyable_v<PrecomputedPhoton>);
        std::vector<std::uint8_t> mine((last - first) * sizeof(PrecomputedPhoton));
        if (!mine.empty()) std::memcpy(mine.data(), &subset[first], mine.size());
        std::vector<std::uint8_t> all = cluster->gatherAll(mine);
        RAYPROC_CHECK(all.size() == count * sizeof(PrecomputedPhoton));
        if (!all.empty()) std::memcpy(subset.data(), all.data(), all.size());
    }
    if (stopped) return false;
    m_deferred.clear();
    m_deferred.shrink_to_fit();
    buildPrecomputedTree(std::move(subset));
    return true;
}

PhotonMap::PrecomputedPhoton PhotonMap::subsetPhoton(const StoredPhoton& s) {
    PrecomputedPhoton out;
    std::copy_n(s.pos, 3, out.pos);
    out.irradiance = {};
    out.normalAxis = std::uint16_t(s.normalAxis & 0x3fffu);
    return out;
}

Rgbe PhotonMap::subsetEstimate(const PrecomputedPhoton& s, int k, float maxDistance) const {
    // decodeNormal reads the low 14 bits: the photon's normal, whether or not the top two
    // already hold this tree's split axis.
    // In units (setPowerUnit): RGBE saturates at 1.7e38.
    return encodeRgbe(coneEstimate(Vec3(s.pos[0], s.pos[1], s.pos[2]), decodeNormal(s.normalAxis),
                                   k, maxDistance, [](const StoredPhoton&) { return Vec3(1.0f); }));
}

void PhotonMap::buildPrecomputedTree(std::vector<PrecomputedPhoton> subset) {
    const std::size_t count = subset.size();
    kdtree::BuildKeys keys(count);
    for (std::size_t j = 0; j < count; ++j) {
        const PrecomputedPhoton& s = subset[j];
        keys[j] = {{s.pos[0], s.pos[1], s.pos[2]}, std::uint32_t(j)};
    }
    std::vector<std::uint8_t> axis;
    kdtree::build(keys, axis);
    m_precomputed.resize(count);
    m_precomputed.shrink_to_fit();
    for (std::size_t i = 0; i < count; ++i) {
        m_precomputed[i] = subset[keys[i].index];
        m_precomputed[i].normalAxis |= std::uint16_t(unsigned(axis[i]) << 14);
    }
    m_hasPrecomputed = true;
}

void PhotonMap::deferIrradiance(int k, float maxDistance, int stride) {
    RAYPROC_CHECK(stride >= 1);
    const std::size_t step = std::size_t(stride), count = precomputeCount(stride);
    std::vector<PrecomputedPhoton> subset(count);
    for (std::size_t j = 0; j < count; ++j) subset[j] = subsetPhoton(m_photons[j * step]);
    m_deferredK = k;
    m_deferredMaxDistance = maxDistance;
    std::vector<std::atomic<std::uint64_t>> slots(count); // value-initialised: 0, not made
    m_deferred.swap(slots);
    buildPrecomputedTree(std::move(subset));
}

Rgbe PhotonMap::precomputedIrradiance(std::size_t i) const {
    if (m_deferred.empty()) return m_precomputed[i].irradiance;
    std::uint64_t v = m_deferred[i].load(std::memory_order_relaxed);
    if (!(v >> 32)) {
        Rgbe e = subsetEstimate(m_precomputed[i], m_deferredK, m_deferredMaxDistance);
        v = (std::uint64_t(1) << 32) | std::bit_cast<std::uint32_t>(e);
        m_deferred[i].store(v, std::memory_order_relaxed);
    }
    return std::bit_cast<Rgbe>(std::uint32_t(v));
}

std::size_t PhotonMap::precomputedEstimatesMade() const {
    if (m_deferred.empty()) return m_hasPrecomputed ? m_precomputed.size() : 0;
    std::size_t made = 0;
    for (const auto& v : m_deferred) made += (v.load(std::memory_order_relaxed) >> 32) != 0;
    return made;
}

Vec3 PhotonMap::irradianceFast(const Vec3& p, const Vec3& n, int k, float maxDistance) const {
    if (m_hasPrecomputed && maxDistance > 0) {
        // 1-nearest search restricted to precomputed photons on a surface oriented like n.
        float radius2 = maxDistance * maxDistance;
        std::size_t best = m_precomputed.size();
        float bestDist2 = 0;
        kdtree::search(m_precomputed.data(), m_precomputed.size(), p, radius2,
                       [&](std::size_t node, float d2) {
                           if (best < m_precomputed.size() &&
                               photon_heap::key(d2, std::uint32_t(node)) >
                                   photon_heap::key(bestDist2, std::uint32_t(best)))
                               return;
                           if (!withinCone(decodeNormalRaw(m_precomputed[node].normalAxis), n,
                                           kPrecomputedNormalCos))
                               return;
                           best = node;
                           bestDist2 = d2;
                           radius2 = d2;
                       });
        if (best < m_precomputed.size()) return inWatts(decodeRgbe(precomputedIrradiance(best)));
    }
    return irradiance(p, n, k, maxDistance);
}

} // namespace rayproc
