#include "lighting/distribution_2d.h"

#include "core/named_loop.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace rayproc {

namespace {

// Guide table of a cumulative sum of n entries: n + 1 entries, entry j the first index whose sum
// is >= j / n of the total (n when none is), so a target in [j, j + 1) / n of the total lies in
// the cells guide[j] .. guide[j + 1].
void buildGuide(const double* cdf, int n, std::uint32_t* guide) {
    const double total = cdf[n - 1];
    int i = 0;
    for (int j = 0; j <= n; ++j) {
        double bound = total * (double(j) / double(n));
        while (i < n && cdf[i] < bound) ++i;
        guide[j] = std::uint32_t(i);
    }
}

// The index whose cumulative interval holds `target` (first entry >= target with a positive
// width), and the position of target inside it in [0, 1). The guide narrows the search; when
// rounding put target outside the guided range the search widens to what bisection would see,
// so the index is the same as std::lower_bound over the whole sum.
int invert(const double* cdf, const std::uint32_t* guide, int n, double target,
           float& remainder) {
    const double total = cdf[n - 1];
    int j = total > 0 ? int(std::clamp(target / total * double(n), 0.0, double(n - 1))) : 0;
    int lo = int(guide[j]), hi = std::min(int(guide[j + 1]), n - 1);
    if (lo > 0 && cdf[lo - 1] >= target) lo = 0;
    if (cdf[hi] < target) hi = n - 1;
    int i = int(std::lower_bound(cdf + lo, cdf + hi + 1, target) - cdf);
    i = std::clamp(i, 0, n - 1);
    while (i < n - 1 && cdf[i] <= (i == 0 ? 0.0 : cdf[i - 1])) ++i; // skip empty cells
    double start = i == 0 ? 0.0 : cdf[i - 1], width = cdf[i] - start;
    remainder = width > 0 ? float(std::clamp((target - start) / width, 0.0, 0.99999994)) : 0.5f;
    return i;
}

} // namespace

Distribution2D::Distribution2D(std::vector<float> weights, int width, int height)
    : m_width(width), m_height(height), m_weights(std::move(weights)) {
    m_rowCdf.resize(m_weights.size());
    m_margCdf.resize(std::size_t(height));
    m_rowGuide.resize(std::size_t(width + 1) * std::size_t(height));
    // The rows are independent (an environment map's build is part of scene setup, which runs
    // before the render's workers start); the marginal sums them in order after.
    std::vector<double> rowTotal(static_cast<std::size_t>(height));
    auto rows = [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y < r.end(); ++y) {
            double row = 0;
            for (int x = 0; x < width; ++x) {
                float& w = m_weights[std::size_t(y) * width + x];
                if (!(w > 0) || !std::isfinite(w)) w = 0;
                row += w;
                m_rowCdf[std::size_t(y) * width + x] = row;
            }
            rowTotal[std::size_t(y)] = row;
            buildGuide(&m_rowCdf[std::size_t(y) * width], width,
                       &m_rowGuide[std::size_t(y) * std::size_t(width + 1)]);
        }
    };
    namedLoop("distribution_rows",
              [&] { tbb::parallel_for(tbb::blocked_range<int>(0, height, 16), rows); });
    double total = 0;
    for (int y = 0; y < height; ++y) {
        total += rowTotal[std::size_t(y)];
        m_margCdf[std::size_t(y)] = total;
    }
    m_total = total;
    m_margGuide.resize(std::size_t(height) + 1);
    buildGuide(m_margCdf.data(), height, m_margGuide.data());
}

Vec2 Distribution2D::sample(Vec2 u, float& pdf, int& cellX, int& cellY) const {
    float fy, fx;
    cellY = invert(m_margCdf.data(), m_margGuide.data(), m_height, double(u.y) * m_total, fy);
    const double* row = &m_rowCdf[std::size_t(cellY) * m_width];
    const std::uint32_t* guide = &m_rowGuide[std::size_t(cellY) * std::size_t(m_width + 1)];
    cellX = invert(row, guide, m_width, double(u.x) * row[m_width - 1], fx);
    pdf = pdfCell(cellX, cellY);
    return {(float(cellX) + fx) / float(m_width), (float(cellY) + fy) / float(m_height)};
}

float Distribution2D::pdfCell(int x, int y) const {
    if (!(m_total > 0)) return 0.0f;
    return float(double(m_weights[std::size_t(y) * m_width + x]) * m_width * m_height / m_total);
}

float Distribution2D::pdf(Vec2 p) const {
    int x = std::clamp(int(p.x * float(m_width)), 0, m_width - 1);
    int y = std::clamp(int(p.y * float(m_height)), 0, m_height - 1);
    return pdfCell(x, y);
}

} // namespace rayproc
