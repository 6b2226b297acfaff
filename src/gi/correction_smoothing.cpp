#include "gi/correction_smoothing.h"

#include "core/named_loop.h"
#include "core/ordered_parallel.h"
#include "gi/photon_heap.h"
#include "gi/photon_kdtree.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>

namespace rayproc {

namespace {

// Records per task of the loops over records (each record's sums are its own).
constexpr std::size_t kRecordGrain = 256;

// body(i) for every record i, on every thread.
template <typename Body>
void forEachRecord(std::size_t n, const Body& body) {
    namedLoop("correction_smoothing", [&] {
        orderedParallelFor(0, n, kRecordGrain, [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) body(i);
        });
    });
}

struct RecordNode {
    float pos[3];
    std::uint8_t split = 0;
    int axis() const { return split; }
};

} // namespace

RecordNeighbours::RecordNeighbours(const std::vector<IrradianceRecord>& records) {
    const std::size_t n = records.size();
    m_lists.assign(n * kMaxSmoothing, 0);
    m_counts.assign(n, 0);
    if (n == 0) return;
    kdtree::BuildKeys keys(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3& p = records[i].position;
        keys[i] = {{p.x, p.y, p.z}, std::uint32_t(i)};
    }
    std::vector<std::uint8_t> axis;
    kdtree::build(keys, axis);
    std::vector<RecordNode> nodes(n);
    for (std::size_t i = 0; i < n; ++i) {
        for (int a = 0; a < 3; ++a) nodes[i].pos[a] = keys[i].p[a];
        nodes[i].split = axis[i];
    }
    // The k nearest of the same facing, by (squared distance, record index): the photon map's
    // k-nearest collector, handed record indices instead of tree positions. Each record's list
    // is its own: the records are shared among the threads.
    auto findNeighbours = [&](std::size_t i) {
        std::uint64_t nearest[kMaxSmoothing];
        const Vec3& normal = records[i].normal;
        float maxDist2 = std::numeric_limits<float>::infinity();
        photon_heap::KnnCollector collect{nearest, kMaxSmoothing, 0, maxDist2};
        kdtree::search(nodes.data(), n, records[i].position, maxDist2,
                       [&](std::size_t at, float d2) {
                           const std::uint32_t j = keys[at].index;
                           if (dot(records[j].normal, normal) >= kNormalCos) collect(j, d2);
                       });
        std::sort(nearest, nearest + collect.count);
        // The record itself is at distance 0 with its own normal; another record at the same
        // position could tie with it, so it is put first explicitly.
        std::uint32_t* out = &m_lists[i * kMaxSmoothing];
        int count = 0;
        out[count++] = std::uint32_t(i);
        for (int k = 0; k < collect.count; ++k) {
            const std::uint32_t j = photon_heap::keyIndex(nearest[k]);
            if (j != i && count < kMaxSmoothing) out[count++] = j;
        }
        m_counts[i] = count;
    };
    orderedParallelFor(0, n, 64,
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t i = r.begin(); i != r.end(); ++i) findNeighbours(i);
                      });
}

void RecordNeighbours::smooth(const std::vector<double>& values, int channels, int s,
                              std::vector<double>& out) const {
    const std::size_t n = size(), ch = std::size_t(channels);
    out.resize(n * ch);
    forEachRecord(n, [&](std::size_t i) {
        const int m = std::min(s, m_counts[i]);
        const std::uint32_t* l = list(i);
        for (std::size_t c = 0; c < ch; ++c) {
            double sum = 0.0;
            for (int k = 0; k < m; ++k) sum += values[std::size_t(l[k]) * ch + c];
            out[i * ch + c] = sum / double(m);
        }
    });
}

void RecordNeighbours::smoothVariance(const std::vector<double>& v, int s,
                                      std::vector<double>& out) const {
    const std::size_t n = size();
    out.resize(n);
    forEachRecord(n, [&](std::size_t i) {
        const int m = std::min(s, m_counts[i]);
        const std::uint32_t* l = list(i);
        double sum = 0.0;
        for (int k = 0; k < m; ++k) sum += v[l[k]];
        out[i] = sum / (double(m) * double(m));
    });
}

int RecordNeighbours::chooseSize(const std::vector<double>& c, const std::vector<double>& v,
                                 std::vector<double>& smoothed, std::vector<double>* risks) const {
    if (risks) risks->clear();
    // Every size's mean in one walk along each record's list, on every thread: the mean over
    // the first m neighbours is the running sum at m, the sum smooth() makes, in its order.
    // Then each size's risk, its records' terms summed in record order.
    constexpr int kSizes = 7; // 1, 2, 4, ..., kMaxSmoothing
    static_assert(1 << (kSizes - 1) == kMaxSmoothing);
    const std::size_t n = size();
    std::vector<double> trials(kSizes * n), terms(kSizes * n);
    forEachRecord(n, [&](std::size_t i) {
        const std::uint32_t* l = list(i);
        double sum = 0.0;
        int k = 0;
        for (int t = 0; t < kSizes; ++t) {
            const int m = std::min(1 << t, m_counts[i]);
            for (; k < m; ++k) sum += c[l[k]];
            const double mean = sum / double(m), d = mean - c[i];
            trials[std::size_t(t) * n + i] = mean;
            terms[std::size_t(t) * n + i] = d * d - v[i] + 2.0 * v[i] / double(m);
        }
    });
    int best = 0;
    double bestRisk = 0.0;
    for (int t = 0; t < kSizes; ++t) {
        double risk = 0.0;
        for (std::size_t i = 0; i < n; ++i) risk += terms[std::size_t(t) * n + i];
        if (risks) risks->push_back(risk);
        if (t == 0 || risk < bestRisk) {
            best = t;
            bestRisk = risk;
        }
    }
    smoothed.assign(trials.begin() + std::ptrdiff_t(std::size_t(best) * n),
                    trials.begin() + std::ptrdiff_t(std::size_t(best + 1) * n));
    return 1 << best;
}

} // namespace rayproc
