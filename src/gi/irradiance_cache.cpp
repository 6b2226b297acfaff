// Ward's irradiance cache in an octree: insertion, lookup and interpolation. The maths is in
// irradiance_cache.h; the design (why each record is stored once, what a node's reach is, why
// usable records are summed in insertion order) in docs/irradiance-cache.md.
#include "gi/irradiance_cache.h"

#include "core/error.h"

#include <algorithm>
#include <array>
#include <limits>

namespace rayproc {

namespace {

float maxAbs(const Vec3& v) {
    return std::max(std::abs(v.x), std::max(std::abs(v.y), std::abs(v.z)));
}

bool insideCube(const Vec3& center, float halfSize, const Vec3& p) {
    return maxAbs(p - center) <= halfSize;
}

// The box around a record outside which its eps_i >= a, i.e. where it cannot be used. The
// margin (a relative 1e-3 of the validity radius plus a few float ulps of the position) keeps
// the box conservative against the rounding of the box corners and of eps_i itself.
Bounds3 validityBox(const IrradianceRecord& r, float accuracy) {
    float validity = accuracy * r.radius;
    float halfSide = validity + validity * 1e-3f + 1e-6f * maxAbs(r.position);
    return {r.position - Vec3(halfSide), r.position + Vec3(halfSide)};
}

// Lookup traversal stack: depth-first, at most 7 pending siblings per level plus 8 children.
constexpr int kStackSize = 8 * (IrradianceCache::kMaxDepth + 2);

} // namespace

// The usable records of one lookup, in the order the traversal met them. Most lookups find a
// handful, so the first kInline live on the stack.
class IrradianceCache::CandidateList {
public:
    void add(std::uint32_t index, float weight) {
        if (m_size < kInline) {
            m_inline[m_size] = {index, weight};
        } else {
            if (m_size == kInline) m_heap.assign(m_inline.begin(), m_inline.end());
            m_heap.push_back({index, weight});
        }
        ++m_size;
    }
    std::span<Candidate> items() {
        return m_size <= kInline ? std::span<Candidate>(m_inline.data(), m_size)
                                 : std::span<Candidate>(m_heap);
    }

private:
    static constexpr std::size_t kInline = 64;
    std::array<Candidate, kInline> m_inline;
    std::vector<Candidate> m_heap;
    std::size_t m_size = 0;
};

IrradianceCache::IrradianceCache(const Bounds3& worldBounds, IrradianceCacheSettings settings)
    : m_settings(settings) {
    RAYPROC_CHECK(settings.accuracy > 0 && std::isfinite(settings.accuracy));
    // The root is the bounds' bounding cube, a little larger so that points on the faces are
    // inside. Empty or non-finite bounds give a unit cube: every record outside it stays at the
    // root, which is slow but correct.
    if (!worldBounds.empty() && isFinite(worldBounds.lo) && isFinite(worldBounds.hi)) {
        m_rootCenter = worldBounds.center();
        m_rootHalfSize = 0.5f * maxComponent(worldBounds.diagonal()) * (1.0f + 1e-4f);
        m_rootHalfSize = std::max(m_rootHalfSize, 1e-6f * (1.0f + maxAbs(m_rootCenter)));
    }
    m_nodes.emplace_back();
}

void IrradianceCache::insert(const std::vector<IrradianceRecord>& records) {
    RAYPROC_CHECK(m_records.size() + records.size() < std::size_t(UINT32_MAX));
    for (const IrradianceRecord& r : records) {
        RAYPROC_CHECK(r.radius > 0 && std::isfinite(r.radius));
        RAYPROC_CHECK(isFinite(r.position) && isFinite(r.normal));
    }
    m_records.insert(m_records.end(), records.begin(), records.end());
    rebuild();
}

// Ward's placement: a record belongs at the depth where the node side is in [2, 4) validity
// radii a R_i, i.e. it goes down while the child's side (the node's half size) is at least
// 2 a R_i. Records outside the root cube belong to the root.
int IrradianceCache::targetDepth(const IrradianceRecord& r) const {
    if (!insideCube(m_rootCenter, m_rootHalfSize, r.position)) return 0;
    const float twiceValidity = 2.0f * m_settings.accuracy * r.radius;
    float halfSize = m_rootHalfSize;
    int depth = 0;
    while (depth < kMaxDepth && halfSize >= twiceValidity) {
        halfSize *= 0.5f;
        ++depth;
    }
    return depth;
}

// The octree is a pure function of the records in insertion order: rebuilt top-down, nodes
// and entries in depth-first order, entries of a node in index order.
void IrradianceCache::rebuild() {
    const std::size_t n = m_records.size();
    std::vector<std::uint8_t> depths(n);
    std::vector<std::uint32_t> items(n), scratch(n);
    for (std::size_t i = 0; i < n; ++i) {
        depths[i] = std::uint8_t(targetDepth(m_records[i]));
        items[i] = std::uint32_t(i);
    }
    m_nodes.assign(1, Node{});
    m_entries.clear();
    m_entries.reserve(n);
    buildNode(0, m_rootCenter, m_rootHalfSize, 0, items, scratch, depths);
    m_nodes.shrink_to_fit();
}

// Keeps the items that belong at this depth (all of them when at most kBucketSize would go
// deeper), sorts the others by octant (stably, so index order holds) and recurses into the
// non-empty octants, whose nodes are allocated side by side.
void IrradianceCache::buildNode(std::uint32_t node, const Vec3& center, float halfSize, int depth,
                                std::span<std::uint32_t> items, std::span<std::uint32_t> scratch,
                                const std::vector<std::uint8_t>& depths) {
    std::size_t deeper = 0;
    for (std::uint32_t i : items) deeper += depths[i] > depth ? 1 : 0;
    const bool bucket = deeper <= kBucketSize || depth == kMaxDepth;

    Bounds3 reach;
    m_nodes[node].entryBegin = std::uint32_t(m_entries.size());
    std::size_t kept = 0; // items that go deeper, compacted to the front
    for (std::uint32_t i : items) {
        if (bucket || depths[i] <= depth) {
            m_entries.push_back(makeEntry(m_records[i], i));
            reach.extend(validityBox(m_records[i], m_settings.accuracy));
        } else {
            items[kept++] = i;
        }
    }
    m_nodes[node].entryEnd = std::uint32_t(m_entries.size());

    if (!bucket) {
        // Counting sort by octant into scratch.
        auto octantOf = [&](std::uint32_t i) {
            const Vec3& p = m_records[i].position;
            return (p.x >= center.x ? 1 : 0) | (p.y >= center.y ? 2 : 0) |
                   (p.z >= center.z ? 4 : 0);
        };
        std::array<std::size_t, 9> start{};
        for (std::size_t k = 0; k < kept; ++k) ++start[std::size_t(octantOf(items[k])) + 1];
        for (int o = 0; o < 8; ++o) start[o + 1] += start[o];
        std::array<std::size_t, 8> cursor;
        std::copy(start.begin(), start.begin() + 8, cursor.begin());
        for (std::size_t k = 0; k < kept; ++k) scratch[cursor[octantOf(items[k])]++] = items[k];
        std::copy(scratch.begin(), scratch.begin() + std::ptrdiff_t(kept), items.begin());

        const auto firstChild = std::uint32_t(m_nodes.size());
        std::uint32_t childCount = 0;
        for (int o = 0; o < 8; ++o) childCount += start[o + 1] > start[o] ? 1 : 0;
        m_nodes.resize(m_nodes.size() + childCount); // invalidates references into m_nodes
        m_nodes[node].firstChild = firstChild;
        m_nodes[node].childCount = childCount;
        const float quarter = 0.5f * halfSize;
        std::uint32_t child = firstChild;
        for (int o = 0; o < 8; ++o) {
            if (start[o + 1] == start[o]) continue;
            Vec3 childCenter =
                center + Vec3((o & 1) ? quarter : -quarter, (o & 2) ? quarter : -quarter,
                              (o & 4) ? quarter : -quarter);
            std::size_t count = start[o + 1] - start[o];
            buildNode(child, childCenter, quarter, depth + 1, items.subspan(start[o], count),
                      scratch.subspan(start[o], count), depths);
            reach.extend(m_nodes[child].reach);
            ++child;
        }
    }
    m_nodes[node].reach = reach;
}

IrradianceCache::Entry IrradianceCache::makeEntry(const IrradianceRecord& r, std::uint32_t index) {
    return {r.position, 1.0f / r.radius, r.normal, index};
}

// Ward's weight w_i = 1 / eps_i when the record is usable (eps_i < a and not in front of p),
// 0 otherwise. The one function both lookups use, so they agree on every bit.
float IrradianceCache::weight(const Entry& e, const Vec3& p, const Vec3& n) const {
    const float a = m_settings.accuracy;
    Vec3 d = p - e.position;
    float distanceTerm = std::sqrt(dot(d, d)) * e.invRadius;
    if (!(distanceTerm < a)) return 0; // eps_i >= |p - p_i| / R_i; also rejects NaN
    float error = distanceTerm + std::sqrt(std::max(0.0f, 1.0f - dot(n, e.normal)));
    if (!(error < a)) return 0;
    // In front: p_i lies above the plane through p with the mean normal, so it may see
    // surfaces that p does not. d_i / R_i keeps the tolerance relative to the local scale.
    float front = 0.5f * dot(d, n + e.normal) * e.invRadius;
    if (front < -kFrontTolerance) return 0;
    return 1.0f / std::max(error, kMinError);
}

// E_i'(p, n) = E_i + (n_i x n) . gradR + (p - p_i) . gradT per channel: the first-order
// Taylor expansion of the record's irradiance in rotation and translation (Ward & Heckbert).
// The translational step is limited to E_i |p - p_i| / R_i, the change the split-sphere model
// (by which R_i was chosen: the distance term of Ward's error estimate) allows between p_i and
// p. The gradients come from the prepass's one gather and are never refined, and the
// translational one divides by hit distances: a gather that catches a sunlit gap close by in a
// few of its strata made it tens of times steeper than that (docs/irradiance-cache.md, "Limiting
// the translational gradient"). A steep gradient may still extrapolate below zero; irradiance
// cannot, so the result is clamped there.
Vec3 IrradianceCache::extrapolate(const IrradianceRecord& r, const Vec3& p, const Vec3& n) const {
    if (!m_settings.useGradients) return r.irradiance;
    Vec3 rotation = cross(r.normal, n);
    Vec3 translation = p - r.position;
    const float distanceTerm = r.radius > 0
                                   ? std::sqrt(dot(translation, translation)) / r.radius
                                   : std::numeric_limits<float>::infinity();
    Vec3 e;
    for (int c = 0; c < 3; ++c) {
        const float bound = r.irradiance[c] > 0 ? distanceTerm * r.irradiance[c] : 0.0f;
        const float step = std::clamp(dot(translation, r.gradT[c]), -bound, bound);
        e[c] = std::max(0.0f, r.irradiance[c] + dot(rotation, r.gradR[c]) + step);
    }
    return e;
}

// Sums the usable records in insertion order, in double: each w_i E_i is exact in double and
// the sums lose ~1e-16 per term, so equal E_i interpolate to exactly E_i after rounding.
bool IrradianceCache::interpolate(CandidateList& candidates, const Vec3& p, const Vec3& n,
                                  LookupResult& out) const {
    std::span<Candidate> items = candidates.items();
    out = LookupResult{};
    if (items.empty()) return false;
    std::sort(items.begin(), items.end(),
              [](const Candidate& x, const Candidate& y) { return x.index < y.index; });
    double weightSum = 0;
    double sum[3] = {0, 0, 0};
    for (const Candidate& c : items) {
        Vec3 e = extrapolate(m_records[c.index], p, n);
        weightSum += double(c.weight);
        for (int k = 0; k < 3; ++k) sum[k] += double(c.weight) * double(e[k]);
    }
    out.irradiance =
        Vec3(float(sum[0] / weightSum), float(sum[1] / weightSum), float(sum[2] / weightSum));
    out.weightSum = float(weightSum);
    out.used = int(items.size());
    return true;
}

// Visits the nodes whose reach contains p: a record can be usable at p only if p is inside
// its validity box, and every such box is inside the reach of every node on the record's path.
bool IrradianceCache::lookup(const Vec3& p, const Vec3& n, LookupResult& out) const {
    CandidateList candidates;
    if (m_nodes[0].reach.contains(p)) {
        std::array<std::uint32_t, kStackSize> stack;
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& node = m_nodes[stack[--top]];
            for (std::uint32_t e = node.entryBegin; e < node.entryEnd; ++e) {
                float w = weight(m_entries[e], p, n);
                if (w > 0) candidates.add(m_entries[e].index, w);
            }
            const std::uint32_t childEnd = node.firstChild + node.childCount;
            for (std::uint32_t child = node.firstChild; child < childEnd; ++child) {
                if (m_nodes[child].reach.contains(p)) stack[top++] = child;
            }
        }
    }
    return interpolate(candidates, p, n, out);
}

bool IrradianceCache::lookupBruteForce(const Vec3& p, const Vec3& n, LookupResult& out) const {
    CandidateList candidates;
    for (std::size_t i = 0; i < m_records.size(); ++i) {
        float w = weight(makeEntry(m_records[i], std::uint32_t(i)), p, n);
        if (w > 0) candidates.add(std::uint32_t(i), w);
    }
    return interpolate(candidates, p, n, out);
}

std::size_t IrradianceCache::memoryBytes() const {
    return sizeof(*this) + m_records.capacity() * sizeof(IrradianceRecord) +
           m_entries.capacity() * sizeof(Entry) + m_nodes.capacity() * sizeof(Node);
}

} // namespace rayproc
