// JSON scenes' blackbody light colours (docs/scene-format.md, "lights"): {"blackbody": K,
// "scale": s} is pbrt-v4's blackbody light, Planck's law at luminance 1 times s: RGB mode takes
// its colour, the spectral mode its spectrum; errors name the JSON path.
#include "scene_test_files.h"
#include "test_util.h"

#include "accel/embree_scene.h"
#include "modes/modes.h"
#include "scene/pbrt/pbrt_spectrum.h"
#include "scene/scene_loader.h"

#include <catch2/catch.hpp>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// A cyan square lit head-on by a directional light of irradiance `irradiance` (JSON text).
std::string litSquare(const std::string& irradiance) {
    return R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 20, "resolution": [8, 8]},
      "materials": {"cyan": {"type": "diffuse", "color": [0.1, 0.9, 0.9]}},
      "lights": [{"type": "directional", "direction": [0, 0, -1], "irradiance": )" +
           irradiance + R"(}],
      "nodes": [{"type": "quad", "material": "cyan",
                 "corners": [[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]]}]})";
}

Image render(const Scene& scene, bool spectral) {
    EmbreeScene accel(scene);
    return renderPath(scene, accel, pathSettings(scene.render, ModeOverrides{4, 0, 0}),
                      quietTwoThreads(spectral))
        .image;
}

} // namespace

TEST_CASE("JSON lights: a blackbody colour is pbrt-v4's blackbody light", "[scene][spectral]") {
    auto scene = sceneFromJson(R"({"lights": [
        {"type": "point", "position": [0, 1, 0], "intensity": {"blackbody": 2700, "scale": 5}},
        {"type": "directional", "direction": [0, -1, 0], "irradiance": {"blackbody": 4000}},
        {"type": "environment", "radiance": {"blackbody": 6000, "scale": 0.5}, "scale": 2},
        {"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0], "intensity": [1, 2, 3]}],
        "materials": {"m": {"type": "diffuse"}}, )" + std::string(kOneSphere) + "}");
    REQUIRE(scene->lights.size() == 4);
    const std::pair<double, float> expected[] = {{2700, 5.0f}, {4000, 1.0f}, {6000, 1.0f}};
    for (std::size_t i = 0; i < 3; ++i) {
        const auto [kelvin, scale] = expected[i];
        const Light& l = scene->lights[i];
        INFO("light " << i);
        REQUIRE(l.spectrum);
        CHECK(l.spectrum->label == pbrt::blackbodyEmission(kelvin)->label);
        CHECK(l.spectrum->values.values == pbrt::blackbodyEmission(kelvin)->values.values);
        const Vec3 rgb = pbrt::blackbodyRgb(kelvin) * scale;
        CHECK(l.intensity == rgb);
    }
    CHECK_FALSE(scene->lights[3].spectrum); // an RGB colour has none
}

TEST_CASE("JSON lights: RGB mode renders a blackbody's colour, the spectral mode its spectrum",
          "[scene][spectral]") {
    auto blackbody = sceneFromJson(litSquare(R"({"blackbody": 2700})"));
    const Vec3 c = pbrt::blackbodyRgb(2700);
    auto rgb = sceneFromJson(litSquare("[" + std::to_string(c.x) + ", " + std::to_string(c.y) +
                                       ", " + std::to_string(c.z) + "]"));
    REQUIRE(blackbody->lights[0].intensity == c);
    rgb->lights[0].intensity = c; // to the bit (the decimal text rounds)
    CHECK(sameBits(render(*blackbody, false), render(*rgb, false)));
    // Planck's law against the RGB illuminant spectrum of its colour: the red of a cyan surface
    // differs by 3% (docs/spectral.md, "Emission spectra").
    const double a = meanValue(render(*blackbody, true)), b = meanValue(render(*rgb, true));
    INFO("spectral mean, blackbody " << a << ", its colour " << b);
    CHECK(a != b);
}

TEST_CASE("JSON lights: a bad blackbody colour names its JSON path", "[scene][spectral]") {
    auto withLight = [](const std::string& intensity) {
        return R"({"lights": [{"type": "point", "position": [0, 1, 0], "intensity": )" +
               intensity + "}], " + kOneMaterial + ", " + kOneSphere + "}";
    };
    checkLoadError("bb1.json", withLight(R"({"blackbody": -5})"), "/lights/0/intensity/blackbody",
                   "must be positive");
    checkLoadError("bb2.json", withLight(R"({"blackbody": 2700, "tint": 1})"),
                   "/lights/0/intensity/tint", "unknown key");
    checkLoadError("bb3.json", withLight(R"({"blackbody": 1})"), "/lights/0/intensity/blackbody",
                   "no visible light");
    checkLoadError("bb4.json", withLight(R"({"blackbody": 2700, "scale": -1})"),
                   "/lights/0/intensity/scale", "must not be negative");
    checkLoadError("bb5.json", withLight(R"({"scale": 2})"), "/lights/0/intensity",
                   "missing required key \"blackbody\"");
}
