// kernels::stratified2D: the shadow stage's light samples at a point and the photon emitter's
// numbers. `count` samples fill the count strata once each: the cells of a jittered grid when
// count is a square, the rows and columns of a Latin hypercube otherwise.
#include "kernels/sampling.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace rayproc;
using namespace rayproc::kernels;

TEST_CASE("Stratification: count samples fill the count strata, a grid or N rooks",
          "[kernels][sampling]") {
    for (std::uint64_t key : {std::uint64_t(1), std::uint64_t(0x9e3779b97f4a7c15ull)}) {
        for (std::uint32_t count : {1u, 7u, 16u, 64u, 100u, 130u}) {
            INFO("key " << key << ", count " << count);
            std::uint32_t side = std::uint32_t(std::sqrt(double(count)) + 0.5);
            bool grid = side * side == count;
            std::vector<int> cells(count, 0), rows(count, 0), columns(count, 0);
            for (std::uint32_t i = 0; i < count; ++i) {
                Vec2 s = stratified2D(i, count, key);
                REQUIRE(s.x >= 0.0f);
                REQUIRE(s.x < 1.0f);
                REQUIRE(s.y >= 0.0f);
                REQUIRE(s.y < 1.0f);
                if (grid) {
                    ++cells[std::uint32_t(s.y * float(side)) * side + std::uint32_t(s.x * float(side))];
                } else {
                    ++columns[std::uint32_t(s.x * float(count))];
                    ++rows[std::uint32_t(s.y * float(count))];
                }
            }
            for (std::uint32_t k = 0; k < count; ++k) {
                if (grid) REQUIRE(cells[k] == 1);
                else {
                    REQUIRE(columns[k] == 1);
                    REQUIRE(rows[k] == 1);
                }
            }
        }
    }
}
