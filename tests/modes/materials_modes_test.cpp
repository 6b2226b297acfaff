// Every material type in every mode: the stages each mode routes a material to exist (the scene
// analysis must not skip a stage a material needs: a check would fail), every pixel is finite,
// no sample is discarded as NaN, and each material shows up (its region is not black).
#include "analytic/analytic.h"
#include "test_util.h"

#include <catch2/catch.hpp>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// A row of spheres, one per material, on a diffuse floor under a quad light and a sky.
std::string materialsScene() {
    return R"({
      "camera": {"position": [0, 2, 9], "look_at": [0, 0.6, 0], "fov": 40, "resolution": [64, 32]},
      "materials": {
        "floor": {"type": "diffuse", "color": [0.6, 0.6, 0.6]},
        "metal": {"type": "conductor", "metal": "Au"},
        "brushed": {"type": "conductor", "metal": "Al", "u_roughness": 0.05, "v_roughness": 0.3,
                    "remap_roughness": false},
        "coated": {"type": "coateddiffuse", "color": [0.7, 0.2, 0.1], "roughness": 0.05},
        "frosted": {"type": "dielectric", "roughness": 0.1},
        "thin": {"type": "thindielectric"},
        "paper": {"type": "diffusetransmission", "color": [0.5, 0.5, 0.5],
                  "transmittance": [0.4, 0.4, 0.4]},
        "mixed": {"type": "mix", "materials": ["coated", "metal"], "amount": 0.5}},
      "lights": [{"type": "environment", "radiance": [0.2, 0.25, 0.3]}],
      "nodes": [
        {"type": "quad", "material": "floor",
         "corners": [[-8, 0, -8], [-8, 0, 8], [8, 0, 8], [8, 0, -8]]},
        {"type": "quad", "emission": [8, 8, 8],
         "corners": [[-1, 5, -1], [1, 5, -1], [1, 5, 1], [-1, 5, 1]]},
        {"type": "sphere", "material": "metal", "center": [-4.2, 0.6, 0], "radius": 0.55},
        {"type": "sphere", "material": "brushed", "center": [-3, 0.6, 0], "radius": 0.55},
        {"type": "sphere", "material": "coated", "center": [-1.8, 0.6, 0], "radius": 0.55},
        {"type": "sphere", "material": "frosted", "center": [-0.6, 0.6, 0], "radius": 0.55},
        {"type": "sphere", "material": "thin", "center": [0.6, 0.6, 0], "radius": 0.55},
        {"type": "sphere", "material": "paper", "center": [1.8, 0.6, 0], "radius": 0.55},
        {"type": "sphere", "material": "mixed", "center": [3, 0.6, 0], "radius": 0.55}]})";
}

} // namespace

TEST_CASE("Every material renders in every mode: finite, no NaN samples, not black", "[modes][materials]") {
    auto scene = sceneFromJson(materialsScene());
    EmbreeScene accel(*scene);
    for (const char* mode : {"preview", "raytrace", "gi", "path"}) {
        RenderOptions o;
        o.mode = mode;
        o.spp = 4;
        RenderResult r = std::string(mode) == "gi" ? renderGiMode(*scene, accel, 4)
                                                   : render(*scene, accel, o);
        INFO("mode " << mode);
        CHECK(allFinite(r.image));
        CHECK(r.stats.totals.invalidSamples == 0);
        // Each sphere's centre pixels see its material: some light comes back from each. The
        // spheres lie on the view axis' plane at depth |(0, -1.4, -9)| = 9.108, where the
        // image's half width is tan(20 deg) * 9.108 * 2 = 6.63.
        for (float x : {-4.2f, -3.0f, -1.8f, -0.6f, 0.6f, 1.8f, 3.0f}) {
            int px = int(std::floor(32 + 32 * x / 6.63f));
            float sum = 0;
            for (int dy = 15; dy <= 16; ++dy)
                for (int dx = 0; dx <= 1; ++dx) {
                    const float* p = r.image.at(std::clamp(px + dx, 0, 63), dy);
                    sum += p[0] + p[1] + p[2];
                }
            INFO("sphere at x = " << x);
            CHECK(sum > 0);
        }
    }
}
