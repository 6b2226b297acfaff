// `rayproc diff`, run as a real process: printed and JSON metrics on PFM, EXR and PNG inputs, the
// difference image and heatmap files, the crop, the limits' exit status 1, and status 2 for
// every error.
#include "image/heatmap.h"
#include "test_util.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <limits>
#include <regex>

using namespace rayproc;
using namespace rayproc::test;

namespace {

bool contains(const std::string& text, const std::string& what) {
    return text.find(what) != std::string::npos;
}

Image constantImage(int w, int h, float v) {
    Image img(w, h);
    for (float& p : img.pixels) p = v;
    return img;
}

// The number after `key` on its line of the text output ("rmse     0.125").
double printed(const std::string& out, const std::string& key) {
    std::smatch m;
    std::regex re("(^|\\n)" + key + " +([^ \\n]+)");
    REQUIRE(std::regex_search(out, m, re));
    return m[2] == "inf" ? INFINITY : std::stod(m[2]);
}

// Test (b + d everywhere) and reference (b), written as `ext` files under `dir`.
struct Pair {
    std::string test, reference;
};
Pair writePair(const TempDir& dir, const std::string& ext, int w, int h, float b, float d) {
    Pair p{dir.file("test." + ext), dir.file("reference." + ext)};
    writeImage(p.test, constantImage(w, h, b + d));
    writeImage(p.reference, constantImage(w, h, b));
    return p;
}

} // namespace

TEST_CASE("diff prints the metrics of PFM and EXR images", "[cli]") {
    TempDir dir;
    const double b = 0.5, d = 0.125;
    for (const char* ext : {"pfm", "exr"}) {
        INFO(ext);
        Pair p = writePair(dir, ext, 12, 8, float(b), float(d));
        RunResult r = runRayproc({"diff", p.test, p.reference}, dir);
        INFO(r.out << r.err);
        CHECK(r.status == 0);
        CHECK(printed(r.out, "rmse") == Approx(d).epsilon(1e-5));
        CHECK(printed(r.out, "relmse") == Approx(d * d / (b * b + 0.01)).epsilon(1e-5));
        CHECK(printed(r.out, "psnr") == Approx(10 * std::log10(1 / (d * d))).epsilon(1e-5));
        CHECK(printed(r.out, "mae") == Approx(d).epsilon(1e-5));
        CHECK(printed(r.out, "max_abs") == Approx(d).epsilon(1e-5));
        CHECK(printed(r.out, "pixels") == 96);
    }
}

TEST_CASE("diff --json has every key - identical images give psnr null", "[cli]") {
    TempDir dir;
    Pair p = writePair(dir, "pfm", 6, 4, 0.25f, 0.5f);
    RunResult r = runRayproc({"diff", p.test, p.reference, "--json"}, dir);
    INFO(r.out << r.err);
    REQUIRE(r.status == 0);
    auto j = nlohmann::json::parse(r.out);
    for (const char* key :
         {"rmse", "relmse", "psnr", "mae", "max_abs", "pixels", "width", "height", "exceeded"})
        CHECK(j.contains(key));
    CHECK(j["width"] == 6);
    CHECK(j["height"] == 4);
    CHECK(j["pixels"] == 24);
    CHECK(j["rmse"].get<double>() == Approx(0.5));
    CHECK(j["relmse"].get<double>() == Approx(0.25 / (0.0625 + 0.01)));
    CHECK(j["mae"].get<double>() == Approx(0.5));
    CHECK(j["max_abs"].get<double>() == Approx(0.5));
    CHECK(j["psnr"].get<double>() == Approx(10 * std::log10(4.0)));
    CHECK(j["exceeded"].empty());

    RunResult same = runRayproc({"diff", p.reference, p.reference, "--json"}, dir);
    INFO(same.out << same.err);
    REQUIRE(same.status == 0);
    auto k = nlohmann::json::parse(same.out);
    CHECK(k["psnr"].is_null());
    CHECK(k["rmse"] == 0.0);
    CHECK(k["max_abs"] == 0.0);
    // The text output says inf.
    RunResult text = runRayproc({"diff", p.reference, p.reference}, dir);
    CHECK(contains(text.out, "psnr     inf"));
}

TEST_CASE("diff --json stays JSON when a file name is not UTF-8", "[cli]") {
    // Linux file names are bytes: this one printed nlohmann's type_error 316 instead of JSON.
    TempDir dir;
    std::string test = dir.file("test-\xff\xfe.pfm"), reference = dir.file("reference.pfm");
    writeImage(test, constantImage(4, 4, 0.5f));
    writeImage(reference, constantImage(4, 4, 0.25f));
    RunResult r = runRayproc({"diff", test, reference, "--json"}, dir);
    INFO(r.out << r.err);
    REQUIRE(r.status == 0);
    auto j = nlohmann::json::parse(r.out);
    CHECK(j["test"].get<std::string>() ==
          dir.file("test-\xef\xbf\xbd\xef\xbf\xbd.pfm")); // U+FFFD each
    CHECK(j["reference"] == reference);
    CHECK(j["rmse"].get<double>() == Approx(0.25));
}

TEST_CASE("diff reads PNG (decoded to linear) and compares it with EXR", "[cli]") {
    TempDir dir;
    std::string png = dir.file("test.png"), exr = dir.file("reference.exr");
    writeImage(png, constantImage(5, 5, 0.5f));
    writeImage(exr, constantImage(5, 5, 0.25f));
    RunResult r = runRayproc({"diff", png, exr, "--json"}, dir);
    INFO(r.out << r.err);
    REQUIRE(r.status == 0);
    auto j = nlohmann::json::parse(r.out);
    // The PNG holds 0.5 quantised to 8-bit sRGB (188), which reads back as 0.5029.
    double decoded = srgbToLinear(float(toSrgb8(0.5f, {})) / 255.0f);
    CHECK(j["rmse"].get<double>() == Approx(decoded - 0.25).epsilon(1e-5));
}

TEST_CASE("diff writes the difference image and the heatmap", "[cli]") {
    TempDir dir;
    Pair p = writePair(dir, "pfm", 20, 10, 0.5f, 0.125f);
    std::string diffPfm = dir.file("diff.pfm"), diffPng = dir.file("diff.png");
    std::string heat = dir.file("heat.png"), bare = dir.file("bare.exr");
    RunResult r = runRayproc(
        {"diff", p.test, p.reference, "-o", diffPfm, "--scale", "4", "--heatmap", heat}, dir);
    INFO(r.out << r.err);
    REQUIRE(r.status == 0);
    Image d = readImage(diffPfm);
    CHECK(d.width == 20);
    CHECK(d.height == 10);
    CHECK(d.at(3, 7)[1] == Approx(0.5)); // 4 * 0.125
    Image h = readImage(heat);
    HeatmapSize expected = heatmapSize(20, 10, HeatmapSettings{});
    CHECK(h.width == expected.width);
    CHECK(h.height == expected.height);
    CHECK(h.width > 20); // the colour bar sits right of the image

    RunResult r2 = runRayproc({"diff", p.test, p.reference, "-o", diffPng, "--heatmap", bare,
                               "--no-legend", "--heatmap-metric", "abs", "--heatmap-scale",
                               "linear", "--crop", "2", "2", "8", "6"},
                              dir);
    INFO(r2.out << r2.err);
    REQUIRE(r2.status == 0);
    Image dp = readImage(diffPng);
    CHECK(dp.width == 20);
    CHECK(dp.height == 10);
    CHECK(dp.at(0, 0)[0] == Approx(0.125).margin(0.003)); // 8-bit sRGB
    Image b = readImage(bare);
    CHECK(b.width == 20);
    CHECK(b.height == 10);
}

TEST_CASE("diff --crop compares only the region", "[cli]") {
    TempDir dir;
    Image ref = constantImage(16, 16, 0.5f), test = ref;
    for (int c = 0; c < 3; ++c) test.at(12, 12)[c] = 3.0f; // outside the crop
    writeImage(dir.file("a.pfm"), test);
    writeImage(dir.file("b.pfm"), ref);
    RunResult r = runRayproc(
        {"diff", dir.file("a.pfm"), dir.file("b.pfm"), "--json", "--crop", "0", "0", "8", "8"},
        dir);
    INFO(r.out << r.err);
    REQUIRE(r.status == 0);
    auto j = nlohmann::json::parse(r.out);
    CHECK(j["pixels"] == 64);
    CHECK(j["max_abs"] == 0.0);
    CHECK(j["crop"] == nlohmann::json::array({0, 0, 8, 8}));
    RunResult whole = runRayproc({"diff", dir.file("a.pfm"), dir.file("b.pfm"), "--json"}, dir);
    CHECK(nlohmann::json::parse(whole.out)["max_abs"].get<double>() == Approx(2.5));
}

TEST_CASE("diff limits: exit 1 when exceeded, naming the limit - 0 otherwise", "[cli]") {
    TempDir dir;
    // rmse = 0.1, relmse = 0.01 / (0.25 + 0.01) = 0.03846.
    Pair p = writePair(dir, "pfm", 8, 8, 0.5f, 0.1f);
    RunResult over = runRayproc({"diff", p.test, p.reference, "--max-relmse", "0.03"}, dir);
    INFO(over.out << over.err);
    CHECK(over.status == 1);
    CHECK(contains(over.err, "--max-relmse"));
    CHECK(contains(over.out, "relmse")); // the metrics are printed all the same

    RunResult under = runRayproc({"diff", p.test, p.reference, "--max-relmse", "0.04"}, dir);
    CHECK(under.status == 0);
    CHECK(under.err.empty());

    RunResult rmse = runRayproc(
        {"diff", p.test, p.reference, "--max-relmse", "1", "--max-rmse", "0.05", "--json"}, dir);
    INFO(rmse.out << rmse.err);
    CHECK(rmse.status == 1);
    CHECK(contains(rmse.err, "--max-rmse"));
    CHECK_FALSE(contains(rmse.err, "--max-relmse"));
    CHECK(nlohmann::json::parse(rmse.out)["exceeded"] == nlohmann::json::array({"rmse"}));

    CHECK(runRayproc({"diff", p.test, p.reference, "--max-rmse", "0.2"}, dir).status == 0);
}

TEST_CASE("diff --relmse-denominator takes relMSE's b from a third image", "[cli]") {
    TempDir dir;
    // Test 0.6 against a converged 0.5; the true reference 1.0, at twice the size.
    Pair p = writePair(dir, "pfm", 8, 8, 0.5f, 0.1f);
    writeImage(dir.file("full.exr"), constantImage(16, 16, 1.0f));
    const std::string full = dir.file("full.exr");
    RunResult r = runRayproc({"diff", p.test, p.reference, "--relmse-denominator", full}, dir);
    INFO(r.out << r.err);
    CHECK(r.status == 0);
    CHECK(printed(r.out, "relmse") == Approx(0.01 / (1.0 + 0.01)).epsilon(1e-5));
    CHECK(printed(r.out, "rmse") == Approx(0.1).epsilon(1e-5));
    CHECK(contains(r.out, "denominators from"));

    RunResult j = runRayproc({"diff", p.test, p.reference, "--relmse-denominator",
                              dir.file("full.exr"), "--json", "--max-relmse", "0.0098"},
                             dir);
    INFO(j.out << j.err);
    CHECK(j.status == 1); // 0.0099 > 0.0098: the limit applies to the denominator's relMSE
    nlohmann::json parsed = nlohmann::json::parse(j.out);
    CHECK(parsed["relmse"].get<double>() == Approx(0.01 / 1.01).epsilon(1e-5));
    CHECK(parsed["relmse_denominator"] == dir.file("full.exr"));

    writeImage(dir.file("odd.pfm"), constantImage(12, 8, 1.0f));
    // The heatmap takes the same denominators (tests/image/metrics_test.cpp checks the values).
    RunResult heat = runRayproc({"diff", p.test, p.reference, "--relmse-denominator", full,
                                 "--heatmap", dir.file("heat.pfm")},
                                dir);
    CHECK(heat.status == 0);
    CHECK(std::filesystem::exists(dir.file("heat.pfm")));

    const std::string odd = dir.file("odd.pfm");
    RunResult bad = runRayproc({"diff", p.test, p.reference, "--relmse-denominator", odd}, dir);
    INFO(bad.err);
    CHECK(bad.status == 2);
    CHECK(contains(bad.err, "--relmse-denominator"));
    CHECK(contains(bad.err, "12x8"));
    RunResult missing = runRayproc(
        {"diff", p.test, p.reference, "--relmse-denominator", dir.file("none.pfm")}, dir);
    CHECK(missing.status == 2);
    CHECK(contains(missing.err, "none.pfm"));
}

TEST_CASE("diff --scale beyond float's range is an error, an overflowing product a warning",
          "[cli]") {
    TempDir dir;
    Pair p = writePair(dir, "pfm", 4, 4, 0.5f, 4.0f);
    std::string out = dir.file("diff.pfm");
    RunResult big = runRayproc({"diff", p.test, p.reference, "-o", out, "--scale", "1e39"}, dir);
    INFO(big.err);
    CHECK(big.status == 2);
    CHECK(contains(big.err, "--scale"));
    CHECK_FALSE(std::filesystem::exists(out));

    RunResult clamp = runRayproc({"diff", p.test, p.reference, "-o", out, "--scale", "3e38"}, dir);
    INFO(clamp.err);
    REQUIRE(clamp.status == 0);
    CHECK(contains(clamp.err, "warning"));
    CHECK(contains(clamp.err, "clamped"));
    Image d = readImage(out);
    for (float v : d.pixels) CHECK(v == std::numeric_limits<float>::max());
}

TEST_CASE("diff errors exit 2 with a clear message", "[cli]") {
    TempDir dir;
    Pair p = writePair(dir, "pfm", 8, 8, 0.5f, 0.1f);
    writeImage(dir.file("small.pfm"), constantImage(8, 6, 0.5f));

    RunResult size = runRayproc({"diff", p.test, dir.file("small.pfm")}, dir);
    INFO(size.err);
    CHECK(size.status == 2);
    CHECK(contains(size.err, "8x8"));
    CHECK(contains(size.err, "8x6"));

    RunResult missing = runRayproc({"diff", dir.file("nope.exr"), p.reference}, dir);
    INFO(missing.err);
    CHECK(missing.status == 2);
    CHECK(contains(missing.err, "nope.exr"));

    writeText(dir.file("garbage.pfm"), "PF\nnot an image\n");
    RunResult garbage = runRayproc({"diff", dir.file("garbage.pfm"), p.reference}, dir);
    INFO(garbage.err);
    CHECK(garbage.status == 2);
    CHECK(contains(garbage.err, "garbage.pfm"));

    RunResult crop = runRayproc({"diff", p.test, p.reference, "--crop", "0", "0", "9", "4"}, dir);
    INFO(crop.err);
    CHECK(crop.status == 2);
    CHECK(contains(crop.err, "crop"));

    // Usage errors are 2 as well, never 1 (which means "limit exceeded").
    CHECK(runRayproc({"diff", p.test}, dir).status == 2);
    CHECK(runRayproc({"diff", p.test, p.reference, "--crop", "1", "2"}, dir).status == 2);
    CHECK(runRayproc({"diff", p.test, p.reference, "--max-rmse", "x"}, dir).status == 2);

    RunResult ext = runRayproc({"diff", p.test, p.reference, "-o", dir.file("d.txt")}, dir);
    CHECK(ext.status == 2);
    CHECK_FALSE(std::filesystem::exists(dir.file("d.txt")));
}

TEST_CASE("diff --help explains every option and the exit codes", "[cli]") {
    TempDir dir;
    RunResult r = runRayproc({"diff", "--help"}, dir);
    INFO(r.out);
    CHECK(r.status == 0);
    for (const char* option :
         {"--json", "--output", "--scale", "--heatmap", "--heatmap-metric", "--heatmap-scale",
          "--heatmap-range", "--no-legend", "--crop", "--max-relmse", "--max-rmse",
          "--relmse-denominator"}) {
        INFO("option " << option);
        CHECK(contains(r.out, std::string(option) + " "));
    }
    CHECK(contains(r.out, "Exit status"));
    CHECK(contains(runRayproc({"--help"}, dir).out, "diff"));
}
