// Regression tests for the scene readers' limits on hostile input (docs/testing.md, "Bad input,
// fuzzing, sanitizers"): counts in a PLY file that the file cannot hold, list lengths that are
// not counts, non-finite vertices, and transforms that carry geometry beyond a float's range.
// Each case must be an InputError naming the problem, found before any allocation or loop
// proportional to the claimed size (the CLI tests repeat the worst under an address-space cap).
#include "core/error.h"
#include "scene/pbrt/pbrt_loader.h"
#include "scene/pbrt/ply_reader.h"
#include "scene/scene_loader.h"

#include <catch2/catch.hpp>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

using namespace rayproc;

namespace {

std::string plyError(const std::string& bytes) {
    try {
        pbrt::parsePly(bytes, "test.ply");
    } catch (const InputError& e) {
        return e.what();
    }
    FAIL("expected an InputError");
    return {};
}

const char* const kAsciiHead = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                               "property float y\nproperty float z\n";

std::string binaryTriangle(float nanAt) {
    std::string h = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                    "property float y\nproperty float z\nelement face 1\n"
                    "property list uchar int vertex_indices\nend_header\n";
    float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    v[4] = nanAt;
    std::string data(reinterpret_cast<const char*>(v), sizeof v);
    unsigned char n = 3;
    std::int32_t idx[3] = {0, 1, 2};
    data += std::string(reinterpret_cast<const char*>(&n), 1);
    data += std::string(reinterpret_cast<const char*>(idx), sizeof idx);
    return h + data;
}

} // namespace

TEST_CASE("PLY list lengths must be counts the file can hold", "[scene][bad-input]") {
    std::string faceHead = std::string(kAsciiHead) +
                           "element face 1\nproperty list uint int vertex_indices\nend_header\n"
                           "0 0 0\n1 0 0\n0 1 0\n";
    auto start = std::chrono::steady_clock::now();
    CHECK_THAT(plyError(faceHead + "4000000000 0 1 2\n"),
               Catch::Contains("face 0") && Catch::Contains("more than the file holds"));
    CHECK_THAT(plyError(faceHead + "-3 0 1 2\n"),
               Catch::Contains("face 0") && Catch::Contains("is not a count"));
    CHECK_THAT(plyError(faceHead + "2.5 0 1 2\n"), Catch::Contains("is not a count"));
    // A list in a skipped element and in the vertex element take the same check.
    std::string extra = std::string(kAsciiHead) + "property list uchar float extra\n" +
                        "element face 1\nproperty list uchar int vertex_indices\nend_header\n" +
                        "0 0 0 200 1\n1 0 0 0\n0 1 0 0\n3 0 1 2\n";
    CHECK_THAT(plyError(extra), Catch::Contains("vertex 0") && Catch::Contains("a list of 200"));
    std::string skipped = std::string(kAsciiHead) +
                          "element face 1\nproperty list uchar int vertex_indices\n"
                          "element edge 1\nproperty list uint int ends\nend_header\n"
                          "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3000000000 1\n";
    CHECK_THAT(plyError(skipped), Catch::Contains("edge 0") && Catch::Contains("more than"));
    // The largest list a file of this size can hold still loads.
    CHECK(pbrt::parsePly(faceHead + "3 0 1 2\n", "ok.ply").indices.size() == 3);
    CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(5));
}

TEST_CASE("PLY elements without properties cannot claim rows", "[scene][bad-input]") {
    // Nothing bounds the row count of an element without data: 10^18 empty rows used to be
    // skipped one by one.
    std::string text = std::string(kAsciiHead) +
                       "element face 1\nproperty list uchar int vertex_indices\n"
                       "element nothing 1000000000000000000\nend_header\n"
                       "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    auto start = std::chrono::steady_clock::now();
    CHECK_THAT(plyError(text), Catch::Contains("\"nothing\"") && Catch::Contains("no properties"));
    CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(5));
    // With zero rows it is harmless and loads.
    std::string zero = std::string(kAsciiHead) +
                       "element face 1\nproperty list uchar int vertex_indices\n"
                       "element nothing 0\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    CHECK(pbrt::parsePly(zero, "ok.ply").positions.size() == 3);
}

TEST_CASE("PLY vertices must be finite", "[scene][bad-input]") {
    CHECK(pbrt::parsePly(binaryTriangle(0.0f), "ok.ply").positions.size() == 3);
    CHECK_THAT(plyError(binaryTriangle(std::numeric_limits<float>::quiet_NaN())),
               Catch::Contains("vertex 1") && Catch::Contains("not a finite number"));
    CHECK_THAT(plyError(binaryTriangle(std::numeric_limits<float>::infinity())),
               Catch::Contains("vertex 1") && Catch::Contains("not a finite number"));
    // Doubles beyond a float's range would turn into infinities: ASCII refuses them as numbers.
    std::string h = "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\n"
                    "property double y\nproperty double z\nelement face 1\n"
                    "property list uchar int vertex_indices\nend_header\n";
    CHECK_THAT(plyError(h + "0 0 0\n1e300 0 0\n0 1 0\n3 0 1 2\n"),
               Catch::Contains("\"1e300\" is not a number"));
}

TEST_CASE("A pbrt transform cannot carry geometry beyond a float's range", "[scene][bad-input]") {
    const std::string head = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
                             "AreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\n";
    auto errorOf = [&](const std::string& world) -> std::string {
        std::vector<std::string> warnings;
        try {
            loadPbrtSceneFromString(head + world, "/nonexistent/scale.pbrt", &warnings);
        } catch (const InputError& e) {
            return e.what();
        }
        return "(loaded)";
    };
    std::string mesh = "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1e30 0 0 0 1e30 0] "
                       "\"integer indices\" [0 1 2]\n";
    CHECK(errorOf(mesh) == "(loaded)");
    CHECK_THAT(errorOf("Scale 1e30 1e30 1e30\n" + mesh),
               Catch::Contains("scale.pbrt:6:") && Catch::Contains("not finite"));
    CHECK(errorOf("Scale 1e30 1e30 1e30\nShape \"sphere\" \"float radius\" [1]\n") ==
          "(loaded)");
    CHECK_THAT(errorOf("Scale 1e30 1e30 1e30\nShape \"sphere\" \"float radius\" [1e30]\n"),
               Catch::Contains("scale.pbrt:6:") && Catch::Contains("not finite"));
}

namespace {

// Prototypes p0 .. p(n-1), each placing the next twice: the root and its instance make 2^n
// placements once nesting is flattened.
std::string instanceExplosion(int n) {
    std::string protos;
    for (int i = 0; i + 1 < n; ++i) {
        std::string next = "\"p" + std::to_string(i + 1) + "\"";
        protos += "\"p" + std::to_string(i) + "\": {\"children\": [" +
                  "{\"type\": \"instance\", \"prototype\": " + next +
                  ", \"transform\": {\"translate\": [1, 0, 0]}}, " +
                  "{\"type\": \"instance\", \"prototype\": " + next + "}]}, ";
    }
    protos += "\"p" + std::to_string(n - 1) + "\": {\"children\": [{\"type\": \"sphere\", " +
              "\"radius\": 1, \"emission\": [1, 1, 1]}]}";
    return "{\"prototypes\": {" + protos +
           "}, \"nodes\": [{\"type\": \"instance\", \"prototype\": \"p0\"}]}";
}

std::string loadError(const std::string& json) {
    try {
        loadSceneFromString(json, "/nonexistent/explosion.json");
    } catch (const InputError& e) {
        return e.what();
    }
    return "(loaded)";
}

} // namespace

TEST_CASE("Nested instancing cannot multiply into billions of placements", "[scene][bad-input]") {
    auto start = std::chrono::steady_clock::now();
    CHECK(loadError(instanceExplosion(22)) == "(loaded)"); // 2^22 placements: the limit
    CHECK_THAT(loadError(instanceExplosion(23)),
               Catch::Contains("explosion.json: /nodes: the scene places 8388608 groups") &&
                   Catch::Contains("the limit is 4194304"));
    // Counts saturate instead of wrapping around.
    CHECK_THAT(loadError(instanceExplosion(70)), Catch::Contains("more than 2^62"));
    CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(5));
}

TEST_CASE("Whole numbers written as floats stay within long long", "[scene][bad-input]") {
    // double(LLONG_MAX) rounds up to 2^63, so "seed": 2^63 written as a float passed the range
    // check and its conversion to long long was undefined behaviour (UBSan: float-cast-overflow).
    const char* scene = R"({"render": {"seed": %s},
        "nodes": [{"type": "sphere", "radius": 1, "emission": [1, 1, 1]}]})";
    for (const char* seed : {"9223372036854775808.0", "1e19", "1e300"}) {
        char text[512];
        std::snprintf(text, sizeof text, scene, seed);
        INFO(seed);
        CHECK_THAT(loadError(text), Catch::Contains("/render/seed: integer out of range"));
    }
    char text[512];
    std::snprintf(text, sizeof text, scene, "9223372036854774784.0"); // the largest double < 2^63
    CHECK(loadError(text) == "(loaded)");
}
