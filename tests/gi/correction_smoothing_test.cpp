// gi/correction_smoothing.h: the records' neighbour lists, and the neighbourhood size Stein's
// unbiased risk estimate chooses for their corrections.
#include "gi/correction_smoothing.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

using namespace rayproc;

namespace {

IrradianceRecord recordAt(const Vec3& p, const Vec3& n) {
    IrradianceRecord r;
    r.position = p;
    r.normal = n;
    return r;
}

// A jittered 12 x 12 grid on the floor (normal +y) and one on a wall (normal +x) meeting it.
std::vector<IrradianceRecord> floorAndWall() {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> jitter(-0.03f, 0.03f);
    std::vector<IrradianceRecord> records;
    for (int a = 0; a < 12; ++a)
        for (int b = 0; b < 12; ++b) {
            records.push_back(recordAt(
                {0.1f * float(a) + jitter(rng), 0.0f, 0.1f * float(b) + jitter(rng)}, {0, 1, 0}));
            records.push_back(recordAt(
                {0.0f, 0.1f * float(a) + jitter(rng), 0.1f * float(b) + jitter(rng)}, {1, 0, 0}));
        }
    return records;
}

// n records on a line, 0.1 apart, all facing up.
std::vector<IrradianceRecord> line(int n) {
    std::vector<IrradianceRecord> records;
    for (int i = 0; i < n; ++i) records.push_back(recordAt({0.1f * float(i), 0, 0}, {0, 1, 0}));
    return records;
}

} // namespace

TEST_CASE("Record neighbours: the nearest records of the same facing, the record first",
          "[gi][smoothing]") {
    const std::vector<IrradianceRecord> records = floorAndWall();
    RecordNeighbours neighbours(records);
    REQUIRE(neighbours.size() == records.size());
    for (std::size_t i = 0; i < records.size(); ++i) {
        // By brute force: same facing, sorted by (squared distance, index).
        std::vector<std::pair<float, std::uint32_t>> all;
        for (std::size_t j = 0; j < records.size(); ++j) {
            if (j == i || dot(records[i].normal, records[j].normal) < RecordNeighbours::kNormalCos)
                continue;
            const Vec3& p = records[j].position;
            const Vec3& q = records[i].position;
            float dx = q.x - p.x, dy = q.y - p.y, dz = q.z - p.z;
            all.push_back({dx * dx + dy * dy + dz * dz, std::uint32_t(j)});
        }
        std::sort(all.begin(), all.end());
        INFO("record " << i);
        REQUIRE(neighbours.count(i) == kMaxSmoothing); // 144 of each facing
        const std::uint32_t* l = neighbours.list(i);
        CHECK(l[0] == i);
        for (int k = 1; k < neighbours.count(i); ++k) CHECK(l[k] == all[std::size_t(k - 1)].second);
    }
    // Fewer records than a neighbourhood: all of them.
    RecordNeighbours few(line(3));
    CHECK(few.count(0) == 3);
    CHECK(few.list(0)[1] == 1);
    CHECK(few.list(0)[2] == 2);
    CHECK(few.list(2)[1] == 1);
}

TEST_CASE("Smoothing averages each record's first s neighbours", "[gi][smoothing]") {
    RecordNeighbours neighbours(line(4)); // 0 - 1 - 2 - 3
    std::vector<double> values = {1, 10, 2, 20, 3, 30, 4, 40}, out;
    neighbours.smooth(values, 2, 1, out);
    CHECK(out == values);
    neighbours.smooth(values, 2, 2, out); // record 0 with 1; 1 with 0 or 2 (tie: lower index)
    CHECK(out[0] == Approx(1.5));
    CHECK(out[1] == Approx(15));
    CHECK(out[2] == Approx(1.5));
    CHECK(out[6] == Approx(3.5));
    neighbours.smooth(values, 2, 64, out); // everything
    for (std::size_t i = 0; i < 4; ++i) CHECK(out[2 * i] == Approx(2.5));
    std::vector<double> v = {1, 1, 1, 4}, var;
    neighbours.smoothVariance(v, 2, var);
    CHECK(var[3] == Approx((4.0 + 1.0) / 4.0));
}

TEST_CASE("Stein's risk estimate: wide neighbourhoods for a smooth field under noise, none for "
          "a varying one, and its risks track the true errors",
          "[gi][smoothing]") {
    // 1024 records on a 32 x 32 grid; means c = beta + noise of variance v.
    std::vector<IrradianceRecord> records;
    for (int a = 0; a < 32; ++a)
        for (int b = 0; b < 32; ++b)
            records.push_back(recordAt({0.1f * float(a), 0, 0.1f * float(b)}, {0, 1, 0}));
    RecordNeighbours neighbours(records);
    const std::size_t n = records.size();
    std::mt19937 rng(11);
    std::normal_distribution<double> gauss(0.0, 1.0);
    auto check = [&](const std::vector<double>& beta, double variance, int expected) {
        std::vector<double> c(n), v(n, variance);
        for (std::size_t i = 0; i < n; ++i) c[i] = beta[i] + std::sqrt(variance) * gauss(rng);
        std::vector<double> risks;
        std::vector<double> chosen;
        int s = neighbours.chooseSize(c, v, chosen, &risks);
        CHECK(s == expected);
        std::vector<double> atSize;
        neighbours.smooth(c, 1, s, atSize);
        CHECK(chosen == atSize);    // the means averaged at the size chosen
        REQUIRE(risks.size() == 7); // 1, 2, 4, ..., 64
        // The estimate's own noise, from R - actual = sum(v(2/s - 1) + ... ): about
        // 2 n v^2 for the noise's squares, plus 4 v sum((S beta - beta)^2) for its cross term
        // with the smoothing's bias.
        for (int k = 0, size = 1; k < 7; ++k, size *= 2) {
            std::vector<double> smoothed, smoothBeta;
            neighbours.smooth(c, 1, size, smoothed);
            neighbours.smooth(beta, 1, size, smoothBeta);
            double actual = 0, bias2 = 0;
            for (std::size_t i = 0; i < n; ++i) {
                actual += (smoothed[i] - beta[i]) * (smoothed[i] - beta[i]);
                bias2 += (smoothBeta[i] - beta[i]) * (smoothBeta[i] - beta[i]);
            }
            const double tolerance =
                5.0 * std::sqrt(2.0 * double(n) * variance * variance + 4.0 * variance * bias2);
            INFO("size " << size << ": estimated " << risks[std::size_t(k)] << ", actual " << actual
                         << ", tolerance " << tolerance);
            CHECK(std::abs(risks[std::size_t(k)] - actual) < tolerance);
        }
    };
    // A constant bias under large noise: the widest neighbourhood.
    check(std::vector<double>(n, 1.0), 1.0, kMaxSmoothing);
    // A field that changes from record to record, measured precisely: no smoothing.
    std::vector<double> rough(n);
    std::uniform_real_distribution<double> uni(-5.0, 5.0);
    for (double& b : rough) b = uni(rng);
    check(rough, 0.01, 1);
    // A slow gradient (one unit over the grid) under moderate noise: something in between.
    std::vector<double> slope(n);
    for (std::size_t i = 0; i < n; ++i) slope[i] = 10.0 * records[i].position.x;
    std::vector<double> c(n), v(n, 0.05), risks;
    for (std::size_t i = 0; i < n; ++i) c[i] = slope[i] + std::sqrt(0.05) * gauss(rng);
    std::vector<double> chosen;
    int s = neighbours.chooseSize(c, v, chosen, &risks);
    INFO("gradient: size " << s);
    CHECK(s > 1);
    CHECK(s < kMaxSmoothing);
}
