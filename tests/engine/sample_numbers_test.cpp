// engine/sample_numbers.h: the one sample generator of path vertices, light samples and film
// gathers. A hit's n samples per pixel sample must be an aligned block of one Sobol sequence
// (a net within the hit, and all the pixel's samples together a net at power-of-two counts);
// path mode's numbers must be the points it always drew (images unchanged); depth, pixel and
// tag must select different sequences; without Sobol points the numbers are independent ones
// of the lane's stream.
#include "engine/sample_numbers.h"

#include <catch2/catch.hpp>

#include <memory>
#include <set>
#include <vector>

using namespace rayproc;

namespace {

// Whether the points form a (0, m, 2)-net: for every split a + b = m, each of the 2^a x 2^b
// elementary boxes holds exactly one point.
bool isNet(const std::vector<Vec2>& pts) {
    int m = 0;
    while ((std::size_t(1) << m) < pts.size()) ++m;
    if ((std::size_t(1) << m) != pts.size()) return false;
    for (int a = 0; a <= m; ++a) {
        std::vector<int> count(pts.size(), 0);
        for (const Vec2& p : pts) {
            if (!(p.x >= 0.0f && p.x < 1.0f && p.y >= 0.0f && p.y < 1.0f)) return false;
            std::size_t bx = std::size_t(p.x * float(1u << a));
            std::size_t by = std::size_t(p.y * float(1u << (m - a)));
            ++count[(by << a) | bx];
        }
        for (int c : count)
            if (c != 1) return false;
    }
    return true;
}

struct Lane {
    std::unique_ptr<RayBatch> batch = std::make_unique<RayBatch>();
    Lane(std::uint32_t pixel, std::uint8_t depth, std::uint32_t sample) {
        batch->pixel[0] = pixel;
        batch->depth[0] = depth;
        batch->sample[0] = sample;
        batch->rngKey[0] = kernels::pathKey(5, pixel, sample);
    }
};

} // namespace

TEST_CASE("SampleNumbers: a hit's n samples are an aligned block, the pixel's samples one net",
          "[engine][sobol]") {
    const std::uint64_t seedKey = sampleSeedKey(3);
    for (std::uint32_t n : {1u, 2u, 4u, 8u}) {
        std::vector<Vec2> all;
        for (std::uint32_t sample = 0; sample < 256 / n; ++sample) {
            Lane lane(77, 1, sample);
            SampleNumbers numbers(*lane.batch, 0, true, seedKey, 5);
            std::vector<Vec2> block;
            for (std::uint32_t s = 0; s < n; ++s) block.push_back(numbers.get2D(106, s, n));
            INFO("n " << n << ", sample " << sample);
            REQUIRE(isNet(block));
            all.insert(all.end(), block.begin(), block.end());
            // Every power-of-two prefix of the pixel's samples.
            std::size_t count = all.size();
            if ((count & (count - 1)) == 0) REQUIRE(isNet(all));
        }
        CHECK(all.size() == 256);
    }
}

TEST_CASE("SampleNumbers: path mode's points are its Sobol sequence per (pixel, depth, pair)",
          "[engine][sobol]") {
    // The definition path mode's images were made with (stop 33): pair `dim` of sample i at
    // (pixel, depth) is point i of the sequence keyed mix64(seedKey ^ (pixel << 8 | depth) *
    // golden) ^ dim * golden.
    const std::uint64_t golden = 0x9e3779b97f4a7c15ULL;
    const std::uint64_t seedKey = sampleSeedKey(11);
    for (std::uint32_t sample : {0u, 1u, 5u, 300u}) {
        Lane lane(1234, 3, sample);
        SampleNumbers numbers(*lane.batch, 0, true, seedKey);
        std::uint64_t key = kernels::mix64(seedKey ^ ((std::uint64_t(1234) << 8 | 3) * golden));
        for (std::uint32_t dim : {19u, 21u, 23u}) {
            Vec2 expected = kernels::owenSobol2D(sample, key ^ (dim * golden));
            Vec2 got = numbers.get2D(dim);
            CHECK(got.x == expected.x);
            CHECK(got.y == expected.y);
        }
        // One sample per pixel sample is the same point as the pair's own.
        Vec2 one = numbers.get2D(21, 0, 1), own = numbers.get2D(21);
        CHECK(one.x == own.x);
        CHECK(one.y == own.y);
    }
}

TEST_CASE("SampleNumbers: pixel, depth, tag and pair select different sequences, and without Sobol "
          "points the lane's own stream", "[engine][sobol]") {
    const std::uint64_t seedKey = sampleSeedKey(1);
    auto first = [&](std::uint32_t pixel, std::uint8_t depth, std::uint32_t tag, std::uint32_t dim,
                     bool sobol) {
        Lane lane(pixel, depth, 9);
        return SampleNumbers(*lane.batch, 0, sobol, seedKey, tag).get2D(dim, 1, 4);
    };
    std::set<std::pair<float, float>> seen;
    Vec2 variants[] = {first(10, 0, 0, 100, true), first(11, 0, 0, 100, true),
                       first(10, 1, 0, 100, true), first(10, 0, 1, 100, true),
                       first(10, 0, 0, 102, true), first(10, 0, 0, 100, false)};
    for (const Vec2& v : variants) seen.insert({v.x, v.y});
    CHECK(seen.size() == 6);
    // Independent numbers: samples of one hit differ and lie in [0, 1).
    Lane lane(10, 0, 9);
    SampleNumbers plain(*lane.batch, 0, false, seedKey);
    std::set<float> xs;
    for (std::uint32_t s = 0; s < 64; ++s) {
        Vec2 u = plain.get2D(100, s, 64);
        REQUIRE(u.x >= 0.0f);
        REQUIRE(u.x < 1.0f);
        REQUIRE(u.y >= 0.0f);
        REQUIRE(u.y < 1.0f);
        xs.insert(u.x);
    }
    CHECK(xs.size() == 64);
}
