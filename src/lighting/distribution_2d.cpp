#include "lighting/distribution_2d.h"

#include <algorithm>
#include <cmath>

namespace rayproc {

namespace {

// The index whose cumulative interval holds `target` (first entry >= target with a positive
// width), and the position of target inside it in [0, 1).
int invert(const double* cdf, int n, double target, float& remainder) {
    int i = int(std::lower_bound(cdf, cdf + n, target) - cdf);
    i = std::clamp(i, 0, n - 1);
    while (i < n - 1 && cdf[i] <= (i == 0 ? 0.0 : cdf[i - 1])) ++i; // skip empty cells
    double lo = i == 0 ? 0.0 : cdf[i - 1], width = cdf[i] - lo;
    remainder = width > 0 ? float(std::clamp((target - lo) / width, 0.0, 0.99999994)) : 0.5f;
    return i;
}

} // namespace

Distribution2D::Distribution2D(std::vector<float> weights, int width, int height)
    : m_width(width), m_height(height), m_weights(std::move(weights)) {
    m_rowCdf.resize(m_weights.size());
    m_margCdf.resize(std::size_t(height));
    double total = 0;
    for (int y = 0; y < height; ++y) {
        double row = 0;
        for (int x = 0; x < width; ++x) {
            float& w = m_weights[std::size_t(y) * width + x];
            if (!(w > 0) || !std::isfinite(w)) w = 0;
            row += w;
            m_rowCdf[std::size_t(y) * width + x] = row;
        }
        total += row;
        m_margCdf[std::size_t(y)] = total;
    }
    m_total = total;
}

Vec2 Distribution2D::sample(Vec2 u, float& pdf, int& cellX, int& cellY) const {
    float fy, fx;
    cellY = invert(m_margCdf.data(), m_height, double(u.y) * m_total, fy);
    const double* row = &m_rowCdf[std::size_t(cellY) * m_width];
    cellX = invert(row, m_width, double(u.x) * row[m_width - 1], fx);
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
