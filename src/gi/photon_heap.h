// The candidate list of a k-nearest search: a max-heap of 64-bit keys (dist2 bits << 32 | index).
// Squared distances are non-negative floats, whose bit patterns order like the values, so one
// integer comparison orders by (dist2, index): ties in distance go to the lower index, and "the
// k nearest" is one well-defined set.
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>

namespace rayproc::photon_heap {

inline std::uint64_t key(float dist2, std::uint32_t index) {
    return (std::uint64_t(std::bit_cast<std::uint32_t>(dist2)) << 32) | index;
}
inline float keyDist2(std::uint64_t k) {
    return std::bit_cast<float>(std::uint32_t(k >> 32));
}
inline std::uint32_t keyIndex(std::uint64_t k) {
    return std::uint32_t(k);
}

// The visitor of kdtree::search for a k-nearest query: fills keys (capacity entries) until
// full, then makes them a heap and from there on replaces its top, shrinking the search radius
// to the k-th distance.
struct KnnCollector {
    std::uint64_t* keys;
    int capacity;
    int count;
    float& radius2;

    void operator()(std::size_t node, float d2) {
        std::uint64_t k = key(d2, std::uint32_t(node));
        if (count < capacity) {
            keys[count] = k;
            if (++count == capacity) {
                std::make_heap(keys, keys + count);
                radius2 = keyDist2(keys[0]);
            }
        } else if (k < keys[0]) {
            siftDownTop(k);
            radius2 = keyDist2(keys[0]);
        }
    }

    // Replaces the top by k and restores the heap.
    void siftDownTop(std::uint64_t k) {
        int i = 0;
        for (;;) {
            int c = 2 * i + 1;
            if (c >= count) break;
            if (c + 1 < count && keys[c] < keys[c + 1]) ++c;
            if (keys[c] <= k) break;
            keys[i] = keys[c];
            i = c;
        }
        keys[i] = k;
    }
};

} // namespace rayproc::photon_heap
