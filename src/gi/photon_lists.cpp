#include "gi/photon_lists.h"

#include "core/ordered_parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>

namespace rayproc {

namespace {

// Below this many photons a bucket of the key sort is not worth a task of its own.
constexpr std::size_t kPhotonsPerBucket = 4096;
constexpr std::size_t kMaxBuckets = 4096;
// Blocks of the parallel filter.
constexpr std::size_t kFilterBlock = 65536;

} // namespace

KeyedPhotons keyedInOrder(std::vector<std::vector<KeyedPhoton>*> runs) {
    // Each run's key range, on its own thread.
    std::vector<std::pair<std::uint64_t, std::uint64_t>> ranges(
        runs.size(), {std::numeric_limits<std::uint64_t>::max(), 0});
    orderedParallelForEach(0, runs.size(), [&](std::size_t r) {
        for (const KeyedPhoton& k : *runs[r]) {
            ranges[r].first = std::min(ranges[r].first, k.first);
            ranges[r].second = std::max(ranges[r].second, k.first);
        }
    });
    std::size_t total = 0;
    std::uint64_t lo = std::numeric_limits<std::uint64_t>::max(), hi = 0;
    for (std::size_t r = 0; r < runs.size(); ++r) {
        total += runs[r]->size();
        lo = std::min(lo, ranges[r].first);
        hi = std::max(hi, ranges[r].second);
    }
    KeyedPhotons all(total); // every element written by the scatter below
    if (total == 0) return all;
    // Buckets of `width` consecutive keys: bucket b holds keys lo + b width ... + width - 1.
    const std::size_t wanted = std::clamp<std::size_t>(total / kPhotonsPerBucket, 1, kMaxBuckets);
    const std::uint64_t width = (hi - lo) / wanted + 1;
    const std::size_t buckets = std::size_t((hi - lo) / width) + 1;
    auto bucketOf = [&](std::uint64_t key) { return std::size_t((key - lo) / width); };

    // counts[r][b]: run r's photons in bucket b; then where run r starts writing bucket b.
    std::vector<std::vector<std::size_t>> at(runs.size(), std::vector<std::size_t>(buckets, 0));
    orderedParallelForEach(0, runs.size(), [&](std::size_t r) {
        for (const KeyedPhoton& k : *runs[r]) ++at[r][bucketOf(k.first)];
    });
    std::vector<std::size_t> bucketStart(buckets + 1, 0);
    std::size_t offset = 0;
    for (std::size_t b = 0; b < buckets; ++b) {
        bucketStart[b] = offset;
        for (auto& counts : at) {
            const std::size_t n = counts[b];
            counts[b] = offset;
            offset += n;
        }
    }
    bucketStart[buckets] = offset;
    orderedParallelForEach(0, runs.size(), [&](std::size_t r) {
        for (KeyedPhoton& k : *runs[r]) all[at[r][bucketOf(k.first)]++] = std::move(k);
        std::vector<KeyedPhoton>().swap(*runs[r]);
    });
    orderedParallelForEach(0, buckets, [&](std::size_t b) {
        std::sort(all.begin() + std::ptrdiff_t(bucketStart[b]),
                  all.begin() + std::ptrdiff_t(bucketStart[b + 1]),
                  [](const KeyedPhoton& x, const KeyedPhoton& y) { return x.first < y.first; });
    });
    return all;
}

PhotonList joinRounds(std::vector<PhotonList>& rounds, float divisor) {
    if (rounds.size() == 1 && divisor == 1.0f) { // the one round as it is, not a copy
        PhotonList one = std::move(rounds[0]);
        rounds.clear();
        return one;
    }
    std::vector<std::size_t> start(rounds.size() + 1, 0);
    for (std::size_t r = 0; r < rounds.size(); ++r) start[r + 1] = start[r] + rounds[r].size();
    PhotonList all(start.back());
    orderedParallelForEach(0, rounds.size(), [&](std::size_t r) {
        const PhotonList& round = rounds[r];
        orderedParallelFor(0, round.size(), kFilterBlock,
                          [&](const tbb::blocked_range<std::size_t>& range) {
                              for (std::size_t i = range.begin(); i != range.end(); ++i) {
                                  PhotonRecord p = round[i];
                                  if (divisor != 1.0f) p.power = p.power / divisor;
                                  all[start[r] + i] = p;
                              }
                          });
    });
    rounds.clear();
    return all;
}

PhotonList scatteredPhotons(const PhotonList& photons) {
    // Count per block, then each block copies its photons from its prefix.
    const std::size_t blocks = (photons.size() + kFilterBlock - 1) / kFilterBlock;
    std::vector<std::size_t> start(blocks + 1, 0);
    auto blockRange = [&](std::size_t b) {
        return std::make_pair(b * kFilterBlock, std::min(photons.size(), (b + 1) * kFilterBlock));
    };
    orderedParallelForEach(0, blocks, [&](std::size_t b) {
        const auto [first, last] = blockRange(b);
        start[b + 1] = std::size_t(std::count_if(photons.begin() + std::ptrdiff_t(first),
                                                 photons.begin() + std::ptrdiff_t(last),
                                                 [](const PhotonRecord& p) {
                                                     return p.sampledDirect == 0;
                                                 }));
    });
    for (std::size_t b = 0; b < blocks; ++b) start[b + 1] += start[b];
    PhotonList out(start[blocks]);
    orderedParallelForEach(0, blocks, [&](std::size_t b) {
        const auto [first, last] = blockRange(b);
        std::size_t to = start[b];
        for (std::size_t i = first; i < last; ++i)
            if (photons[i].sampledDirect == 0) out[to++] = photons[i];
    });
    return out;
}

} // namespace rayproc
