// gi's focus region (gi/focus_region.h): the camera's view bounds the part of a large scene that
// photons are aimed at, and the aimed photons still carry the right power. A diffuse sphere of
// radius R under a directional light of irradiance E intercepts E pi R^2 (its cross-section),
// and under a constant sky of radiance L, 4 pi L pi R^2, however the photons are distributed,
// as long as each carries its flux divided by the emission density.
#include "engine/intersect.h"
#include "engine/pipeline.h"
#include "gi/focus_region.h"
#include "gi/gi_pipeline.h"
#include "gi/photon_emitter.h"
#include "gi/photon_stage.h"

#include "../analytic/analytic.h"

using namespace rayproc;
using namespace rayproc::test;

namespace {

// A unit sphere at the origin in view, and a second sphere 300 units away that the camera does
// not see: the scene's bounding sphere is 150 times the region in view.
std::unique_ptr<Scene> farScene(const std::string& light) {
    return sceneFromJson(
        R"({"camera": {"position": [0, 0, 6], "look_at": [0, 0, 0], "resolution": [32, 32],
                       "fov": 30},
            "materials": {"m": {"type": "diffuse", "color": [0.5, 0.5, 0.5]}},
            "lights": [)" + light + R"(],
            "nodes": [{"type": "sphere", "material": "m", "center": [0, 0, 0], "radius": 1},
                      {"type": "sphere", "material": "m", "center": [300, 0, 0], "radius": 1}]})");
}

struct Stored {
    Vec3 power{0, 0, 0};
    std::size_t photons = 0;
};

// First-hit photons stored on the sphere at the origin.
Stored storedOnNearSphere(const Scene& scene, const EmbreeScene& accel, const FocusRegion& focus,
                          std::uint32_t count) {
    LightSet lights = LightSet::build(scene, accel);
    Film film(1, 1);
    ShadingPolicy policy;
    RenderContext rc{scene, accel, lights, policy, film, 5};
    Stats stats;
    PhotonStage stage(rc, /*causticPass=*/false, /*maxPhotonDepth=*/1);
    Pipeline pipeline("photons", "photon", accel.root(), 16, stats, 2);
    pipeline.stage("photon", {kPhotonQueue}, stage);
    PhotonEmitter emitter(lights, scene.worldBounds(), count, 5, 1,
                          focus.active ? focus.emissionBounds() : Bounds3{},
                          focus.active ? kFocusPhotonShare : 0.0f);
    pipeline.run(emitter, [] { return false; });
    Stored s;
    double sum[3] = {0, 0, 0};
    for (const PhotonRecord& p : stage.takePhotons()) {
        if (length(p.position) > 1.5f) continue;
        ++s.photons;
        for (int c = 0; c < 3; ++c) sum[c] += p.power[c];
    }
    s.power = Vec3(float(sum[0]), float(sum[1]), float(sum[2]));
    return s;
}

} // namespace

TEST_CASE("Focus region: the camera's hits bound the sphere in view, not the far one", "[gi]") {
    auto scene = farScene(R"({"type": "directional", "direction": [0, -1, 0], "irradiance": [2, 2, 2]})");
    EmbreeScene accel(*scene);
    FocusRegion focus = cameraFocusRegion(*scene, accel, 16);
    CHECK(focus.active);
    CHECK(focus.hits > 0);
    for (int a = 0; a < 3; ++a) {
        CHECK(focus.bounds.lo[a] >= -1.001f);
        CHECK(focus.bounds.hi[a] <= 1.001f);
    }
    // The visible side of the sphere spans most of its width.
    CHECK(focus.bounds.hi.x - focus.bounds.lo.x > 1.5f);
}

TEST_CASE("Focus region: a camera that sees the whole scene leaves gi unfocused", "[gi]") {
    auto scene = sceneFromJson(
        R"({"camera": {"position": [0, 0, 6], "look_at": [0, 0, 0], "resolution": [32, 32]},
            "materials": {"m": {"type": "diffuse", "color": [0.5, 0.5, 0.5]}},
            "lights": [{"type": "directional", "direction": [0, -1, 0], "irradiance": [1, 1, 1]}],
            "nodes": [{"type": "sphere", "material": "m", "center": [-1, 0, 0], "radius": 0.8},
                      {"type": "sphere", "material": "m", "center": [1, 0, 0], "radius": 0.8}]})");
    EmbreeScene accel(*scene);
    CHECK_FALSE(cameraFocusRegion(*scene, accel, 16).active);
}

TEST_CASE("Focused directional photons: the sphere in view stores E pi R^2, from many more photons",
          "[gi]") {
    auto scene = farScene(R"({"type": "directional", "direction": [0, -1, 0], "irradiance": [2, 1, 0.5]})");
    EmbreeScene accel(*scene);
    FocusRegion focus = cameraFocusRegion(*scene, accel, 16);
    REQUIRE(focus.active);
    const std::uint32_t count = 100000;
    Stored focused = storedOnNearSphere(*scene, accel, focus, count);
    Stored uniform = storedOnNearSphere(*scene, accel, FocusRegion{}, count);
    Vec3 E(2, 1, 0.5f);
    for (int c = 0; c < 3; ++c) {
        double expected = E[c] * kPi;
        INFO("channel " << c << ": stored " << focused.power[c] << ", expected " << expected
                        << " from " << focused.photons << " photons");
        CHECK(focused.power[c] == Approx(expected).epsilon(0.02));
    }
    // Uniform emission over the scene's disk lands a handful of photons on the sphere.
    INFO("focused " << focused.photons << ", uniform " << uniform.photons);
    CHECK(focused.photons > 100 * std::max<std::size_t>(uniform.photons, 1));
}

TEST_CASE("Focused sky photons: the sphere in view stores 4 pi L pi R^2", "[gi]") {
    auto scene = farScene(R"({"type": "environment", "radiance": [0.5, 0.25, 1]})");
    EmbreeScene accel(*scene);
    FocusRegion focus = cameraFocusRegion(*scene, accel, 16);
    REQUIRE(focus.active);
    Stored focused = storedOnNearSphere(*scene, accel, focus, 200000);
    Vec3 L(0.5f, 0.25f, 1);
    for (int c = 0; c < 3; ++c) {
        double expected = 4 * kPi * L[c] * kPi;
        INFO("channel " << c << ": stored " << focused.power[c] << ", expected " << expected
                        << " from " << focused.photons << " photons");
        CHECK(focused.power[c] == Approx(expected).epsilon(0.03));
    }
}

TEST_CASE("The caustic focus follows the probe rays through water and off mirrors",
          "[gi][focus]") {
    // A floor at y = 0 under open water at y = 1 (6 x 6 both), seen from straight above: the
    // first hits are the water's surface, what the camera sees through it is the floor.
    auto scene = sceneFromJson(R"({
        "camera": {"position": [0, 3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1],
                   "resolution": [32, 32], "fov": 8},
        "materials": {"floor": {"type": "diffuse", "color": [0.5, 0.5, 0.5]},
                      "water": {"type": "dielectric", "ior": 1.33, "color": [1, 1, 1]}},
        "nodes": [
          {"type": "quad", "material": "floor", "corners": [[-3,0,-3],[-3,0,3],[3,0,3],[3,0,-3]]},
          {"type": "quad", "material": "water", "corners": [[-3,1,-3],[-3,1,3],[3,1,3],[3,1,-3]]},
          {"type": "quad", "material": "floor", "corners": [[-40,-5,-40],[-40,-5,40],[40,-5,40],[40,-5,-40]]}]})");
    EmbreeScene accel(*scene);
    FocusRegion focus = cameraFocusRegion(*scene, accel, 8);
    REQUIRE(focus.active);
    CHECK(focus.bounds.lo.y == Approx(1.0f).margin(1e-4));
    CHECK(focus.bounds.hi.y == Approx(1.0f).margin(1e-4));
    // The floor seen through the water is in the caustic pass's bounds, the water still too.
    CHECK(focus.specularBounds.lo.y == Approx(0.0f).margin(1e-4));
    CHECK(focus.specularBounds.hi.y == Approx(1.0f).margin(1e-4));
    CHECK(focus.specularBounds.hi.x - focus.specularBounds.lo.x < 1.0f);
    // Without specular surfaces in view both are the same.
    auto plain = farScene("");
    EmbreeScene plainAccel(*plain);
    FocusRegion p = cameraFocusRegion(*plain, plainAccel, 8);
    CHECK(p.specularBounds.lo == p.bounds.lo);
    CHECK(p.specularBounds.hi == p.bounds.hi);
}
