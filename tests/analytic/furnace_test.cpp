// Furnaces: the camera inside a closed diffuse sphere, where every point sees the same
// radiance, so every pixel has the closed-form value.
//  - Inside-out furnace (pbrt-v4's test): the sphere of albedo a emits Le from its inside.
//    Full global illumination gives L = Le + a L, so L = Le / (1 - a) (path mode). Without
//    indirect diffuse light only the emission and its direct reflection remain: the sphere's
//    irradiance from itself is pi Le, reflected a Le, so L = Le (1 + a) (raytrace, and preview
//    whose sphere light is a point light of intensity pi r^2 Le at the centre: irradiance
//    pi Le at every point of the sphere, the same).
//  - A point light of intensity I at the centre of a sphere of radius r, albedo a: direct
//    L1 = a / pi * I / r^2 at every point, and each bounce multiplies it by a, so
//    L = L1 / (1 - a) (path), L = L1 (raytrace, preview: one deterministic shadow ray).
// The channels carry different albedos, so one render checks three of them.
#include "analytic.h"

using namespace rayproc;
using namespace rayproc::test;

namespace {

constexpr int kSize = 32;

// A camera at the centre of a sphere of radius `radius` with albedo `albedo`.
std::string sphereFurnace(const Vec3& albedo, float radius, const std::string& emission,
                          const std::string& lights) {
    return R"({"camera": {"position": [0, 0, 0], "look_at": [0, 0, -1], "fov": 70,
                          "resolution": [32, 32]},
               "materials": {"wall": {"type": "diffuse", "color": )" +
           jsonVec(albedo) + R"(}},
               "lights": )" + lights + R"(,
               "nodes": [{"type": "sphere", "material": "wall", "radius": )" +
           std::to_string(radius) + emission + "}]}";
}

} // namespace

TEST_CASE("Inside-out furnace: Le / (1 - a) with GI, Le (1 + a) without", "[analytic]") {
    const Vec3 albedo(0.5f, 0.8f, 0.2f);
    const Vec3 le(1.0f, 1.0f, 2.0f);
    auto scene = sceneFromJson(sphereFurnace(albedo, 1.0f,
                                             R"(, "emission": )" + jsonVec(le) +
                                                 R"(, "two_sided": true)",
                                             "[]"));
    REQUIRE(scene->camera.width == kSize);
    EmbreeScene accel(*scene);

    Vec3 gi, direct;
    for (int c = 0; c < 3; ++c) {
        gi[c] = le[c] / (1.0f - albedo[c]);
        direct[c] = le[c] * (1.0f + albedo[c]);
    }
    SECTION("path") { checkMeanRadiance(renderMode(*scene, accel, "path", 256), gi, 0.01, "path"); }
    SECTION("gi") {
        // Direct light (Le (1 + a)) by shadow rays; the rest, a^2 Le / (1 - a), from the
        // cache's final gathers reading the global map. The photons leave the sphere from an
        // offset origin (a photon starting on the surface could be stored at t ~ 0).
        checkMeanRadiance(renderGiMode(*scene, accel, 4).image, gi, kGiTolerance, "gi");
    }
    SECTION("gi, the map corrected per pixel and per cache record") {
        // The corrections' paths stand for the photons' light, so they go as deep as the
        // photons: at gi's own depth limit (8, its specular chains') the albedo-0.8 channel
        // came out 11% dark per pixel, 7% per record.
        EngineSettings engine;
        engine.threads = 2;
        engine.seed = 1;
        engine.quiet = true;
        GiSettings s = giSettings(*scene, ModeOverrides{32, 0, 0});
        s.mapCorrection = true;
        s.icCorrectionRays = 4;
        checkMeanRadiance(renderGi(*scene, accel, s, engine).image, gi, kGiTolerance,
                          "gi corrected");
    }
    SECTION("raytrace") {
        checkMeanRadiance(renderMode(*scene, accel, "raytrace", 4), direct, 0.01, "raytrace");
    }
    SECTION("preview") {
        checkMeanRadiance(renderMode(*scene, accel, "preview", 1), direct, 0.01, "preview");
    }
}

TEST_CASE("Point light at the centre of a sphere: a/pi I/r^2, over (1 - a) with GI",
          "[analytic]") {
    const Vec3 albedo(0.5f, 0.8f, 0.2f);
    const float r = 2.0f;
    const Vec3 intensity(4.0f, 4.0f, 8.0f);
    auto scene = sceneFromJson(sphereFurnace(
        albedo, r, "",
        R"([{"type": "point", "position": [0, 0, 0], "intensity": )" + jsonVec(intensity) + "}]"));
    EmbreeScene accel(*scene);

    Vec3 gi, direct;
    for (int c = 0; c < 3; ++c) {
        direct[c] = albedo[c] / kPi * intensity[c] / (r * r);
        gi[c] = direct[c] / (1.0f - albedo[c]);
    }
    SECTION("path") { checkMeanRadiance(renderMode(*scene, accel, "path", 256), gi, 0.01, "path"); }
    SECTION("gi") {
        checkMeanRadiance(renderGiMode(*scene, accel, 1).image, gi, kGiTolerance, "gi");
    }
    SECTION("gi debug view: photons") {
        // The global map alone at the first hit holds every bounce: L1 / (1 - a) too.
        checkMeanRadiance(renderGiMode(*scene, accel, 16, 1, GiDebugView::Photons).image, gi,
                          kGiTolerance, "gi photons view");
    }
    SECTION("raytrace") {
        checkMeanRadiance(renderMode(*scene, accel, "raytrace", 1), direct, 1e-4, "raytrace");
    }
    SECTION("preview") {
        checkMeanRadiance(renderMode(*scene, accel, "preview", 1), direct, 1e-4, "preview");
    }
}
