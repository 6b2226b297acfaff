// `render --reference --error-log` and `diff` against references with NaN or infinite pixels:
// such pixels are left out of every error, as diff always did; a reference without a finite
// pixel is an error that says so (it printed "-nan" rows in the error log and in bench).
#include "test_util.h"

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>

using namespace rayproc;
using namespace rayproc::test;

namespace {

bool contains(const std::string& text, const std::string& what) {
    return text.find(what) != std::string::npos;
}

const char* kScene = R"({"camera": {"position": [0, 0, 5], "resolution": [8, 8]},
    "materials": {"m": {"type": "diffuse"}},
    "lights": [{"type": "point", "position": [0, 0, 4], "intensity": [1, 1, 1]}],
    "nodes": [{"type": "sphere", "radius": 1, "material": "m"}]})";

// A copy of `image` whose pixels up to `count` (row-major) are NaN.
Image withNaN(Image image, std::size_t count) {
    for (std::size_t p = 0; p < count; ++p) image.pixels[p * 3 + 1] = std::nanf("");
    return image;
}

} // namespace

TEST_CASE("render --error-log leaves NaN reference pixels out, refuses an all-NaN reference",
          "[cli]") {
    TempDir dir;
    std::string scene = dir.file("scene.json"), ref = dir.file("ref.pfm");
    writeText(scene, kScene);
    REQUIRE(runRayproc({"render", scene, "--mode", "raytrace", "--quiet", "-o", ref}, dir).status == 0);
    Image good = readImage(ref);
    std::string half = dir.file("half.pfm"), all = dir.file("nan.pfm");
    writeImage(half, withNaN(good, 32));
    writeImage(all, withNaN(good, 64));

    std::string log = dir.file("log.csv");
    RunResult r = runRayproc({"render", scene, "--mode", "raytrace", "--spp", "2", "--reference",
                              half, "--error-log", log, "-o", dir.file("a.pfm")},
                             dir);
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(contains(r.err, "32 pixels are NaN or infinite"));
    // Every row's relmse and rmse (columns 3 and 4) are numbers over the finite half.
    std::istringstream rows(readText(log));
    std::string row;
    std::getline(rows, row); // the header
    int rowCount = 0;
    while (std::getline(rows, row)) {
        ++rowCount;
        INFO(row);
        std::istringstream cols(row);
        std::string col[4];
        for (std::string& c : col) std::getline(cols, c, ',');
        CHECK(std::isfinite(std::strtod(col[2].c_str(), nullptr)));
        CHECK(std::isfinite(std::strtod(col[3].c_str(), nullptr)));
        CHECK(col[2].find("nan") == std::string::npos);
    }
    CHECK(rowCount > 0);

    std::string log2 = dir.file("log2.csv");
    RunResult n = runRayproc({"render", scene, "--mode", "raytrace", "--spp", "2", "--reference",
                              all, "--error-log", log2, "-o", dir.file("b.pfm")},
                             dir);
    INFO(n.err);
    CHECK(n.status != 0);
    CHECK(contains(n.err, "no pixel of the reference is finite"));
    CHECK_FALSE(std::filesystem::exists(dir.file("b.pfm")));

    RunResult d = runRayproc({"diff", ref, all}, dir);
    INFO(d.err);
    CHECK(d.status == 2);
    CHECK(contains(d.err, "no pixel of the reference is finite"));
}
