// kernels/sobol.h: the Owen-scrambled Sobol points of the camera and of path mode's vertices.
// Checked against their definitions: the bit tricks against plain loops, the (0,2)-net property
// at every power-of-two prefix and for later aligned blocks (the points a pixel's passes add),
// 1D stratification, and that different keys give sequences that are not the same.
#include "kernels/sobol.h"

#include <catch2/catch.hpp>

#include <set>
#include <vector>

using namespace rayproc;
using namespace rayproc::kernels;

namespace {

std::uint32_t naiveReverse(std::uint32_t v) {
    std::uint32_t r = 0;
    for (int k = 0; k < 32; ++k)
        if (v & (1u << k)) r |= 1u << (31 - k);
    return r;
}

std::uint32_t naiveSobolSecond(std::uint32_t i) {
    std::uint32_t y = 0;
    for (std::uint32_t v = 0x80000000u; i != 0; i >>= 1, v ^= v >> 1)
        if (i & 1u) y ^= v;
    return y;
}

// Whether points [first, first + 2^m) form a (0, m, 2)-net: for every split a + b = m, each
// of the 2^a x 2^b elementary boxes holds exactly one point.
bool isNet(std::uint32_t first, int m, std::uint64_t key) {
    std::uint32_t n = 1u << m;
    std::vector<Vec2> pts;
    for (std::uint32_t i = first; i < first + n; ++i) pts.push_back(owenSobol2D(i, key));
    for (int a = 0; a <= m; ++a) {
        std::vector<int> count(n, 0);
        for (const Vec2& p : pts) {
            REQUIRE(p.x >= 0.0f);
            REQUIRE(p.x < 1.0f);
            REQUIRE(p.y >= 0.0f);
            REQUIRE(p.y < 1.0f);
            std::uint32_t bx = std::uint32_t(p.x * float(1u << a));
            std::uint32_t by = std::uint32_t(p.y * float(1u << (m - a)));
            ++count[(by << a) | bx];
        }
        for (int c : count)
            if (c != 1) return false;
    }
    return true;
}

} // namespace

TEST_CASE("Sobol: bit reversal and the second dimension match their plain definitions",
          "[kernels][sobol]") {
    std::uint64_t state = 12345;
    for (int k = 0; k < 10000; ++k) {
        state = mix64(state);
        std::uint32_t v = std::uint32_t(state);
        REQUIRE(reverseBits(v) == naiveReverse(v));
        std::uint32_t w = std::uint32_t(state >> 32);
        std::uint64_t both = reverseBits64(std::uint64_t(w) << 32 | v);
        REQUIRE(std::uint32_t(both) == naiveReverse(w));
        REQUIRE(std::uint32_t(both >> 32) == naiveReverse(v));
        REQUIRE(sobolSecond(v) == naiveSobolSecond(v));
    }
    CHECK(sobolSecond(1) == 0x80000000u);
    CHECK(sobolSecond(2) == 0xc0000000u);
    CHECK(sobolSecond(3) == 0x40000000u);
}

TEST_CASE("Sobol: the scramble is a bijection that keeps the leading digits' blocks",
          "[kernels][sobol]") {
    // All 2^16 values with the same low 16 bits map to distinct values, and values sharing
    // their top k bits still share them after the scramble (a nested permutation).
    std::set<std::uint32_t> seen;
    for (std::uint32_t hi = 0; hi < 65536; ++hi) seen.insert(owenScramble(hi << 16 | 0x1234u, 77));
    CHECK(seen.size() == 65536);
    for (std::uint32_t v = 0; v < 4096; ++v) {
        std::uint32_t a = owenScramble(v << 20, 99), b = owenScramble((v << 20) | 0xabcdeu, 99);
        REQUIRE((a >> 20) == (b >> 20));
    }
}

TEST_CASE("Sobol: every power-of-two prefix and aligned block of a pixel's samples is a (0,2)-net",
          "[kernels][sobol]") {
    for (std::uint64_t key : {std::uint64_t(1), std::uint64_t(42), std::uint64_t(0xdeadbeef), mix64(7)}) {
        for (int m = 0; m <= 10; ++m) {
            INFO("key " << key << ", 2^" << m << " samples");
            CHECK(isNet(0, m, key));
        }
        // Passes add samples in order: samples 256-511 and 1024-1279 are nets of their own.
        CHECK(isNet(256, 8, key));
        CHECK(isNet(1024, 8, key));
        // Not an aligned block: the samples 100-163 need not be a net, but they are all
        // distinct points.
        std::set<std::pair<float, float>> distinct;
        for (std::uint32_t i = 100; i < 164; ++i) {
            Vec2 p = owenSobol2D(i, key);
            distinct.insert({p.x, p.y});
        }
        CHECK(distinct.size() == 64);
    }
}

TEST_CASE("Sobol: each coordinate alone is stratified, and different keys give different sequences",
          "[kernels][sobol]") {
    for (int m = 0; m <= 12; ++m) {
        std::uint32_t n = 1u << m;
        std::vector<int> strata(n, 0);
        for (std::uint32_t i = 0; i < n; ++i) ++strata[std::uint32_t(owenSobol2D(i, 5).x * float(n))];
        for (int c : strata) REQUIRE(c == 1);
    }
    // Two pairs of one pixel (keys differ) are independent scrambles: their x's are not the
    // same sequence, and the mean of their product over 4096 samples is about 1/4 (it would
    // be 1/3 if they were the same).
    double product = 0;
    int same = 0;
    const int n = 4096;
    for (std::uint32_t i = 0; i < std::uint32_t(n); ++i) {
        Vec2 a = owenSobol2D(i, 1000), b = owenSobol2D(i, 1001);
        product += double(a.x) * b.x;
        same += a.x == b.x;
    }
    CHECK(same < 5);
    CHECK(product / n == Approx(0.25).margin(0.02));
}

TEST_CASE("Sobol: three pairs at once are the pairs one at a time, to the bit",
          "[kernels][sobol]") {
    std::uint64_t state = 777;
    for (int n = 0; n < 20000; ++n) {
        state = mix64(state);
        std::uint32_t reversed = std::uint32_t(state);
        const std::uint64_t keys[3] = {mix64(state + 1), mix64(state + 2), mix64(state + 3)};
        Vec2 three[3];
        owenSobol2DReversed3(reversed, keys, three);
        for (int k = 0; k < 3; ++k) {
            Vec2 one = owenSobol2DReversed(reversed, keys[k]);
            REQUIRE(three[k].x == one.x);
            REQUIRE(three[k].y == one.y);
        }
    }
}
