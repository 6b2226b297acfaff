// summary.md: the tables read the envelopes right and say "not reached" instead of
// extrapolating.
#include "bench/mode_curves.h"
#include "bench/summary.h"

#include <catch2/catch.hpp>

using namespace rayproc::bench;

TEST_CASE("renderSummary tabulates time to target and error at equal time", "[bench]") {
    BenchSuite suite = findSuite("quick");
    std::vector<BenchRow> rows = {
        // path: 0.1 at 1 s, 0.001 at 10 s: reaches 0.01 at sqrt(10) = 3.16 s.
        {"s", "path", "spp=1", 1, 1, 0.1, 0},
        {"s", "path", "spp=16", 10, 1, 0.001, 0},
        // raytrace: stuck at 0.02 (biased): never reaches 0.01.
        {"s", "raytrace", "spp=1", 0.5, 1, 0.03, 0},
        {"s", "raytrace", "spp=4", 2, 1, 0.02, 0},
    };
    SummaryContext ctx;
    ctx.suite = &suite;
    ctx.commandLine = "rayproc bench quick";
    std::string md = renderSummary(rows, ctx);
    CHECK(md.find("## s") != std::string::npos);
    CHECK(md.find("![s: relMSE against time](s.svg)") != std::string::npos);
    CHECK(md.find("| path | 3.16 s | 10 s |") != std::string::npos);
    CHECK(md.find("| raytrace | not reached (best 0.02 at 2 s) | not reached (best 0.02 at 2 s) |") !=
          std::string::npos);
    // Equal time: 1 and 2 s are inside both spans (0.5 s and 5 s only inside one).
    std::vector<double> t = equalTimePoints(rows, "s");
    REQUIRE(t.size() == 2);
    CHECK(t[0] == 1.0);
    CHECK(t[1] == 2.0);
    // At 1 s: path 0.1; raytrace between (0.5, 0.03) and (2, 0.02): 0.03 * (2/3)^(1/2).
    CHECK(md.find("| path | 0.1 |") != std::string::npos);
    CHECK(md.find("| raytrace | 0.0245 |") != std::string::npos);
    CHECK(md.find("128x128") == std::string::npos); // the quick suite is 64x64
    CHECK(md.find("64x64") != std::string::npos);
}

TEST_CASE("summary.md's time-to-reach table takes the suite's relMSE targets", "[bench]") {
    std::vector<BenchRow> rows = {{"s", "path", "spp=1", 1, 1, 0.1, 0},
                                  {"s", "path", "spp=16", 10, 1, 0.001, 0}};
    SummaryContext ctx;
    BenchSuite quick = findSuite("quick");
    ctx.suite = &quick;
    std::string md = renderSummary(rows, ctx);
    CHECK(md.find("| mode | relMSE 0.01 | relMSE 0.001 |") != std::string::npos);
    BenchSuite publicSuite = findSuite("public");
    ctx.suite = &publicSuite;
    md = renderSummary(rows, ctx);
    // path: 0.1 at 1 s, 0.001 at 10 s (log-log): 0.05 at 10^(log 2 / 2) = 1.41 s.
    CHECK(md.find("| mode | relMSE 0.05 | relMSE 0.01 |") != std::string::npos);
    CHECK(md.find("| path | 1.41 s | 3.16 s |") != std::string::npos);
}

TEST_CASE("settingsWithoutBudget keeps what stays fixed along a ladder", "[bench]") {
    CHECK(settingsWithoutBudget("spp=4 gather=64 ic=0.25") == "gather=64 ic=0.25");
    CHECK(settingsWithoutBudget("samples=16 device=cpu") == "device=cpu");
    CHECK(settingsWithoutBudget("time=2.5") == "");
    CHECK(settingsWithoutBudget("seconds=1 spp=2") == "");
}
