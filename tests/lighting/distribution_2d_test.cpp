// src/lighting/distribution_2d.h: sampling through the guide tables finds exactly the cell that
// inverting the cumulative sums by bisection finds, on grids with empty rows, empty runs and a
// spike holding nearly all the weight; and the cells come with their weight's frequency.
#include "lighting/distribution_2d.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using namespace rayproc;

namespace {

// The definition, by bisection over whole sums: the first row whose cumulative total reaches
// u.y x total and has a positive weight, then the same within that row.
struct Bisection {
    int width, height;
    std::vector<double> rowCdf, margCdf;
    Bisection(const std::vector<float>& w, int width_, int height_)
        : width(width_), height(height_), rowCdf(w.size()), margCdf(std::size_t(height_)) {
        double total = 0;
        for (int y = 0; y < height; ++y) {
            double row = 0;
            for (int x = 0; x < width; ++x) {
                float v = w[std::size_t(y) * width + x];
                row += v > 0 && std::isfinite(v) ? v : 0.0f;
                rowCdf[std::size_t(y) * width + x] = row;
            }
            total += row;
            margCdf[std::size_t(y)] = total;
        }
    }
    static int invert(const double* cdf, int n, double target) {
        int i = std::clamp(int(std::lower_bound(cdf, cdf + n, target) - cdf), 0, n - 1);
        while (i < n - 1 && cdf[i] <= (i == 0 ? 0.0 : cdf[i - 1])) ++i;
        return i;
    }
    void cell(Vec2 u, int& x, int& y) const {
        y = invert(margCdf.data(), height, double(u.y) * margCdf.back());
        const double* row = &rowCdf[std::size_t(y) * width];
        x = invert(row, width, double(u.x) * row[width - 1]);
    }
};

std::vector<float> randomGrid(int w, int h, std::mt19937& rng) {
    std::uniform_real_distribution<float> uni(0.0f, 1.0f);
    std::vector<float> g(std::size_t(w) * std::size_t(h));
    for (int y = 0; y < h; ++y) {
        bool emptyRow = h > 1 && uni(rng) < 0.2f;
        for (int x = 0; x < w; ++x) {
            float v = uni(rng);
            if (emptyRow || (x / 5) % 3 == 1) v = 0; // empty rows and runs of five empty cells
            if (uni(rng) < 0.002f) v *= 1e6f;        // spikes: a sun
            g[std::size_t(y) * w + x] = v;
        }
    }
    if (std::all_of(g.begin(), g.end(), [](float v) { return v == 0; })) g[0] = 1;
    return g;
}

} // namespace

TEST_CASE("Distribution2D's guide tables find the cell bisection finds",
          "[lighting][distribution]") {
    std::mt19937 rng(2026);
    std::uniform_real_distribution<float> uni(0.0f, 1.0f);
    const int sizes[][2] = {{1, 1}, {1, 9}, {9, 1}, {33, 17}, {512, 256}, {7, 300}};
    for (const auto& size : sizes) {
        const int w = size[0], h = size[1];
        std::vector<float> grid = randomGrid(w, h, rng);
        Bisection reference(grid, w, h);
        Distribution2D dist(grid, w, h);
        REQUIRE(dist.valid());
        std::vector<Vec2> us = {{0, 0}, {0.5f, 0.5f}, {0.99999994f, 0.99999994f}, {0, 0.99999994f}};
        for (int i = 0; i < 20000; ++i) us.push_back({uni(rng), uni(rng)});
        // Targets exactly on cumulative boundaries, where rounding decides.
        for (int y = 0; y < h; y += std::max(1, h / 16))
            us.push_back(
                {0.5f, float(reference.margCdf[std::size_t(y)] / reference.margCdf.back())});
        int mismatches = 0;
        for (const Vec2& u : us) {
            int x, y, rx, ry;
            float pdf;
            Vec2 p = dist.sample(u, pdf, x, y);
            reference.cell(u, rx, ry);
            if (x != rx || y != ry) {
                if (mismatches++ == 0)
                    FAIL_CHECK(w << "x" << h << " u (" << u.x << ", " << u.y << "): cell (" << x
                                 << ", " << y << ") where bisection finds (" << rx << ", " << ry
                                 << ")");
            }
            CHECK(grid[std::size_t(y) * w + x] > 0);
            CHECK(pdf > 0);
            CHECK((p.x >= float(x) / float(w) && p.x <= float(x + 1) / float(w)));
        }
        CHECK(mismatches == 0);
    }
}

TEST_CASE("Distribution2D samples cells with their weight's frequency",
          "[lighting][distribution]") {
    const int w = 6, h = 4;
    std::vector<float> grid = {1, 0, 2, 0, 0, 3, //
                               0, 0, 0, 0, 0, 0, //
                               5, 1, 0, 0, 4, 0, //
                               0, 0, 0, 0, 0, 8};
    Distribution2D dist(grid, w, h);
    const double total = 24;
    const int n = 240000;
    std::vector<int> counts(grid.size(), 0);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> uni(0.0f, 1.0f);
    for (int i = 0; i < n; ++i) {
        float pdf;
        int x, y;
        dist.sample({uni(rng), uni(rng)}, pdf, x, y);
        ++counts[std::size_t(y) * w + x];
        REQUIRE(pdf == Approx(grid[std::size_t(y) * w + x] / total * w * h));
    }
    for (std::size_t c = 0; c < grid.size(); ++c) {
        double expected = n * grid[c] / total;
        INFO("cell " << c << ": " << counts[c] << " samples, expected " << expected);
        CHECK(std::abs(counts[c] - expected) <= 5 * std::sqrt(expected) + (grid[c] == 0 ? 0 : 1));
    }
}
