// The CI smoke test of `rayproc bench --quick`: runs the quick suite as a child process and
// checks that its outputs exist and hold numbers. Hidden from the default run (about a minute);
// ctest runs it as `bench_quick` (label bench), or: rayproc_tests "[bench-quick]".
#include "bench/results_csv.h"

#include "test_util.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <set>
#include <thread>

using namespace rayproc;

TEST_CASE("rayproc bench --quick writes results, plots and a summary", "[.bench-quick]") {
    test::TempDir dir;
    std::string out = dir.file("bench");
    test::RunResult r = test::runRayproc(
        {"bench", "--quick", "-q", "-o", out, "--scenes-dir",
         (test::sourceDir() / "scenes").string()},
        dir, 280);
    INFO(r.err);
    REQUIRE(r.status == 0);
    INFO("took " << r.seconds << " s");

    std::string csv = out + "/results.csv";
    REQUIRE(std::filesystem::exists(csv));
    CHECK(test::readText(csv).rfind(bench::kResultsCsvHeader, 0) == 0);
    std::vector<bench::BenchRow> rows = bench::readResultsCsv(csv);
    std::set<std::string> modes;
    for (const bench::BenchRow& row : rows) {
        INFO(bench::formatCsvRow(row));
        CHECK(row.scene == "cornell-box");
        CHECK(std::isfinite(row.seconds));
        CHECK(row.seconds > 0);
        CHECK(row.rays > 0);
        CHECK(std::isfinite(row.relmse));
        CHECK(row.relmse > 0);
        CHECK(std::isfinite(row.rmse));
        CHECK(!bench::settingValue(row.settings, "spp").empty());
        modes.insert(row.mode);
    }
    CHECK(modes == std::set<std::string>{"preview", "raytrace", "gi", "path"});

    std::string svg = test::readText(out + "/cornell-box.svg");
    CHECK(svg.size() > 2000);
    CHECK(svg.find("</svg>") != std::string::npos);
    std::size_t markers = 0;
    for (std::size_t p = svg.find("class=\"pt\""); p != std::string::npos;
         p = svg.find("class=\"pt\"", p + 1))
        ++markers;
    CHECK(markers == rows.size());

    std::string md = test::readText(out + "/summary.md");
    CHECK(md.size() > 500);
    CHECK(md.find("## cornell-box") != std::string::npos);
    CHECK(md.find("64x64") != std::string::npos);
    // The reference is cached: a second run (preview only, a second or two) renders it no more:
    // it does not say it renders one, and the cached files are the same, unchanged.
    REQUIRE(!std::filesystem::is_empty(out + "/refs"));
    auto cached = [&] {
        std::vector<std::pair<std::string, std::filesystem::file_time_type>> files;
        for (const auto& e : std::filesystem::directory_iterator(out + "/refs"))
            files.push_back({e.path().filename().string(), e.last_write_time()});
        std::sort(files.begin(), files.end());
        return files;
    };
    auto before = cached();
    test::RunResult again = test::runRayproc(
        {"bench", "--quick", "--modes", "preview", "-o", out, "--scenes-dir",
         (test::sourceDir() / "scenes").string()},
        dir, 280);
    INFO(again.err);
    REQUIRE(again.status == 0);
    CHECK(again.err.find("rendering the reference") == std::string::npos);
    CHECK(cached() == before);
}

TEST_CASE("rayproc bench rejects an unknown suite and an unwritable output", "[cli][bench]") {
    test::TempDir dir;
    test::RunResult r = test::runRayproc({"bench", "nosuch", "-o",
                                          dir.file("out")},
                                         dir, 30);
    CHECK(r.status == 1);
    CHECK(r.err.find("unknown bench suite 'nosuch'; known suites: default, quick, public") !=
          std::string::npos);
    test::writeText(dir.file("file"), "x");
    r = test::runRayproc({"bench", "--quick", "-o", dir.file("file/sub")},
                         dir, 30);
    CHECK(r.status == 1);
    CHECK(r.err.find("cannot create the output directory") != std::string::npos);
    r = test::runRayproc({"bench", "default", "--quick", "-o",
                          dir.file("out")},
                         dir, 30);
    CHECK(r.status == 1);
    CHECK(r.err.find("--quick") != std::string::npos);
    CHECK(!std::filesystem::exists(dir.file("out/results.csv")));
}

TEST_CASE("SIGINT stops rayproc bench, keeping the finished rows and writing the report",
          "[cli][bench]") {
    test::TempDir dir;
    std::string out = dir.file("bench");
    // The default suite on one scene runs for minutes: the signal surely lands mid-run.
    test::Child child({"bench", "default", "-o", out, "--scene", test::scenePath("cornell-box"),
                       "--reference", test::goldenPath("cornell-box-path.exr")},
                      dir.file("stdout.txt"), dir.file("stderr.txt"));
    REQUIRE(child.started());
    std::string csv = out + "/results.csv";
    auto rowsSoFar = [&] {
        if (!std::filesystem::exists(csv)) return std::size_t(0);
        std::string text = test::readText(csv);
        return std::size_t(std::count(text.begin(), text.end(), '\n'));
    };
    auto start = std::chrono::steady_clock::now();
    while (rowsSoFar() < 3 && std::chrono::steady_clock::now() - start < std::chrono::seconds(60))
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    REQUIRE(rowsSoFar() >= 3); // the header and two renders
    child.signal(SIGINT);
    bool finished = child.wait(60.0);
    INFO(child.err());
    REQUIRE(finished);
    CHECK(child.status() == 130);
    CHECK(child.err().find("interrupted") != std::string::npos);
    std::vector<bench::BenchRow> rows = bench::readResultsCsv(csv);
    CHECK(rows.size() >= 2);
    std::string md = test::readText(out + "/summary.md");
    CHECK(md.find("Interrupted") != std::string::npos);
    CHECK(md.find("given: `") != std::string::npos);
    CHECK(std::filesystem::exists(out + "/cornell-box.svg"));
}

TEST_CASE("rayproc bench --progressive renders each mode once and records every pass",
          "[cli][bench]") {
    test::TempDir dir;
    std::string out = dir.file("bench");
    // The golden reference is 128x128: the quick suite's cornell-box renders at its size.
    test::RunResult r = test::runRayproc(
        {"bench", "--quick", "-q", "--progressive", "--modes", "gi,path", "--time-cap", "1.5",
         "-o", out, "--scenes-dir", (test::sourceDir() / "scenes").string(), "--reference",
         "cornell-box=" + test::goldenPath("cornell-box-path.exr")},
        dir, 120);
    INFO(r.err);
    REQUIRE(r.status == 0);
    std::vector<bench::BenchRow> rows = bench::readResultsCsv(out + "/results.csv");
    std::set<std::string> modes;
    for (const std::string mode : {"gi", "path"}) {
        std::vector<bench::BenchRow> own;
        for (const bench::BenchRow& row : rows)
            if (row.mode == mode) own.push_back(row);
        INFO(mode << ": " << own.size() << " passes");
        // Path's passes take milliseconds; gi's first holds its photon pass and cache prepass,
        // which a sanitizer build or a loaded machine can stretch past the limit.
        REQUIRE(own.size() >= (mode == "path" ? 2u : 1u));
        for (std::size_t i = 0; i < own.size(); ++i) {
            INFO(bench::formatCsvRow(own[i]));
            // One row per pass of one render: 1, 2, 3 ... spp, in time order.
            CHECK(bench::settingValue(own[i].settings, "spp") == std::to_string(i + 1));
            CHECK(bench::settingValue(own[i].settings, "time-limit") == "1.5");
            CHECK(own[i].relmse > 0);
            CHECK(own[i].rays > 0);
            if (i > 0) CHECK(own[i].seconds >= own[i - 1].seconds);
        }
        // The render stops after the first pass that ends past the limit (the rows' own
        // times, which the budget decides on).
        CHECK(own.back().seconds >= 1.5);
        if (own.size() >= 2) CHECK(own[own.size() - 2].seconds < 1.5);
        // The error falls with the passes (the first pass against the last): path always has
        // two passes or more (required above); gi's first pass may take the whole budget, so
        // for gi the fall is checked only when it ran two, and the run says whether it did.
        if (own.size() >= 2) CHECK(own.back().relmse < own.front().relmse);
        else WARN("gi ran one pass in the budget: its error fall is not checked");
    }
    for (const bench::BenchRow& row : rows) modes.insert(row.mode);
    CHECK(modes == std::set<std::string>{"gi", "path"});
    // The plot draws each render as a line through its passes, without markers.
    std::string svg = test::readText(out + "/cornell-box.svg");
    CHECK(svg.find("<polyline") != std::string::npos);
    CHECK(svg.find("class=\"pt\"") == std::string::npos);
    std::string md = test::readText(out + "/summary.md");
    CHECK(md.find("--progressive") != std::string::npos);
    CHECK(md.find("128x128") != std::string::npos);
    CHECK(md.find("| path (time-limit=1.5) |") != std::string::npos);
}

TEST_CASE("rayproc bench names what is wrong with --reference, --modes and --progressive",
          "[cli][bench]") {
    test::TempDir dir;
    const std::string scenes = (test::sourceDir() / "scenes").string();
    const std::string golden = test::goldenPath("cornell-box-path.exr");
    struct Case {
        std::vector<std::string> args;
        std::string message;
    };
    const std::vector<Case> cases = {
        {{"--quick", "--reference", "nosuch=" + golden},
         "--reference nosuch=" + golden +
             ": the run has no scene called 'nosuch' (its scenes: cornell-box)"},
        {{"--quick", "--reference", "cornell-box=" + dir.file("missing.exr")},
         dir.file("missing.exr") + ": no such file"},
        {{"--quick", "--reference", "cornell-box=" + golden, "--reference", golden},
         "cornell-box already has a reference"},
        {{"default", "--reference", golden}, "is the reference of one scene, but the run has 2"},
        {{"--quick", "--modes", "gi,bogus"},
         "--modes: 'bogus' is not a mode of suite 'quick' (its modes: preview, raytrace, gi, "
         "path)"},
        {{"--quick", "--ablation", "--progressive"}, "pick one"},
        {{"--quick", "--ablation", "--modes", "gi"}, "--modes selects the curves' modes"},
    };
    for (const Case& c : cases) {
        std::vector<std::string> args = {"bench"};
        args.insert(args.end(), c.args.begin(), c.args.end());
        for (const std::string& a :
             {std::string("-o"), dir.file("out"), std::string("--scenes-dir"), scenes})
            args.push_back(a);
        test::RunResult r = test::runRayproc(args, dir, 30);
        INFO(r.err);
        CHECK(r.status == 1);
        CHECK(r.err.find(c.message) != std::string::npos);
        CHECK(!std::filesystem::exists(dir.file("out/results.csv")));
    }
}

TEST_CASE("rayproc bench --spectral renders every mode spectrally, its references too",
          "[cli][bench][heavy]") {
    test::TempDir dir;
    const std::string scenes = (test::sourceDir() / "scenes").string();
    std::string out = dir.file("bench");
    // The quick suite with a short time cap: each ladder stops after a render or two.
    test::RunResult r = test::runRayproc({"bench", "--quick", "--spectral", "--time-cap", "0.3",
                                          "-o", out, "--scenes-dir", scenes},
                                         dir, 120);
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(r.err.find("(path mode, spectral, 1024 spp") != std::string::npos);
    std::vector<bench::BenchRow> rows = bench::readResultsCsv(out + "/results.csv");
    std::set<std::string> modes;
    for (const bench::BenchRow& row : rows) {
        INFO(bench::formatCsvRow(row));
        CHECK(row.settings.find(" spectral") != std::string::npos);
        CHECK(std::isfinite(row.relmse));
        modes.insert(row.mode);
    }
    CHECK(modes == std::set<std::string>{"preview", "raytrace", "path", "gi"});
    // The reference is a spectral path render, cached under a name of its own (an RGB run's
    // cached reference is never taken for it, nor it for an RGB run's).
    std::vector<std::string> refs;
    for (const auto& e : std::filesystem::directory_iterator(out + "/refs"))
        refs.push_back(e.path().filename().string());
    REQUIRE(refs.size() == 1);
    CHECK(refs[0].rfind("cornell-box-64x64-path-spectral-1024-", 0) == 0);
    std::string md = test::readText(out + "/summary.md");
    CHECK(md.find("--spectral") != std::string::npos);
    CHECK(md.find("path (spectral), 1024 spp") != std::string::npos);

    // The flag reaches the renders: against the same given reference, with the same seed, the
    // spectral preview renders' errors differ from the RGB ones (an RGB render is
    // deterministic, so a flag that changed nothing would give the same numbers).
    auto previewErrors = [&](bool spectral) {
        std::vector<std::string> args = {
            "bench", "--quick", "-q", "--modes", "preview", "-o", dir.file(spectral ? "s" : "rgb"),
            "--scenes-dir", scenes, "--reference",
            "cornell-box=" + test::goldenPath("cornell-box-path.exr")};
        if (spectral) args.push_back("--spectral");
        test::RunResult run = test::runRayproc(args, dir, 60);
        INFO(run.err);
        REQUIRE(run.status == 0);
        std::vector<double> errors;
        for (const bench::BenchRow& row : bench::readResultsCsv(dir.file(spectral ? "s" : "rgb") +
                                                                "/results.csv"))
            errors.push_back(row.relmse);
        return errors;
    };
    std::vector<double> rgb = previewErrors(false), spectral = previewErrors(true);
    REQUIRE(rgb.size() == 2); // preview's ladder: 1 and 4 spp
    REQUIRE(spectral.size() == rgb.size());
    for (std::size_t i = 0; i < rgb.size(); ++i) CHECK(spectral[i] != rgb[i]);
}

TEST_CASE("rayproc bench --spectral refuses --ablation", "[cli][bench]") {
    test::TempDir dir;
    const std::string scenes = (test::sourceDir() / "scenes").string();
    test::RunResult r;
    r = test::runRayproc({"bench", "--quick", "--spectral", "--ablation", "-o", dir.file("b"),
                          "--scenes-dir", scenes},
                         dir, 30);
    CHECK(r.status == 1);
    CHECK(r.err.find("--spectral renders the curves spectrally; --ablation") !=
          std::string::npos);
    CHECK(!std::filesystem::exists(dir.file("b/ablation.csv")));
}
