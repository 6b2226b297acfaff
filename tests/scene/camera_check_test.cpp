// The camera's limits (scene/camera_check.h), one check for the JSON loader, the pbrt importer,
// serve's camera message and EmbreeScene: a camera whose rays would leave Embree's range is
// refused, naming the field (its JSON path, or pbrt's parameter), before Embree sees it.
#include "scene_test_files.h"

#include "accel/embree_scene.h"
#include "scene/camera_check.h"
#include "scene/pbrt/pbrt_loader.h"

using namespace rayproc;
using namespace rayproc::test;

namespace {

std::string withCamera(const std::string& camera) {
    return R"({"camera": )" + camera + R"(, "materials": {"m": {"type": "diffuse"}},
               "nodes": [{"type": "sphere", "material": "m", "radius": 1}]})";
}

std::string pbrtWith(const std::string& lookAt, const std::string& lens) {
    return "LookAt " + lookAt + "  0 0 0  0 1 0\nCamera \"perspective\" " + lens +
           "\nWorldBegin\nShape \"sphere\"\n";
}

std::string pbrtErrorOf(const std::string& text) {
    try {
        loadPbrtSceneFromString(text, "camera.pbrt");
    } catch (const InputError& e) {
        return e.what();
    }
    FAIL("expected an InputError");
    return {};
}

} // namespace

TEST_CASE("JSON cameras outside Embree's range are refused, naming the field", "[scene]") {
    checkLoadError("cam-far.json", withCamera(R"({"position": [0, 0, 1e17]})"), "/camera/position",
                   "the camera is at a coordinate of 1e+17");
    // 1e16 itself rounds beyond 1e16 in float: the message shows by how much.
    checkLoadError("cam-edge.json", withCamera(R"({"position": [0, 0, 1e16]})"), "/camera/position",
                   "coordinate of 10000000272564224 (as a 32-bit float)");
    // These aborted render and serve inside Embree (status 134).
    checkLoadError("cam-aperture.json", withCamera(R"({"position": [0, 0, 5], "aperture": 1e19})"),
                   "/camera/aperture", "aperture (lens radius) of 1e+19");
    checkLoadError(
        "cam-focus.json",
        withCamera(R"({"position": [0, 0, 5], "aperture": 0.1, "focus_distance": 1e30})"),
        "/camera/focus_distance", "focus point");
    // Without focus_distance the lens focuses at look_at: 1e30 away is as far.
    checkLoadError(
        "cam-lookat.json",
        withCamera(R"({"position": [0, 0, 5], "look_at": [0, 0, -1e30], "aperture": 0.1})"),
        "/camera/focus_distance", "distance to look_at");
    checkLoadError("cam-parallel.json",
                   withCamera(R"({"position": [0, 5, 0], "look_at": [0, 0, 0], "up": [0, 2, 0]})"),
                   "/camera/up", "parallel");
    checkLoadError("cam-same.json", withCamera(R"({"position": [1, 2, 3], "look_at": [1, 2, 3]})"),
                   "/camera/look_at", "coincides");
    // In range: a far camera, a wide lens, a pinhole looking at a point 1e30 away.
    for (const char* fine :
         {R"({"position": [0, 0, 9e15]})", R"({"position": [0, 0, 5], "aperture": 1e15})",
          R"({"position": [0, 0, 5], "look_at": [0, 0, -1e30]})"}) {
        INFO(fine);
        auto scene = loadSceneFromString(withCamera(fine), "fine.json");
        CHECK_FALSE(cameraProblem(scene->camera));
        CHECK_NOTHROW(EmbreeScene(*scene));
    }
}

TEST_CASE("pbrt cameras outside Embree's range are refused, naming the parameter", "[pbrt]") {
    CHECK_THAT(pbrtErrorOf(pbrtWith("0 0 5", R"("float lensradius" [1e30])")),
               Catch::Contains("camera \"lensradius\"") && Catch::Contains("1e+30"));
    CHECK_THAT(
        pbrtErrorOf(pbrtWith("0 0 5", R"("float lensradius" [0.1] "float focaldistance" [1e35])")),
        Catch::Contains("camera \"focaldistance\""));
    CHECK_THAT(pbrtErrorOf(pbrtWith("0 0 1e17", "")),
               Catch::Contains("camera transform") && Catch::Contains("1e+17"));
    // Far but in range: look_at stays ahead of the eye in float (one unit ahead rounded onto
    // it beyond ~1e7, a zero-length view).
    auto far = loadPbrtSceneFromString(pbrtWith("0 0 1e9", ""), "far.pbrt");
    const Camera& c = far->camera;
    CHECK_FALSE(cameraProblem(c));
    CHECK(c.lookAt.z < c.position.z);
    CHECK(normalize(c.lookAt - c.position).z == Approx(-1.0f));
}

TEST_CASE("EmbreeScene refuses a camera built in code by the same check", "[scene]") {
    auto scene = loadSceneFromString(withCamera(R"({"position": [0, 0, 5]})"), "code.json");
    scene->camera.apertureRadius = 1e19f;
    try {
        EmbreeScene accel(*scene);
        FAIL("expected an InputError");
    } catch (const InputError& e) {
        CHECK_THAT(e.what(),
                   Catch::Contains("the scene cannot be rendered: the camera's aperture"));
    }
}
