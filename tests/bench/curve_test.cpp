// The bench's curve readings: lower envelope, time to a target relMSE and relMSE at a time,
// log-log interpolated between measured renders and never extrapolated.
#include "bench/curve.h"
#include "bench/runner.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace rayproc::bench;

TEST_CASE("lowerEnvelope keeps the renders no faster render beats", "[bench]") {
    std::vector<CurvePoint> pts = {{4, 0.02, 0}, {1, 0.1, 1}, {2, 0.2, 2}, {8, 0.005, 3},
                                   {3, 0.05, 4}, {0, 0.01, 5}, {5, -1, 6},
                                   {6, std::numeric_limits<double>::quiet_NaN(), 7}};
    std::vector<CurvePoint> e = lowerEnvelope(pts);
    REQUIRE(e.size() == 4);
    CHECK(e[0].tag == 1); // (1, 0.1)
    CHECK(e[1].tag == 4); // (3, 0.05); (2, 0.2) is dominated
    CHECK(e[2].tag == 0);
    CHECK(e[3].tag == 3);
    for (std::size_t i = 1; i < e.size(); ++i) {
        CHECK(e[i].seconds > e[i - 1].seconds);
        CHECK(e[i].relmse < e[i - 1].relmse);
    }
    // Equal times: only the lower error stays.
    std::vector<CurvePoint> tie = lowerEnvelope({{1, 0.3, 0}, {1, 0.1, 1}});
    REQUIRE(tie.size() == 1);
    CHECK(tie[0].tag == 1);
}

TEST_CASE("timeToReach interpolates log-log between the bracketing renders", "[bench]") {
    // From (1 s, 0.1) to (10 s, 0.001): relMSE ~ t^-2, so 0.01 is reached at sqrt(10) s.
    std::vector<CurvePoint> e = {{1, 0.1}, {10, 0.001}, {100, 0.0005}};
    CurveReading r = timeToReach(e, 0.01);
    CHECK(r.kind == Reading::Interpolated);
    CHECK(r.value == Approx(std::sqrt(10.0)).epsilon(1e-12));
    // Exactly at a measured point.
    r = timeToReach(e, 0.001);
    CHECK(r.kind == Reading::Interpolated);
    CHECK(r.value == Approx(10.0));
    // Between the second and third point: 0.0007 on the t^-0.301 segment.
    r = timeToReach(e, 0.0007);
    double expected = std::exp(std::log(10.0) + (std::log(0.0007) - std::log(0.001)) /
                                                    (std::log(0.0005) - std::log(0.001)) *
                                                    (std::log(100.0) - std::log(10.0)));
    CHECK(r.value == Approx(expected).epsilon(1e-12));
    // Already reached by the first render: an upper bound, flagged.
    r = timeToReach(e, 0.5);
    CHECK(r.kind == Reading::BeforeFirst);
    CHECK(r.value == 1.0);
    // Never reached: the best error, flagged, no extrapolated time.
    r = timeToReach(e, 1e-4);
    CHECK(r.kind == Reading::AfterLast);
    CHECK(r.value == 0.0005);
    CHECK(timeToReach({}, 0.01).kind == Reading::NoData);
}

TEST_CASE("errorAtTime interpolates log-log and says when a time was not measured", "[bench]") {
    std::vector<CurvePoint> e = {{1, 0.1}, {10, 0.001}};
    CurveReading r = errorAtTime(e, std::sqrt(10.0));
    CHECK(r.kind == Reading::Interpolated);
    CHECK(r.value == Approx(0.01).epsilon(1e-12));
    CHECK(errorAtTime(e, 1.0).value == Approx(0.1));
    CHECK(errorAtTime(e, 10.0).kind == Reading::Interpolated);
    CHECK(errorAtTime(e, 10.0).value == Approx(0.001));
    r = errorAtTime(e, 0.5);
    CHECK(r.kind == Reading::BeforeFirst);
    CHECK(r.value == 1.0);
    r = errorAtTime(e, 20);
    CHECK(r.kind == Reading::AfterLast);
    CHECK(r.value == 0.001);
    // One render: readable at its own time only.
    std::vector<CurvePoint> one = {{2, 0.05}};
    CHECK(errorAtTime(one, 2).kind == Reading::Interpolated);
    CHECK(errorAtTime(one, 2).value == 0.05);
    CHECK(errorAtTime(one, 3).kind == Reading::AfterLast);
}

TEST_CASE("predictSeconds fits a fixed cost plus a cost per sample", "[bench]") {
    // 1 spp in 2 s, 2 spp in 3 s: 1 s fixed + 1 s per sample, so 4 spp in 5 s.
    CHECK(predictSeconds(1, 2.0, 2, 3.0, 4) == Approx(5.0));
    // First render: in proportion to the samples.
    CHECK(predictSeconds(0, 0.0, 4, 1.0, 16) == Approx(4.0));
    // Noise that made the larger budget faster predicts no less than the last time.
    CHECK(predictSeconds(1, 3.0, 2, 2.5, 4) == Approx(2.5));
}
