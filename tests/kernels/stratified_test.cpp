// kernels::groupStratified2D: the camera's sub-pixel positions and path mode's first-hit
// samples. Every prefix of complete groups must be stratified (one sample per 8 x 8 cell in
// each group of 64), a count up to 64 must give exactly stratified2D's samples (the images of
// renders up to 64 spp did not change), and stratified2D over a large count must not be.
#include "kernels/sampling.h"

#include <catch2/catch.hpp>

#include <array>

using namespace rayproc;
using namespace rayproc::kernels;

namespace {

// How many of the 64 cells of an 8 x 8 grid samples [first, first + 64) of `count` fill.
int cellsFilled(std::uint32_t first, std::uint32_t count, std::uint64_t key, bool grouped) {
    std::array<int, 64> cells{};
    for (std::uint32_t i = first; i < first + 64; ++i) {
        Vec2 s = grouped ? groupStratified2D(i, count, key) : stratified2D(i, count, key);
        REQUIRE(s.x >= 0.0f);
        REQUIRE(s.x < 1.0f);
        REQUIRE(s.y >= 0.0f);
        REQUIRE(s.y < 1.0f);
        cells[std::size_t(int(s.y * 8) * 8 + int(s.x * 8))] = 1;
    }
    int filled = 0;
    for (int c : cells) filled += c;
    return filled;
}

} // namespace

TEST_CASE("Group stratification: every group of 64 samples fills the 8 x 8 cells, whatever the "
          "count",
          "[kernels][sampling]") {
    for (std::uint64_t key : {1ull, 0x9e3779b97f4a7c15ull, 12345ull}) {
        for (std::uint32_t count : {64u, 1000u, 100000u}) {
            for (std::uint32_t first : {0u, 64u, 640u}) {
                if (first + 64 > count) continue;
                INFO("key " << key << ", count " << count << ", samples " << first << "+64");
                CHECK(cellsFilled(first, count, key, true) == 64);
            }
        }
        // The old way over 100,000 samples: the first 64 are a random subset of the strata
        // (about 64 (1 - 1/e) = 40 cells expected).
        CHECK(cellsFilled(0, 100000, key, false) < 56);
    }
}

TEST_CASE("Group stratification: up to 64 samples it is stratified2D, sample for sample",
          "[kernels][sampling]") {
    for (std::uint32_t count : {1u, 7u, 16u, 64u})
        for (std::uint32_t i = 0; i < count; ++i) {
            Vec2 a = groupStratified2D(i, count, 77), b = stratified2D(i, count, 77);
            CHECK(a.x == b.x);
            CHECK(a.y == b.y);
        }
    // The last group of a count that is not a multiple of 64 is stratified over what is left.
    std::array<int, 4> quarters{};
    for (std::uint32_t i = 128; i < 132; ++i) {
        Vec2 s = groupStratified2D(i, 132, 5);
        quarters[std::size_t(int(s.y * 2) * 2 + int(s.x * 2))] += 1;
    }
    CHECK(quarters == std::array<int, 4>{1, 1, 1, 1});
}
