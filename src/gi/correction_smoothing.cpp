#include "gi/correction_smoothing.h"

#include "core/ordered_parallel.h"
#include "gi/photon_heap.h"
#include "gi/photon_kdtree.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>

namespace rayproc {

namespace {

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
    std::vector<kdtree::BuildKey> keys(n);
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
    out.assign(n * ch, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        const int m = std::min(s, m_counts[i]);
        const std::uint32_t* l = list(i);
        for (std::size_t c = 0; c < ch; ++c) {
            double sum = 0.0;
            for (int k = 0; k < m; ++k) sum += values[std::size_t(l[k]) * ch + c];
            out[i * ch + c] = sum / double(m);
        }
    }
}

void RecordNeighbours::smoothVariance(const std::vector<double>& v, int s,
                                      std::vector<double>& out) const {
    const std::size_t n = size();
    out.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        const int m = std::min(s, m_counts[i]);
        const std::uint32_t* l = list(i);
        double sum = 0.0;
        for (int k = 0; k < m; ++k) sum += v[l[k]];
        out[i] = sum / (double(m) * double(m));
    }
}

int RecordNeighbours::chooseSize(const std::vector<double>& c, const std::vector<double>& v,
                                 std::vector<double>& smoothed, std::vector<double>* risks) const {
    if (risks) risks->clear();
    int best = 1;
    double bestRisk = 0.0;
    std::vector<double> trial;
    for (int s = 1; s <= kMaxSmoothing; s *= 2) {
        smooth(c, 1, s, trial);
        double risk = 0.0;
        for (std::size_t i = 0; i < size(); ++i) {
            const double d = trial[i] - c[i];
            const int m = std::min(s, m_counts[i]);
            risk += d * d - v[i] + 2.0 * v[i] / double(m);
        }
        if (risks) risks->push_back(risk);
        if (s == 1 || risk < bestRisk) {
            best = s;
            bestRisk = risk;
            smoothed.swap(trial);
        }
    }
    return best;
}

} // namespace rayproc
