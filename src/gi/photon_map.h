// The photon map of Jensen's two-pass method (Jensen 2001, "Realistic Image Synthesis Using
// Photon Mapping", ch. 6-7): the photons the photon tracer stored, in a balanced kd-tree kept
// implicitly in the photon array (photon_kdtree.h), and radiance estimates from the k nearest
// photons. With Christensen's 1999 "Faster photon map global illumination", irradiance is
// precomputed at a subset of the photons and a lookup returns that of the nearest one.
//
// Consumes: PhotonRecords from the photon pass (position, flux, incoming direction, normal).
// Produces: k-nearest-neighbour queries and irradiance estimates for the gather pass.
//
// A stored photon is 20 bytes (kPhotonBytes): position 3 floats, power RGBE, direction octahedral
// 8+8 bits, normal octahedral 7+7 bits and the kd-tree split axis in the 2 bits left over
// (photon_encoding.h states the precision). Photon indices are storage (tree) order, not the
// order build() received them in; photon(i) for i < size() enumerates the map.
//
// Every const method is safe to call concurrently: no scratch state is shared.
#pragma once

#include "core/math.h"
#include "core/uninitialized.h"
#include "gi/photon_encoding.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace rayproc {

class Cluster;

// What the photon tracer hands over: one stored photon.
struct PhotonRecord {
    Vec3 position;
    Vec3 power;     // flux (W) carried, RGB
    Vec3 direction; // unit, pointing from the surface back towards where the photon came from
    Vec3 normal;    // unit surface normal at the hit, on the side the photon arrived from
    // 1: the direct light of a delta light or the sky, stored where the photon first landed:
    // gi's gather samples those lights at its hits instead (buildPhotonMap's `indirect` map
    // leaves these photons out). 0 otherwise.
    std::uint32_t sampledDirect = 0;
    // Spectral mode: the one wavelength (nm) a photon past dispersive glass carries (its power
    // is that wavelength's alone, SpectralRender::lane), 0 for a photon of three.
    float wavelength = 0;
};

// The photon lists between the tracer and the map. vector(n) and resize(n) leave the records
// unwritten (core/uninitialized.h): their parallel loops write every one, and the page faults of
// a few hundred thousand photons fall on those loops' threads, not on one thread's zero-fill.
using PhotonList = UnwrittenVector<PhotonRecord>;

class PhotonMap {
public:
    // The compact stored photon.
    struct StoredPhoton {
        float pos[3];
        Rgbe power;
        std::uint16_t direction;  // encodeDirection
        std::uint16_t normalAxis; // encodeNormal in the low 14 bits, split axis in the top 2
        int axis() const { return normalAxis >> 14; }
    };
    static constexpr std::size_t kPhotonBytes = 20;

    // A photon with precomputed irradiance (Christensen 1999), in a kd-tree of its own.
    struct PrecomputedPhoton {
        float pos[3];
        Rgbe irradiance;
        std::uint16_t normalAxis; // the photon's normal code, this tree's split axis
        std::uint16_t unused = 0;
        int axis() const { return normalAxis >> 14; }
    };
    static constexpr std::size_t kPrecomputedBytes = 20;

    // Cone filter constant k of w = 1 - d / (k r) (Jensen 2001, ch. 7).
    static constexpr float kConeK = 1.1f;
    // irradiance() counts photons whose stored normal is within 60 degrees of the query normal.
    static constexpr float kNormalCos = 0.5f;
    // irradianceFast() takes precomputed photons whose normal is within 25.8 degrees of it.
    static constexpr float kPrecomputedNormalCos = 0.9f;
    // Jensen's disc (2001, ch. 7.2): a photon counts only within this fraction of the search
    // radius of the query's tangent plane. Photons on a parallel surface just behind a wall or
    // a floor (the sunlit ground under a room's floor) otherwise leak into the estimate.
    static constexpr float kDiscThickness = 0.25f;

    // Builds the kd-tree (parallel; deterministic: the same input, in the same order, gives the
    // same tree whatever the thread count). Discards precomputed irradiance.
    // Positions and powers must be finite (checked); negative power channels are stored as 0;
    // direction and normal are normalised (a zero vector becomes +z). When `stop` (optional)
    // turns true during the build the map is left empty and false is returned.
    bool build(PhotonList photons, const std::function<bool()>& stop = {});
    std::size_t size() const { return m_photons.size(); }
    // Heap bytes held: the stored photons and the precomputed subset.
    std::size_t memoryBytes() const;

    // The k nearest photons to p with squared distance <= maxDistance^2, sorted by ascending
    // (dist2, index): ties in distance go to the lower index, so the result is one well-defined
    // set. maxDist2 is the squared radius of the gathered disc: the k-th distance when k photons
    // were found, maxDistance^2 otherwise (0 when k <= 0 or maxDistance <= 0, with no photons).
    // out's vectors keep their capacity between calls (k > 128 also allocates a temporary).
    struct Neighbours {
        std::vector<std::uint32_t> index;
        std::vector<float> dist2;
        float maxDist2 = 0;
    };
    void nearest(const Vec3& p, int k, float maxDistance, Neighbours& out) const;

    // Decoded photon i < size() (power, direction and normal from the compact form; the map
    // does not keep `sampledDirect`: 0).
    PhotonRecord photon(std::uint32_t i) const;

    // Irradiance at p with surface normal n from the k nearest photons within maxDistance,
    // counting those whose stored normal has dot(normal, n) > kNormalCos and that arrive from
    // above (dot(direction, n) > 0), with the cone filter:
    //   E = sum(power_i w_i) / ((1 - 2 / (3 kConeK)) pi r^2),  w_i = 1 - d_i / (kConeK r),
    // r = the distance to the k-th photon, or maxDistance when fewer were found. Zero when no
    // photon counts (or r = 0: k photons all exactly at p).
    Vec3 irradiance(const Vec3& p, const Vec3& n, int k, float maxDistance) const;

    // Radiance leaving p towards the viewer from the k nearest photons irradiance() would count
    // (Jensen 2001, eq. 7.6, with the cone filter): sum f(wi_i) power_i w_i / ((1 - 2 / (3
    // kConeK)) pi r^2), f(wi) the BSDF value (no cosine) from the photon's incoming direction
    // to the viewer, given by the caller. gi's gather uses it at glossy surfaces, where taking
    // the lobe as Lambertian misplaces the light and tracing it on is noisy.
    Vec3 radiance(const Vec3& p, const Vec3& n, int k, float maxDistance,
                  const std::function<Vec3(const Vec3& wi)>& f) const;

    // radiance() with every photon's power taken as its channel `channel` alone, in all
    // three results (spectral gi: the maps hold CIE XYZ and f is the BSDF at a path's three
    // wavelengths, so this is sum f(wi_i) Y_i w_i / (...)); `irradiance` receives irradiance()
    // of the same photons. gi scales the first by the irradiance's spectrum over its luminance.
    Vec3 luminanceRadiance(const Vec3& p, const Vec3& n, int k, float maxDistance, int channel,
                           const std::function<Vec3(const Vec3& wi)>& f, Vec3& irradiance) const;

    // Irradiance at p from every photon within `radius` that irradiance() would count, with
    // the same cone filter over that radius: the fixed-radius estimate of progressive photon
    // mapping, whose radius the caller shrinks from pass to pass (gi/progressive_caustics.h).
    // `counted` (optional) receives how many photons the estimate counted (SPPM's M).
    Vec3 irradianceWithin(const Vec3& p, const Vec3& n, float radius,
                          std::uint32_t* counted = nullptr) const;
    // The same photons as irradianceWithin, split by what they carry: photons of three
    // wavelengths sum their power into `others`, photons of one (PhotonRecord::wavelength)
    // add oneWavelength(their wavelength, their power) into `oneWavelength`, with the same
    // cone filter (gi's caustic estimate for a path of one wavelength, GatherStage).
    struct WavelengthSplit {
        Vec3 others{0.0f};
        float oneWavelength = 0;
    };
    WavelengthSplit irradianceSplit(const Vec3& p, const Vec3& n, float radius,
                                    const std::function<float(float, const Vec3&)>& oneWavelength,
                                    std::uint32_t* counted = nullptr) const;
    // Whether any stored photon carries one wavelength.
    bool hasWavelengths() const { return !m_wavelength.empty(); }
    // The distance^2 from p to its k-th nearest photon, or maxDistance^2 when fewer lie within
    // it (the radius a k-nearest estimate at p would use); `found` (optional): the photons
    // within that radius (k, or fewer at maxDistance).
    float neighbourRadius2(const Vec3& p, int k, float maxDistance,
                           std::uint32_t* found = nullptr) const;

    // The median, over up to `samples` stored photons spaced evenly in storage order, of the
    // distance from each to its k-th nearest photon (at most maxDistance): a radius matched to
    // the map's own density where its photons are. 0 for an empty map.
    float medianNeighbourRadius(int k, float maxDistance, int samples) const;

    // Precomputes irradiance(position, normal, k, maxDistance) at photons 0, stride, 2 stride...
    // (storage order), in parallel; the result does not depend on the thread count. `done`
    // (optional) counts the estimates made, for progress; when `stop` (optional) turns true the
    // remaining work is skipped, nothing is precomputed and false is returned. With a
    // distributed cluster, each rank estimates a contiguous share of the photons and every
    // rank receives all the estimates (a collective: every rank calls it, stopped or not).
    bool precomputeIrradiance(int k, float maxDistance, int stride,
                              std::atomic<std::size_t>* done = nullptr,
                              const std::function<bool()>& stop = {},
                              const Cluster* cluster = nullptr);
    std::size_t precomputeCount(int stride) const {
        return (m_photons.size() + std::size_t(stride) - 1) / std::size_t(stride);
    }
    // The same subset and kd-tree, but each photon's estimate is made the first time a lookup
    // (irradianceFast) lands on it, with this call's k and maxDistance, and kept: the
    // precomputation then costs only the photons lookups use (most of a map's photons may lie
    // outside the view). An estimate is a function of the map and the photon alone, so the
    // results equal precomputeIrradiance's bit for bit, whichever thread makes each one first
    // (two may both make it and store the same value). Serial: the tree's build only.
    void deferIrradiance(int k, float maxDistance, int stride);
    // Estimates deferIrradiance's lookups have made so far (precomputedCount() when eager).
    std::size_t precomputedEstimatesMade() const;
    bool hasPrecomputedIrradiance() const { return m_hasPrecomputed; }
    std::size_t precomputedCount() const { return m_precomputed.size(); }
    // The precomputed irradiance of the nearest precomputed photon within maxDistance whose
    // normal has dot > kPrecomputedNormalCos with n (ties: lower index in the subset); when there
    // is none, or nothing was precomputed, irradiance(p, n, k, maxDistance).
    Vec3 irradianceFast(const Vec3& p, const Vec3& n, int k, float maxDistance) const;

    // The flux one unit of stored power stands for (W; default 1). The photon emitter gives
    // photons in units of PhotonEmitter::powerUnit() so that no power overflows float; every
    // estimate above and photon() are multiplied back by it (in double; exact, a power of two).
    // The stored photons and the precomputed irradiance stay in units.
    void setPowerUnit(double unit) { m_unit = unit; }
    double powerUnit() const { return m_unit; }

private:
    Vec3 inWatts(const Vec3& v) const {
        if (m_unit == 1) return v;
        return {float(double(v.x) * m_unit), float(double(v.y) * m_unit),
                float(double(v.z) * m_unit)};
    }
    // Queries with k up to this keep their candidates on the stack.
    static constexpr int kStackCandidates = 128;

    // Room for the keys of a k-nearest query on a map of `photons`: min(k, photons) entries,
    // on the stack up to kStackCandidates, else on the heap.
    class KeyBuffer {
    public:
        KeyBuffer(int k, std::size_t photons) {
            std::size_t capacity = k > 0 ? std::min<std::size_t>(std::size_t(k), photons) : 0;
            if (capacity > std::size_t(kStackCandidates)) m_heap.resize(capacity);
        }
        KeyBuffer(const KeyBuffer&) = delete;
        KeyBuffer& operator=(const KeyBuffer&) = delete;
        std::uint64_t* data() { return m_heap.empty() ? m_stack.data() : m_heap.data(); }

    private:
        std::array<std::uint64_t, kStackCandidates> m_stack;
        std::vector<std::uint64_t> m_heap;
    };

    // Gathers the k nearest into keys (photon_heap.h; room for min(k, size()) entries,
    // kept as a max-heap once full); returns the count and sets radius2 as
    // Neighbours::maxDist2.
    int gather(const Vec3& p, int k, float maxDistance, std::uint64_t* keys, float& radius2) const;
    // The cone-filtered estimate over the k nearest photons, each photon's power times
    // weight(photon): irradiance() (weight 1) and radiance() (the BSDF value).
    template <class Weight>
    Vec3 coneEstimate(const Vec3& p, const Vec3& n, int k, float maxDistance,
                      const Weight& weight) const;

    // A subset entry for stored photon s: its position and normal code, no irradiance yet.
    static PrecomputedPhoton subsetPhoton(const StoredPhoton& s);
    // The estimate an entry holds, eager (precomputeIrradiance) or deferred alike: the one
    // function both call, so their values are the same bits.
    Rgbe subsetEstimate(const PrecomputedPhoton& s, int k, float maxDistance) const;
    // Orders `subset` (precomputed photons in subset order) into their own kd-tree.
    void buildPrecomputedTree(std::vector<PrecomputedPhoton> subset);
    // The irradiance of precomputed photon i (tree order), made now if deferred and not yet made.
    Rgbe precomputedIrradiance(std::size_t i) const;

    UnwrittenVector<StoredPhoton> m_photons; // every one written by build()
    // Per stored photon (tree order) its PhotonRecord::wavelength; empty where none has one.
    std::vector<float> m_wavelength;
    double m_unit = 1; // setPowerUnit
    std::vector<PrecomputedPhoton> m_precomputed;
    bool m_hasPrecomputed = false;
    // deferIrradiance: per precomputed photon, 0 until made, then 2^32 | the RGBE's bits.
    mutable std::vector<std::atomic<std::uint64_t>> m_deferred;
    int m_deferredK = 0;
    float m_deferredMaxDistance = 0;
};

static_assert(sizeof(PhotonMap::StoredPhoton) == PhotonMap::kPhotonBytes);
static_assert(sizeof(PhotonMap::PrecomputedPhoton) == PhotonMap::kPrecomputedBytes);

} // namespace rayproc
