// `rayproc render` on cameras outside Embree's range: a clear error naming the field and
// status 1, never Embree's abort (status 134), and no output file.
#include "test_util.h"

#include <filesystem>

using namespace rayproc;
using namespace rayproc::test;

TEST_CASE("render refuses cameras and lenses outside Embree's range, naming the field",
          "[cli][bad-input]") {
    TempDir dir, logs;
    auto json = [](const std::string& camera) {
        return R"({"camera": {"look_at": [0, 0, 0], "resolution": [16, 16], )" + camera +
               R"(}, "materials": {"m": {"type": "diffuse"}},
                   "lights": [{"type": "point", "position": [0, 0, 4], "intensity": [1, 1, 1]}],
                   "nodes": [{"type": "sphere", "material": "m", "radius": 1}]})";
    };
    struct Case {
        const char* name;
        std::string text;
        std::string message;
    };
    const std::vector<Case> cases = {
        {"far-camera.json", json(R"("position": [0, 0, 1e19])"),
         "/camera/position: the camera is at a coordinate of 1e+19"},
        {"aperture.json", json(R"("position": [0, 0, 5], "aperture": 1e19)"),
         "/camera/aperture: the camera's aperture (lens radius) of 1e+19"},
        {"lens.pbrt",
         "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float lensradius\" [1e30]\n"
         "Film \"rgb\" \"integer xresolution\" [16] \"integer yresolution\" [16]\nWorldBegin\n"
         "LightSource \"point\" \"point3 from\" [0 0 4]\nShape \"sphere\"\n",
         "camera \"lensradius\": the camera's aperture (lens radius) of 1e+30"},
    };
    for (const Case& c : cases) {
        INFO(c.name);
        std::string path = dir.file(c.name);
        writeText(path, c.text);
        RunResult r = runRayproc(
            {"render", path, "--mode", "path", "--spp", "2", "--quiet", "-o", dir.file("out.pfm")},
            logs);
        INFO(r.err);
        CHECK(r.status == 1);
        CHECK(r.err.find(c.message) != std::string::npos);
        CHECK_FALSE(std::filesystem::exists(dir.file("out.pfm")));
    }
}
