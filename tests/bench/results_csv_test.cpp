// results.csv: the writer's header and row-by-row appends, quoting, and the reader's checks.
#include "bench/results_csv.h"
#include "core/error.h"

#include "test_util.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace rayproc;
using namespace rayproc::bench;

TEST_CASE("formatCsvRow and parseResultsCsv round-trip, quoting where needed", "[bench]") {
    BenchRow a{"cornell-box", "gi", "spp=4 gather=64 ic=0.25 photons=200000", 1.25, 123456789,
               0.012345678901234567, 0.5};
    BenchRow b{"odd, \"name\"", "cycles", "samples=16", 0.1, 0, 1e-5, 2e-3};
    std::string text = std::string(kResultsCsvHeader) + "\n" + formatCsvRow(a) + "\n" +
                       formatCsvRow(b) + "\n";
    CHECK(formatCsvRow(b).rfind("\"odd, \"\"name\"\"\",cycles,", 0) == 0);
    std::vector<BenchRow> rows = parseResultsCsv(text, "t.csv");
    REQUIRE(rows.size() == 2);
    CHECK(rows[0].scene == a.scene);
    CHECK(rows[0].settings == a.settings);
    CHECK(rows[0].seconds == a.seconds);
    CHECK(rows[0].rays == a.rays);
    CHECK(rows[0].relmse == a.relmse); // 17 significant digits: exact
    CHECK(rows[1].scene == b.scene);
    CHECK(rows[1].mode == "cycles");
    CHECK(rows[1].rmse == b.rmse);
}

TEST_CASE("parseResultsCsv finds columns by name and rejects malformed files", "[bench]") {
    // Another column order and an extra column (a peer script's CSV).
    std::vector<BenchRow> rows = parseResultsCsv(
        "mode,scene,seconds,settings,rays,rmse,relmse,device\ncycles,cornell-box,2.5,samples=64,"
        "0,0.01,0.002,cpu\n",
        "peer.csv");
    REQUIRE(rows.size() == 1);
    CHECK(rows[0].mode == "cycles");
    CHECK(rows[0].relmse == 0.002);
    CHECK(rows[0].rmse == 0.01);
    CHECK_THROWS_AS(parseResultsCsv("scene,mode,settings,seconds\n", "x.csv"), InputError);
    CHECK_THROWS_WITH(parseResultsCsv(std::string(kResultsCsvHeader) + "\na,b,c,1,2,abc,3\n",
                                      "x.csv"),
                      Catch::Contains("x.csv: line 2") && Catch::Contains("'abc'"));
    CHECK_THROWS_WITH(parseResultsCsv(std::string(kResultsCsvHeader) + "\na,b,c,1,2\n", "x.csv"),
                      Catch::Contains("5 fields"));
    CHECK_THROWS_AS(parseResultsCsv("", "x.csv"), InputError);
}

TEST_CASE("ResultsCsvWriter writes the header once and flushes every row", "[bench]") {
    test::TempDir dir;
    std::string path = dir.file("results.csv");
    BenchRow r{"s", "path", "spp=1", 0.5, 10, 0.1, 0.2};
    {
        ResultsCsvWriter w(path, true);
        w.append(r);
        // Flushed: readable while the writer is still open (an interrupted run keeps it).
        CHECK(readResultsCsv(path).size() == 1);
    }
    {
        ResultsCsvWriter w(path, false); // append
        w.append(r);
    }
    std::string text = test::readText(path);
    CHECK(text.rfind(kResultsCsvHeader, 0) == 0);
    CHECK(text.find(kResultsCsvHeader, 1) == std::string::npos);
    CHECK(readResultsCsv(path).size() == 2);
    {
        // A new run that ends before its first row (a bad option found late, a failed
        // reference) leaves the earlier results as they were.
        ResultsCsvWriter w(path, true);
    }
    CHECK(readResultsCsv(path).size() == 2);
    {
        ResultsCsvWriter w(path, true); // truncate: a new run, at its first row
        w.append(r);
    }
    CHECK(readResultsCsv(path).size() == 1);
    ResultsCsvWriter missing(dir.file("missing/results.csv"), true);
    CHECK_THROWS_AS(missing.append(r), InputError);
}

TEST_CASE("settingValue and settingsWithout read the settings column", "[bench]") {
    CHECK(settingValue("spp=16 gather=64", "spp") == "16");
    CHECK(settingValue("spp=16 gather=64", "gather") == "64");
    CHECK(settingValue("spp=16", "sp") == "");
    CHECK(settingsWithout("spp=4 gather=64 ic=0.25", "spp") == "gather=64 ic=0.25");
    CHECK(settingsWithout("spp=4", "spp") == "");
}
