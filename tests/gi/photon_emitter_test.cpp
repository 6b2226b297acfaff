// The photon emitter's power unit: lights whose power passes float's range (an area light of
// radiance 3e37, a sky of 3e37, a directional light of 1e10 over a plane 1e15 wide) aborted gi
// with "internal check failed: isFinite(ph.power)". Photons now carry power in units of
// PhotonEmitter::powerUnit() and the map's estimates are scaled back: gi renders such scenes
// as the same scene at a sane brightness, times the factor.
#include "gi/photon_emitter.h"
#include "gi/photon_map.h"
#include "stress/stress_scenes.h"

#include <cmath>
#include <string>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// A diffuse plane `size` wide under a unit sphere, lit by `light` (a JSON light object).
std::unique_ptr<Scene> planeScene(double size, const std::string& light) {
    char corners[256];
    std::snprintf(corners, sizeof corners,
                  "[[%.17g, 0, %.17g], [%.17g, 0, %.17g], [%.17g, 0, %.17g], [%.17g, 0, %.17g]]",
                  -size, size, size, size, size, -size, -size, -size);
    return sceneFromJson(
        R"({"camera": {"position": [0, 3, 8], "look_at": [0, 0.5, 0], "resolution": [16, 12]},
            "materials": {"g": {"type": "diffuse", "color": [0.5, 0.5, 0.5]},
                          "s": {"type": "diffuse", "color": [0.8, 0.3, 0.2]}},
            "lights": [)" + light + R"(],
            "nodes": [{"type": "quad", "material": "g", "corners": )" + std::string(corners) +
            R"(}, {"type": "sphere", "material": "s", "center": [0, 1, 0], "radius": 1}]})",
        "photon-unit.json");
}

double unitOf(const Scene& scene) {
    EmbreeScene accel(scene);
    return PhotonEmitter::powerUnit(LightSet::build(scene, accel), scene.worldBounds());
}

} // namespace

TEST_CASE("Photon power unit: 1 for ordinary scenes, a power of two beyond float's range",
          "[gi]") {
    CHECK(unitOf(*loadSceneAt("cornell-box", 8, 8)) == 1.0);
    auto sky = planeScene(10, R"({"type": "environment", "radiance": [3e37, 3e37, 3e37]})");
    double u = unitOf(*sky);
    CHECK(u > 1e38);
    CHECK(std::ldexp(1.0, std::ilogb(u)) == u);
    auto dim = planeScene(10, R"({"type": "environment", "radiance": [1e-30, 1e-30, 1e-30]})");
    CHECK(unitOf(*dim) < 1e-25);
}

TEST_CASE("Photon map estimates are scaled by the power unit, exactly", "[gi]") {
    PhotonList photons;
    for (int i = 0; i < 64; ++i)
        photons.push_back({Vec3(float(i % 8) * 0.1f, 0, float(i / 8) * 0.1f),
                           Vec3(0.25f, 0.5f, 1.0f), Vec3(0, 1, 0), Vec3(0, 1, 0)});
    PhotonMap watts, units;
    watts.build(photons);
    units.build(photons);
    units.setPowerUnit(std::ldexp(1.0, 100));
    Vec3 p(0.35f, 0, 0.35f), n(0, 1, 0);
    Vec3 e = watts.irradiance(p, n, 16, 1.0f), eu = units.irradiance(p, n, 16, 1.0f);
    REQUIRE(e.x > 0);
    for (int c = 0; c < 3; ++c) CHECK(eu[c] == std::ldexp(e[c], 100));
    CHECK(units.irradianceWithin(p, n, 0.3f).y == std::ldexp(watts.irradianceWithin(p, n, 0.3f).y, 100));
    CHECK(units.photon(0).power.z == std::ldexp(1.0f, 100));
    watts.precomputeIrradiance(16, 1.0f, 4);
    units.precomputeIrradiance(16, 1.0f, 4);
    CHECK(units.irradianceFast(p, n, 16, 1.0f).x ==
          std::ldexp(watts.irradianceFast(p, n, 16, 1.0f).x, 100));
}

TEST_CASE("gi renders lights whose power passes float's range, as the dimmer scene times the "
          "factor",
          "[gi]") {
    struct Case {
        const char* name;
        double size;
        std::string bright, dim; // the light, and the same divided by `factor`
        double factor;
    };
    const Case cases[] = {
        // Its power through the disk covering the scene (r = 14), L 4 pi^2 r^2 = 7.7e38, passes
        // float's range; its light samples, L pi / cos, do not except at grazing angles.
        {"sky of radiance 1e35", 10, R"({"type": "environment", "radiance": [1e35, 1e35, 1e35]})",
         R"({"type": "environment", "radiance": [1, 1, 1]})", 1e35},
        {"directional light of 1e10 over a plane 1e15 wide", 1e15,
         R"({"type": "directional", "direction": [-0.3, -1, -0.2], "irradiance": [1e10, 1e10, 1e10]})",
         R"({"type": "directional", "direction": [-0.3, -1, -0.2], "irradiance": [1, 1, 1]})",
         1e10},
    };
    for (const Case& c : cases) {
        INFO(c.name);
        auto bright = planeScene(c.size, c.bright), dim = planeScene(c.size, c.dim);
        EmbreeScene brightAccel(*bright), dimAccel(*dim);
        RenderResult b = stress::renderStress(*bright, brightAccel, "gi", 2, 1);
        RenderResult d = stress::renderStress(*dim, dimAccel, "gi", 2, 1);
        REQUIRE(meanValue(d.image) > 0);
        CHECK(allFinite(b.image));
        CHECK(b.stats.totals.invalidSamples == 0);
        CHECK(b.stats.totals.clampedSamples == 0);
        Image scaled = b.image;
        for (float& v : scaled.pixels) v = float(double(v) / c.factor);
        CHECK(relMse(scaled, d.image) < 1e-8);
    }
}

TEST_CASE("gi with a sky of radiance 3e37 finishes with a finite image", "[gi]") {
    // Its photons are fine now; what is left is the sky's own light samples in direct
    // lighting, whose weight L pi / cos passes float's range at grazing angles: those samples
    // are dropped and counted (invalid_samples, with a warning), not an abort
    // (docs/robustness.md, "Light power beyond float's range in gi").
    auto sky = planeScene(10, R"({"type": "environment", "radiance": [3e37, 3e37, 3e37]})");
    EmbreeScene accel(*sky);
    RenderResult r = stress::renderStress(*sky, accel, "gi", 2, 1);
    CHECK(allFinite(r.image));
    CHECK(meanValue(r.image) > 1e36);
}
