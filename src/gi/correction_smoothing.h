// Smoothing the cache records' corrections over their neighbours (gi/cache_refinement.h).
//
// A record's correction (the path-traced light beyond its gather rays' far ends minus the
// global map's estimate there) is an unbiased but noisy estimate of the map's error at that
// record, and the map's error varies slowly over a surface: the classroom's map is 5-20% dark
// over whole walls. Averaging each record's mean correction with its nearest records' (same
// facing) trades the noise of one record's few paths for the variation of the error across
// the neighbourhood. How many neighbours is chosen before every pass by Stein's unbiased risk
// estimate (SURE) of the smoothed corrections against the true ones: for the linear smoother
// S_s that averages each record with its s - 1 nearest,
//   R(s) = sum_i ((S_s c)_i - c_i)^2 - v_i + 2 v_i / s_i,
// c_i the record's mean correction (luminance), v_i that mean's variance, s_i the records
// averaged for i (s, or fewer where it has fewer neighbours). E[R(s)] is the
// summed squared error of S_s c. s = 1 (no smoothing) scores sum v_i. As the passes add paths
// the v_i fall and smaller neighbourhoods win wherever the error varies, so the smoothing
// fades and the records converge to their own corrections: consistent, like the rest of gi.
//
// Consumes: the records' positions and normals (fixed after the prepass), per-record means and
// variances. Produces: the neighbourhood size, and the smoothed values. Deterministic: the
// neighbour lists are a function of the records (ties broken by index), the sums run in record
// and list order.
#pragma once

#include "gi/irradiance_cache.h"

#include <cstdint>
#include <vector>

namespace rayproc {

// The neighbourhood sizes tried: 1 (none), 2, 4, ..., kMaxSmoothing records.
constexpr int kMaxSmoothing = 64;

class RecordNeighbours {
public:
    RecordNeighbours() = default;
    // Each record's kMaxSmoothing nearest records (itself first) among those whose normal is
    // within acos(kNormalCos) of its own; fewer where there are not as many.
    explicit RecordNeighbours(const std::vector<IrradianceRecord>& records);
    static constexpr float kNormalCos = 0.9f;

    std::size_t size() const { return m_counts.size(); }
    // Record i's list, nearest first (entry 0 is i), and its length.
    const std::uint32_t* list(std::size_t i) const { return &m_lists[i * kMaxSmoothing]; }
    int count(std::size_t i) const { return m_counts[i]; }

    // The neighbourhood size (1, 2, 4, ... kMaxSmoothing) of least estimated risk for means c
    // with variances v (one per record), and in `smoothed` c averaged at that size; `risks`,
    // when given, receives R(s) for each size tried.
    int chooseSize(const std::vector<double>& c, const std::vector<double>& v,
                   std::vector<double>& smoothed, std::vector<double>* risks = nullptr) const;
    // out_i = the mean of values over record i's first min(s, count(i)) neighbours, with
    // `channels` values per record (1: luminance, 3: RGB).
    void smooth(const std::vector<double>& values, int channels, int s,
                std::vector<double>& out) const;
    // The variance of that mean for independent values of variances v.
    void smoothVariance(const std::vector<double>& v, int s, std::vector<double>& out) const;

private:
    std::vector<std::uint32_t> m_lists; // kMaxSmoothing entries per record
    std::vector<int> m_counts;
};

} // namespace rayproc
