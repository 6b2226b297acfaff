// A piecewise-constant density on [0,1]^2 over a grid of cells (an image's pixels): sampling
// picks a row by its marginal weight, then a cell within the row by its weight, then a uniform
// point inside the cell (inversion of the two cumulative sums). pdf(p) = f(cell) / mean(f).
// Each cumulative sum has a guide table (Chen & Asau's index table): entry j is the first cell
// whose sum reaches j / n of the total, so inverting u starts between two neighbouring entries
// instead of bisecting the whole row; the cell found is the one bisection finds.
#pragma once

#include "core/math.h"
#include "core/uninitialized.h"

#include <cstdint>
#include <vector>

namespace rayproc {

class Distribution2D {
public:
    Distribution2D() = default;
    // `weights` row-major, width * height, non-negative (negatives and NaN count as 0).
    Distribution2D(std::vector<float> weights, int width, int height);

    bool valid() const { return m_total > 0; }
    // A point of [0,1)^2, its density with respect to area in [0,1]^2, and its cell.
    Vec2 sample(Vec2 u, float& pdf, int& cellX, int& cellY) const;
    float pdf(Vec2 p) const;
    float pdfCell(int x, int y) const;

private:
    int m_width = 0, m_height = 0;
    std::vector<float> m_weights;  // cell weights
    // Per row: cumulative weights within it (width entries); the rows' loop writes every entry
    // (of this and the row guides), so neither is zero-filled first.
    UnwrittenVector<double> m_rowCdf;
    std::vector<double> m_margCdf; // cumulative row totals (height entries)
    // Guide tables: per row (width + 1 entries each), then the marginal's (height + 1).
    UnwrittenVector<std::uint32_t> m_rowGuide;
    std::vector<std::uint32_t> m_margGuide;
    double m_total = 0;
};

} // namespace rayproc
