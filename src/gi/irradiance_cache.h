// Ward's irradiance cache (Ward, Rubinstein & Clear 1988) with Ward & Heckbert's irradiance
// gradients (1992), stored in an octree.
//
// Consumes: irradiance records computed by a final gather (position, normal, irradiance, the
// harmonic mean distance R_i of the gather rays, optional gradients), inserted between passes.
// Produces: the interpolated irradiance at a shading point (p, n) when enough records are
// close, or "no usable record" so that the caller computes a new one.
//
// Interpolation (Ward 1988, eq. 1-2):
//   eps_i(p, n) = |p - p_i| / R_i + sqrt(max(0, 1 - n . n_i))      (the error estimate)
//   w_i(p, n)   = 1 / eps_i                                          (Ward's weight)
//   record i is usable  <=>  w_i > 1/a  <=>  eps_i < a,  and it is not "in front" of p:
//   d_i = (p - p_i) . (n + n_i) / 2 >= -kFrontTolerance * R_i
//   E(p, n) = sum_i w_i E_i'(p, n) / sum_i w_i over the usable records, with
//   E_i'(p, n) = E_i + (n_i x n) . gradR_i + (p - p_i) . gradT_i   (per channel, clamped at 0)
// when gradients are enabled, E_i' = E_i otherwise. See docs/irradiance-cache.md.
//
// Since eps_i >= |p - p_i| / R_i, a usable record lies within its validity radius a R_i of p.
// The octree stores each record once, in the node at its position whose side is between 2 and
// 4 validity radii (or higher up, in a bucket, where records are sparse), and every node keeps
// the bounding box of the validity spheres of its subtree, so a lookup visits exactly the
// nodes whose "reach" contains p.
#pragma once

#include "core/math.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace rayproc {

struct IrradianceRecord {
    Vec3 position;
    Vec3 normal;      // unit
    Vec3 irradiance;  // RGB
    float radius = 0; // harmonic mean distance of the gather rays, clamped by the caller
    // Ward & Heckbert gradients per RGB channel c: gradT[c] = dE_c / dp (translation, in the
    // tangent plane), gradR[c] = dE_c / d(rotation vector) (rotation of the normal). Zero =
    // unused.
    Vec3 gradT[3]{};
    Vec3 gradR[3]{};
    // How the record was gathered, for refining it later (gi/cache_refinement.h): the rays'
    // origin (off the surface), the geometric normal they stay above, and their count.
    Vec3 gatherOrigin;
    Vec3 geometricNormal;
    int gatherRays = 0;
};

struct IrradianceCacheSettings {
    float accuracy = 0.2f; // Ward's a: the largest error estimate eps_i a usable record may have
    bool useGradients = true;
};

// The per-stratum results of a cosine-weighted stratified final gather, the input of
// IrradianceCache::estimateGradients. Stratum (j, k), j < thetaCount (M), k < phiCount (N),
// covers the directions of the local frame (u, v, n)
//   sin^2(theta) in [j / M, (j + 1) / M),  phi in [2 pi k / N, 2 pi (k + 1) / N),
//   direction = sin(theta) cos(phi) u + sin(theta) sin(phi) v + cos(theta) n,
// so every stratum carries the same cosine-weighted solid angle pi / (M N) and the gathered
// irradiance is E = pi / (M N) sum_jk L_jk.
struct GatherStrata {
    int thetaCount = 0;              // M
    int phiCount = 0;                // N
    std::span<const Vec3> radiance;  // L_jk at [j * N + k]: incident radiance of stratum (j, k)
    std::span<const float> distance; // r_jk at [j * N + k]: hit distance, kInfinity for a miss
};

class IrradianceCache {
public:
    // Records inside worldBounds (expanded to a cube) descend the octree; records outside it
    // are kept at the root, so any bounds are correct, tight ones are fast.
    IrradianceCache(const Bounds3& worldBounds, IrradianceCacheSettings settings);

    // Inserts records in the given order (record index = insertion order) and rebuilds the
    // octree over all records, O(records x depth): insert a pass's records at once, not one by
    // one. The same sequence of inserts gives the same cache and the same lookups. Not
    // concurrent with lookups. Radii must be positive and finite, positions finite (checked).
    void insert(const std::vector<IrradianceRecord>& records);

    std::size_t size() const { return m_records.size(); }
    std::size_t memoryBytes() const;
    const IrradianceCacheSettings& settings() const { return m_settings; }

    struct LookupResult {
        Vec3 irradiance;
        float weightSum = 0;
        int used = 0;
    };
    // Interpolates E(p, n) for a unit normal n; false when no record is usable (out is then
    // zeroed). Usable records are summed in insertion order, so the result depends only on
    // the records and their order, never on the tree: it is bit-identical to
    // lookupBruteForce. Const and thread-safe.
    bool lookup(const Vec3& p, const Vec3& n, LookupResult& out) const;
    // The same rules over every record, without the octree (tests and debugging).
    bool lookupBruteForce(const Vec3& p, const Vec3& n, LookupResult& out) const;

    // Every record, in insertion order (the debug view).
    const std::vector<IrradianceRecord>& records() const { return m_records; }
    // Replaces record i's irradiance (a refined estimate; gradients are kept). Not concurrent
    // with lookups.
    void setIrradiance(std::size_t i, const Vec3& irradiance) { m_records[i].irradiance = irradiance; }

    // Ward & Heckbert's gradient estimates from a stratified gather at a record with the
    // orthonormal frame (u, v, n) of GatherStrata. Writes gradT[c] and gradR[c] for each channel
    // c; the formulas are in docs/irradiance-cache.md. A boundary between two strata moves
    // at the speed of the closer hit: between two misses (kInfinity) it adds nothing to the
    // translational gradient, nor when a distance is not positive.
    static void estimateGradients(const GatherStrata& strata, const Vec3& u, const Vec3& v,
                                  const Vec3& n, Vec3 gradT[3], Vec3 gradR[3]);

    // A record whose d_i is below -kFrontTolerance * R_i is "in front" of p and not used.
    static constexpr float kFrontTolerance = 0.01f;
    // eps_i is clamped below by this before w_i = 1 / eps_i (a query at a record's own
    // position and normal would otherwise have an infinite weight).
    static constexpr float kMinError = 1e-6f;
    // Depth limit of the octree: records with a smaller validity radius stay at this depth.
    static constexpr int kMaxDepth = 20;
    // A subtree that would hold at most this many records below its root keeps them in its
    // root instead (a bucket): sparse records do not each get a chain of nearly empty nodes.
    static constexpr std::size_t kBucketSize = 8;

private:
    // What a lookup reads of a record: 32 bytes, two to a cache line.
    struct Entry {
        Vec3 position;
        float invRadius;
        Vec3 normal;
        std::uint32_t index; // into m_records
    };
    // An octree node: its records are m_entries[entryBegin, entryEnd), its children (only the
    // non-empty octants) m_nodes[firstChild, firstChild + childCount).
    struct Node {
        Bounds3 reach; // union of the validity boxes of the records in this subtree
        std::uint32_t firstChild = 0, childCount = 0;
        std::uint32_t entryBegin = 0, entryEnd = 0;
    };
    struct Candidate {
        std::uint32_t index;
        float weight;
    };
    class CandidateList;

    static Entry makeEntry(const IrradianceRecord& r, std::uint32_t index);
    float weight(const Entry& e, const Vec3& p, const Vec3& n) const;
    Vec3 extrapolate(const IrradianceRecord& r, const Vec3& p, const Vec3& n) const;
    bool interpolate(CandidateList& candidates, const Vec3& p, const Vec3& n,
                     LookupResult& out) const;
    int targetDepth(const IrradianceRecord& r) const;
    void rebuild();
    void buildNode(std::uint32_t node, const Vec3& center, float halfSize, int depth,
                   std::span<std::uint32_t> items, std::span<std::uint32_t> scratch,
                   const std::vector<std::uint8_t>& depths);

    IrradianceCacheSettings m_settings;
    Vec3 m_rootCenter;
    float m_rootHalfSize = 0.5f;
    std::vector<IrradianceRecord> m_records;
    std::vector<Entry> m_entries; // grouped by node
    std::vector<Node> m_nodes;    // m_nodes[0] is the root cube
};

} // namespace rayproc
