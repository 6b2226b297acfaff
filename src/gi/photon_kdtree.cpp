// Balanced kd-tree construction (Jensen 2001, ch. 6.3.2, in the in-order layout of
// photon_kdtree.h): median splits by selection, not sorting, O(n log n) overall; the two halves
// of every large range are built in parallel. Everything happens in place in the keys' array.
#include "gi/photon_kdtree.h"

#include "core/error.h"
#include "core/ordered_parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <atomic>
#include <cmath>

namespace rayproc::kdtree {
namespace {

// Below this many points a subtree is built on the calling thread.
constexpr std::size_t kParallelGrain = 8192;
// Ranges of more than twice this many points choose their split axis from a sample this large.
constexpr std::size_t kBoundsSample = 256;

// Polled once per subtree of at least kParallelGrain points; set once the build is abandoned.
struct StopCheck {
    const std::function<bool()>& stop;
    std::atomic<bool> stopped{false};
    bool operator()() {
        if (stopped.load(std::memory_order_relaxed)) return true;
        if (stop && stop()) stopped = true;
        return stopped.load(std::memory_order_relaxed);
    }
};

void buildRange(BuildKey* keys, std::uint8_t* axis, std::size_t n, StopCheck& stop) {
    if (n <= kLeafSize) return;
    if (n >= kParallelGrain && stop()) return;
    // Split the axis along which the range's points spread most (the lowest on ties). The bounds
    // are measured, not inherited from the parent's cut: photons lie on surfaces, and a cut box
    // would keep splitting a wall across its thickness of zero. Large ranges measure a sample of
    // kBoundsSample evenly spaced points: the axis only steers the tree's shape, and scanning
    // every point of every level was a third of the build.
    std::size_t step = n > 2 * kBoundsSample ? n / kBoundsSample : 1;
    float lo[3] = {keys[0].p[0], keys[0].p[1], keys[0].p[2]};
    float hi[3] = {lo[0], lo[1], lo[2]};
    for (std::size_t i = step; i < n; i += step) {
        for (int c = 0; c < 3; ++c) {
            lo[c] = std::min(lo[c], keys[i].p[c]);
            hi[c] = std::max(hi[c], keys[i].p[c]);
        }
    }
    int a = 0;
    for (int c = 1; c < 3; ++c) {
        if (hi[c] - lo[c] > hi[a] - lo[a]) a = c;
    }
    std::size_t half = n / 2;
    std::nth_element(keys, keys + half, keys + n, [a](const BuildKey& x, const BuildKey& y) {
        return x.p[a] < y.p[a] || (x.p[a] == y.p[a] && x.index < y.index);
    });
    axis[half] = std::uint8_t(a);

    auto left = [&] { buildRange(keys, axis, half, stop); };
    auto right = [&] { buildRange(keys + half + 1, axis + half + 1, n - half - 1, stop); };
    if (n >= kParallelGrain) {
        // The halves' keys were just moved by this thread (ordered where TSan sees it).
        orderedParallelInvoke(left, right);
    } else {
        left();
        right();
    }
}

} // namespace

bool build(BuildKeys& keys, std::vector<std::uint8_t>& axis, const std::function<bool()>& stop) {
    RAYPROC_CHECK(keys.size() < (std::size_t(1) << 32));
    std::atomic<bool> finite{true};
    orderedParallelFor(0, keys.size(), 16384,
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          bool ok = true;
                          for (std::size_t i = r.begin(); i != r.end(); ++i) {
                              const BuildKey& k = keys[i];
                              ok &= std::isfinite(k.p[0]) && std::isfinite(k.p[1]) &&
                                    std::isfinite(k.p[2]);
                          }
                          if (!ok) finite = false;
                      });
    RAYPROC_CHECK(finite.load()); // every position
    axis.assign(keys.size(), 0);
    StopCheck check{stop};
    buildRange(keys.data(), axis.data(), keys.size(), check);
    return !check.stopped.load();
}

} // namespace rayproc::kdtree
