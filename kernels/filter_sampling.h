// Pixel reconstruction filters and filter importance sampling (pbrt-v4's definitions; the
// sampling follows its FilterSampler idea). Each camera sample's offset from the pixel centre
// is drawn with density proportional to |f| and carries the weight f / pdf, normalised here so
// that a filter without negative lobes gives exactly 1: the film's per-pixel average is then the
// filter-weighted average sum w L / sum w with no per-sample weights to store.
//
//   box       f = 1 on [-rx, rx] x [-ry, ry]                     (sampled analytically)
//   triangle  f = max(0, rx - |x|) max(0, ry - |y|)               (analytically, per axis)
//   gaussian  f = (g(x) - g(rx))+ (g(y) - g(ry))+, g the normal density of deviation sigma:
//             subtracting the value at the radius makes f reach 0 there
//   mitchell  f = m(2x / rx) m(2y / ry), m Mitchell-Netravali's cubic with B, C on |t| <= 2
//   lanczos   f = s(x) s(x / tau) s(y) s(y / tau) for |x| <= rx, |y| <= ry, s(t) = sin(pi t)/(pi t)
//
// Others are sampled from a table of f at the centres of 32 cells per unit radius: the density is
// piecewise constant, |f_cell| / sum |f_cell| dA, and the weight f_cell / pdf, divided by
// sum |f_cell| dA, is the sign of f_cell (+-1).
#pragma once

#include "core/math.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace rayproc::kernels {

enum class FilterType { Box, Triangle, Gaussian, Mitchell, Lanczos };

struct FilterShape {
    FilterType type = FilterType::Box;
    float rx = 0.5f, ry = 0.5f;
    float sigma = 0.5f;                     // gaussian
    float b = 1.0f / 3.0f, c = 1.0f / 3.0f; // mitchell
    float tau = 3.0f;                       // lanczos
};

namespace detail {

inline float gaussian1D(float x, float sigma) {
    return std::exp(-x * x / (2 * sigma * sigma)) / std::sqrt(2 * kPi * sigma * sigma);
}

inline float mitchell1D(float t, float b, float c) {
    t = std::abs(t);
    if (t <= 1)
        return ((12 - 9 * b - 6 * c) * t * t * t + (-18 + 12 * b + 6 * c) * t * t + (6 - 2 * b)) /
               6;
    if (t <= 2)
        return ((-b - 6 * c) * t * t * t + (6 * b + 30 * c) * t * t + (-12 * b - 48 * c) * t +
                (8 * b + 24 * c)) /
               6;
    return 0;
}

// The cubic divided by size >= 1. It is affine in (B, C), m = m(0, 0) + B m_B + C m_C, so
// m / size = m(B / size, C / size) - (1 - 1 / size) m(0, 0): finite for any finite B and C.
inline float mitchell1DScaled(float t, float b, float c, float size) {
    return mitchell1D(t, b / size, c / size) - (1 - 1 / size) * mitchell1D(t, 0, 0);
}

inline float sinc(float x) {
    if (std::abs(x) < 1e-5f) return 1 - kPi * kPi * x * x / 6; // Taylor: avoids 0 / 0
    return std::sin(kPi * x) / (kPi * x);
}

inline float windowedSinc(float x, float radius, float tau) {
    if (std::abs(x) > radius) return 0;
    return sinc(x) * sinc(x / tau);
}

// Inverse CDF of the tent max(0, r - |x|) on [-r, r].
inline float sampleTent(float u, float r) {
    if (u < 0.5f) return -r + r * std::sqrt(2 * u);
    return r - r * std::sqrt(2 * (1 - u));
}

} // namespace detail

// f(x, y) for an offset from the pixel centre, in pixels.
inline float evalFilter(const FilterShape& s, Vec2 p) {
    if (std::abs(p.x) > s.rx || std::abs(p.y) > s.ry) return 0;
    switch (s.type) {
    case FilterType::Box:
        return 1;
    case FilterType::Triangle:
        return (s.rx - std::abs(p.x)) * (s.ry - std::abs(p.y));
    case FilterType::Gaussian:
        return std::max(0.0f,
                        detail::gaussian1D(p.x, s.sigma) - detail::gaussian1D(s.rx, s.sigma)) *
               std::max(0.0f, detail::gaussian1D(p.y, s.sigma) - detail::gaussian1D(s.ry, s.sigma));
    case FilterType::Mitchell: {
        // The cubic is linear in (1, B, C): for |B| or |C| > 1 it is evaluated divided by their
        // size, so B = 1e30 keeps its shape instead of overflowing (a product of two 1e20s is
        // already beyond float). Sampling uses only the shape; B, C within [-1, 1] are as given.
        float size = std::max({1.0f, std::abs(s.b), std::abs(s.c)});
        if (size > 1)
            return detail::mitchell1DScaled(2 * p.x / s.rx, s.b, s.c, size) *
                   detail::mitchell1DScaled(2 * p.y / s.ry, s.b, s.c, size);
        return detail::mitchell1D(2 * p.x / s.rx, s.b, s.c) *
               detail::mitchell1D(2 * p.y / s.ry, s.b, s.c);
    }
    case FilterType::Lanczos:
        return detail::windowedSinc(p.x, s.rx, s.tau) * detail::windowedSinc(p.y, s.ry, s.tau);
    }
    return 0;
}

struct FilterSample {
    Vec2 offset;      // from the pixel centre, in pixels
    float weight = 1; // f / pdf over the integral of |f|: +-1
};

class FilterSampler {
public:
    // `positivePart`: sample max(f, 0) instead of |f| (every weight 1), for a film that cannot
    // take signed weights.
    explicit FilterSampler(const FilterShape& shape, bool positivePart = false) : m_shape(shape) {
        if (shape.type == FilterType::Box || shape.type == FilterType::Triangle) return;
        m_nx = std::max(1, int(32 * shape.rx));
        m_ny = std::max(1, int(32 * shape.ry));
        m_f.resize(std::size_t(m_nx) * m_ny);
        m_rowCdf.assign(std::size_t(m_ny) + 1, 0.0);
        m_cdf.assign(std::size_t(m_nx + 1) * m_ny, 0.0);
        for (int j = 0; j < m_ny; ++j) {
            double row = 0;
            for (int i = 0; i < m_nx; ++i) {
                Vec2 p = cellCentre(i, j);
                float f = evalFilter(shape, p);
                if (positivePart) f = std::max(0.0f, f);
                m_f[std::size_t(j) * m_nx + i] = f;
                row += std::abs(f);
                m_cdf[std::size_t(j) * (m_nx + 1) + i + 1] = row;
            }
            m_rowCdf[j + 1] = m_rowCdf[j] + row;
        }
        m_total = m_rowCdf[m_ny];
    }

    const FilterShape& shape() const { return m_shape; }

    // Maps u in [0, 1)^2 to an offset drawn from |f| (the table's |f| for tabulated filters).
    FilterSample sample(Vec2 u) const {
        switch (m_shape.type) {
        case FilterType::Box:
            return {{(2 * u.x - 1) * m_shape.rx, (2 * u.y - 1) * m_shape.ry}, 1.0f};
        case FilterType::Triangle:
            return {{detail::sampleTent(u.x, m_shape.rx), detail::sampleTent(u.y, m_shape.ry)},
                    1.0f};
        default:
            break;
        }
        if (!(m_total > 0)) return {{0, 0}, 0.0f}; // a filter that is zero everywhere
        // Row by the marginal, then column by the row's conditional; the remainder of u within
        // the chosen cell places the point uniformly inside it.
        double ty = double(u.y) * m_total;
        int j = int(std::upper_bound(m_rowCdf.begin() + 1, m_rowCdf.end(), ty) -
                    (m_rowCdf.begin() + 1));
        j = std::min(j, m_ny - 1);
        while (j > 0 && m_rowCdf[j + 1] - m_rowCdf[j] <= 0) --j;
        double rowMass = m_rowCdf[j + 1] - m_rowCdf[j];
        double fy = rowMass > 0 ? (ty - m_rowCdf[j]) / rowMass : 0.5;
        const double* cdf = &m_cdf[std::size_t(j) * (m_nx + 1)];
        double tx = double(u.x) * cdf[m_nx];
        int i = int(std::upper_bound(cdf + 1, cdf + m_nx + 1, tx) - (cdf + 1));
        i = std::min(i, m_nx - 1);
        while (i > 0 && cdf[i + 1] - cdf[i] <= 0) --i;
        double cellMass = cdf[i + 1] - cdf[i];
        double fx = cellMass > 0 ? (tx - cdf[i]) / cellMass : 0.5;
        fx = std::clamp(fx, 0.0, 1.0);
        fy = std::clamp(fy, 0.0, 1.0);
        Vec2 p{float(-m_shape.rx + 2 * m_shape.rx * (i + fx) / m_nx),
               float(-m_shape.ry + 2 * m_shape.ry * (j + fy) / m_ny)};
        float f = m_f[std::size_t(j) * m_nx + i];
        return {p, f > 0 ? 1.0f : (f < 0 ? -1.0f : 0.0f)};
    }

    // The density sample() draws offsets with (over the offset plane, per square pixel).
    double pdf(Vec2 p) const {
        if (std::abs(p.x) > m_shape.rx || std::abs(p.y) > m_shape.ry) return 0;
        switch (m_shape.type) {
        case FilterType::Box:
            return 1.0 / (4.0 * m_shape.rx * m_shape.ry);
        case FilterType::Triangle:
            return double(evalFilter(m_shape, p)) /
                   (double(m_shape.rx) * m_shape.rx * m_shape.ry * m_shape.ry);
        default:
            break;
        }
        if (!(m_total > 0)) return 0;
        int i = std::min(m_nx - 1, int((p.x + m_shape.rx) / (2 * m_shape.rx) * m_nx));
        int j = std::min(m_ny - 1, int((p.y + m_shape.ry) / (2 * m_shape.ry) * m_ny));
        double cellArea = 4.0 * m_shape.rx * m_shape.ry / (double(m_nx) * m_ny);
        return std::abs(m_f[std::size_t(j) * m_nx + i]) / (m_total * cellArea);
    }

    // Expected weight: integral of f over integral of |f| (1 without negative lobes).
    double meanWeight() const {
        if (m_shape.type == FilterType::Box || m_shape.type == FilterType::Triangle) return 1;
        double sum = 0;
        for (float f : m_f) sum += f;
        return m_total > 0 ? sum / m_total : 0;
    }

private:
    Vec2 cellCentre(int i, int j) const {
        return {-m_shape.rx + 2 * m_shape.rx * (float(i) + 0.5f) / float(m_nx),
                -m_shape.ry + 2 * m_shape.ry * (float(j) + 0.5f) / float(m_ny)};
    }

    FilterShape m_shape;
    int m_nx = 0, m_ny = 0;
    std::vector<float> m_f;       // f at the cell centres, row-major (y rows)
    std::vector<double> m_rowCdf; // running sum of the rows' |f|, m_ny + 1 entries
    std::vector<double> m_cdf;    // per row, running sum of |f| over its cells (m_nx + 1 each)
    double m_total = 0;
};

} // namespace rayproc::kernels
