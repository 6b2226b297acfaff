// JSON image environments and goniometric lights: relative image paths, mappings, frames and
// scales as loaded, and errors that name the JSON path.
#include "core/error.h"
#include "image/image.h"
#include "scene/scene_loader.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <unistd.h>

using namespace rayproc;

namespace {

// A per-process folder with two images, removed at exit.
struct JsonLightsDir {
    std::filesystem::path path = std::filesystem::temp_directory_path() /
                                 ("rayproc-json-lights-" + std::to_string(::getpid()));
    JsonLightsDir() {
        std::filesystem::create_directories(path / "maps");
        writeImage((path / "maps" / "square.pfm").string(), Image(8, 8));
        writeImage((path / "maps" / "wide.pfm").string(), Image(16, 8));
    }
    ~JsonLightsDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
};

std::filesystem::path testDir() {
    static JsonLightsDir dir;
    return dir.path;
}

std::unique_ptr<Scene> load(const std::string& lights) {
    std::string json = R"({"lights": [)" + lights +
                       R"(], "materials": {"m": {"type": "diffuse"}}, "nodes": [{"type": "sphere", "material": "m", "radius": 1}]})";
    return loadSceneFromString(json, (testDir() / "scene.json").string());
}

std::string errorOf(const std::string& lights) {
    try {
        load(lights);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST_CASE("JSON image environment and goniometric lights load", "[lights]") {
    auto s = load(R"({"type": "environment", "image": "maps/wide.pfm", "mapping": "lat-long",
                      "scale": 2, "radiance": [1, 0.5, 0.25],
                      "transform": {"rotate": {"angle": -90, "axis": [1, 0, 0]}}},
                     {"type": "goniometric", "position": [0, 2, 0], "intensity": [3, 3, 3],
                      "image": "maps/square.pfm"})");
    REQUIRE(s->lights.size() == 2);
    const Light& sky = s->lights[0];
    REQUIRE(sky.image);
    CHECK(sky.image->width == 16);
    CHECK(sky.mapping == EnvironmentMapping::LatLong);
    CHECK(sky.intensity.y == Approx(1.0f));
    Vec3 up = sky.toWorld.vector({0, 0, 1}); // the map's +z becomes world +y
    CHECK(up.y == Approx(1.0f));
    const Light& g = s->lights[1];
    CHECK(g.type == LightType::Goniometric);
    REQUIRE(g.image);
    CHECK(g.position.y == Approx(2.0f));
    auto e = load(R"({"type": "environment", "image": "maps/square.pfm"})");
    CHECK(e->lights[0].mapping == EnvironmentMapping::EqualArea);
    CHECK(e->lights[0].intensity.x == Approx(1.0f));
}

TEST_CASE("JSON light image errors name the JSON path", "[lights]") {
    CHECK_THAT(errorOf(R"({"type": "environment", "image": "maps/missing.exr"})"),
               Catch::Contains("/lights/0/image") && Catch::Contains("missing.exr"));
    CHECK_THAT(errorOf(R"({"type": "environment", "image": "maps/wide.pfm"})"),
               Catch::Contains("/lights/0/image") && Catch::Contains("square"));
    CHECK_THAT(errorOf(R"({"type": "environment", "image": "maps/square.pfm", "mapping": "cube"})"),
               Catch::Contains("/lights/0/mapping"));
    CHECK_THAT(errorOf(R"({"type": "environment", "radiance": [1, 1, 1], "mapping": "lat-long"})"),
               Catch::Contains("/lights/0/mapping"));
    CHECK_THAT(errorOf(R"({"type": "goniometric", "position": [0, 0, 0], "intensity": [1, 1, 1],
                          "image": "maps/wide.pfm"})"),
               Catch::Contains("/lights/0/image") && Catch::Contains("square"));
    CHECK_THAT(errorOf(R"({"type": "environment", "image": "maps/square.pfm", "scale": -1})"),
               Catch::Contains("/lights/0/scale"));
}
