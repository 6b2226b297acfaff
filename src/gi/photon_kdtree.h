// A balanced kd-tree stored implicitly in its points' array, in in-order layout with leaf
// buckets: the subtree of a range [b, b + n) has its node (the splitting point) at b + n/2,
// the left subtree in [b, b + n/2) and the right one in [b + n/2 + 1, b + n); ranges of at most
// kLeafSize points are leaves, scanned linearly. No pointers and no child indices: the tree is
// the order of the array plus one split axis per node. Shared by the photon map and by its
// precomputed-irradiance subset (Christensen 1999).
//
// This replaces Jensen's left-balanced heap layout (2001, ch. 6.3: children of i at 2i+1, 2i+2),
// which measured 1.5-1.8x slower for k = 50 queries (docs/photon-map.md): here every subtree
// is one contiguous range, so the deep levels of a search, where nearly all the visits are, stay
// in a few cache lines, while the heap layout scatters a subtree's levels over the whole array.
//
// Build: the node of a range is its median, by (coordinate, input index), on the axis along
// which the range's points (or, for large ranges, an evenly spaced sample of 256 of them)
// spread most; every point left of it is <= on that axis and every
// point right of it >=, so the tree is balanced (ceil(log2(n + 1)) levels at most) and is a
// function of the input alone.
//
// Search: walk from the root towards the query, testing each node and deferring the far side
// when its splitting plane is within the current search radius; scan the leaf; then resume the
// deferred subtrees whose plane distance is still within the (possibly shrunk) radius.
#pragma once

#include "core/math.h"
#include "core/uninitialized.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace rayproc::kdtree {

// Ranges of at most this many points are leaves.
constexpr std::size_t kLeafSize = 8;

// A point handed to the builder.
struct BuildKey {
    float p[3];
    std::uint32_t index; // the caller's index of the point
};
// Keys that vector(n) leaves unwritten: the callers' parallel loops write every one.
using BuildKeys = UnwrittenVector<BuildKey>;

// Reorders keys into the tree and sets axis[i] to the split axis (0, 1, 2) of position i when
// it is a node (0 in leaves). Afterwards keys[i].index says which input point sits at position
// i. Parallel over subtrees, same result whatever the thread count. Positions must be finite.
// When `stop` (optional, polled once per large subtree) turns true the build is abandoned, the
// tree is not valid and false is returned.
bool build(BuildKeys& keys, std::vector<std::uint8_t>& axis,
           const std::function<bool()>& stop = {});

// Squared distance, always evaluated as (dx dx + dy dy) + dz dz, so that callers comparing with
// a brute-force search get bit-identical values.
inline float distance2(const float* p, const Vec3& q) {
    float dx = q.x - p[0], dy = q.y - p[1], dz = q.z - p[2];
    return dx * dx + dy * dy + dz * dz;
}

// Calls visit(i, d2) for every point i with squared distance d2 <= maxDist2 from q, except in
// subtrees that cannot hold such a point. visit may shrink maxDist2 (a k-nearest search sets it
// to the k-th distance once k are found). Node needs `float pos[3]` and `int axis() const`.
//
// Pruning is exact in floating point: a point beyond a splitting plane has |q[a] - x[a]| >= the
// plane distance |q[a] - s[a]|, rounding is monotone, and adding non-negative squares never
// decreases a float sum, so its computed d2 >= the computed plane distance squared; subtrees are
// skipped only when that is > maxDist2. Ties at exactly maxDist2 are therefore always visited.
template <class Node, class Visit>
inline void search(const Node* nodes, std::size_t n, const Vec3& q, float& maxDist2,
                   Visit&& visit) {
    const float qv[3] = {q.x, q.y, q.z};
    struct Deferred {
        std::size_t begin, count;
        float plane2;
    };
    Deferred stack[64]; // at most one per level: n < 2^32 points have at most 32 levels
    int top = 0;
    std::size_t begin = 0, count = n;
    for (;;) {
        while (count > kLeafSize) {
            std::size_t half = count / 2, mid = begin + half;
            const Node& node = nodes[mid];
            float d2 = distance2(node.pos, q);
            if (d2 <= maxDist2) visit(mid, d2);
            int a = node.axis();
            float d = qv[a] - node.pos[a];
            float plane2 = d * d;
            std::size_t rightCount = count - half - 1;
            if (d < 0) { // near: left, far: right
                if (rightCount > 0 && plane2 <= maxDist2)
                    stack[top++] = {mid + 1, rightCount, plane2};
                count = half;
            } else {
                if (plane2 <= maxDist2) stack[top++] = {begin, half, plane2};
                begin = mid + 1;
                count = rightCount;
            }
        }
        for (std::size_t i = begin, end = begin + count; i < end; ++i) {
            float d2 = distance2(nodes[i].pos, q);
            if (d2 <= maxDist2) visit(i, d2);
        }
        do {
            if (top == 0) return;
            --top;
        } while (stack[top].plane2 > maxDist2);
        begin = stack[top].begin;
        count = stack[top].count;
    }
}

} // namespace rayproc::kdtree
