// raytrace's (and gi's) multiple importance sampling of the rest of a BSDF, the part no
// reflection ray samples (ShadingPolicy::diffuseMis): area-light samples and one cosine-sampled
// ray that collects only emission share it by the power heuristic. A plane with a light standing
// on it has no indirect light (the light's back is black), so raytrace's expectation is exactly
// path mode's: with MIS on or off the means must agree with path's, and MIS must remove the
// fireflies of floor points in front of the light's lower edge, where a light sample near that
// edge has a huge 1 / distance^2.
#include "test_util.h"

#include <catch2/catch.hpp>

#include <algorithm>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// A 4x4 plane of `material` seen obliquely, a 0.6x0.6 light standing on it (its lower edge
// 0.005 above it) facing the camera.
std::string lowLightScene(const std::string& material) {
    return R"({
      "camera": {"position": [0, 1.5, 3], "look_at": [0, 0, -0.5], "fov": 40, "resolution": [24, 24]},
      "materials": {"m": )" + material + R"(},
      "nodes": [
        {"type": "quad", "material": "m",
         "corners": [[-2, 0, -2], [-2, 0, 2], [2, 0, 2], [2, 0, -2]]},
        {"type": "quad", "emission": [4, 4, 4],
         "corners": [[-0.3, 0.005, -0.5], [0.3, 0.005, -0.5], [0.3, 0.605, -0.5], [-0.3, 0.605, -0.5]]}]})";
}

Image renderWith(const Scene& scene, const EmbreeScene& accel, const char* mode, int spp,
                 bool mis, std::uint64_t seed = 1) {
    RenderOptions o;
    o.mode = mode;
    o.spp = spp;
    o.seed = seed;
    o.diffuseMis = mis;
    return render(scene, accel, o).image;
}

// The largest per-value error (a - b)^2 / (b^2 + 0.01): a firefly's.
double worstError(const Image& a, const Image& b) {
    double worst = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        double d = double(a.pixels[i]) - double(b.pixels[i]);
        worst = std::max(worst, d * d / (double(b.pixels[i]) * b.pixels[i] + 0.01));
    }
    return worst;
}

} // namespace

TEST_CASE("Diffuse MIS: raytrace agrees with path on a plane lit by a light standing on it, MIS on and off",
          "[modes][mis]") {
    const char* materials[] = {
        R"({"type": "diffuse", "color": [0.7, 0.5, 0.3]})",
        R"({"type": "coateddiffuse", "color": [0.6, 0.3, 0.1], "roughness": 0.1, "remap_roughness": false})",
    };
    for (const char* material : materials) {
        auto scene = sceneFromJson(lowLightScene(material));
        EmbreeScene accel(*scene);
        Vec3 path = imageMean(renderWith(*scene, accel, "path", 1024, true));
        Vec3 on = imageMean(renderWith(*scene, accel, "raytrace", 512, true));
        Vec3 off = imageMean(renderWith(*scene, accel, "raytrace", 512, false));
        for (int c = 0; c < 3; ++c) {
            INFO(material << " channel " << c << ": path " << path[c] << " MIS " << on[c]
                          << " light samples only " << off[c]);
            CHECK(on[c] == Approx(path[c]).epsilon(0.02));
            CHECK(off[c] == Approx(path[c]).epsilon(0.05));
        }
    }
}

TEST_CASE("Diffuse MIS: no fireflies at a light's edge, a lower error at equal samples",
          "[modes][mis]") {
    // Over eight seeds: one render's error is decided by a few pixels (a floor firefly without
    // MIS, or a pixel at the light's foot whose 16 camera samples are far from its mean with
    // either), so a single seed can go either way. Measured (seeds 1-8, 16 spp): relMSE summed
    // 0.0132 with MIS, 0.0215 without; worst value 0.59 / 1.59, with independent light samples;
    // since they are Sobol points over the pixel's samples (engine/sample_numbers.h, stop 42)
    // light samples alone land near the edge less unevenly: 0.0108 with MIS, 0.0132 without,
    // worst 0.59 / 1.13. The bars keep MIS's margin on both (a broken weight brings the
    // fireflies back: worst > 1).
    auto scene = sceneFromJson(lowLightScene(R"({"type": "diffuse", "color": [0.7, 0.7, 0.7]})"));
    EmbreeScene accel(*scene);
    Image reference = renderWith(*scene, accel, "path", 4096, true, 7);
    double errOn = 0, errOff = 0, worstOn = 0, worstOff = 0;
    for (std::uint64_t seed = 1; seed <= 8; ++seed) {
        Image on = renderWith(*scene, accel, "raytrace", 16, true, seed);
        Image off = renderWith(*scene, accel, "raytrace", 16, false, seed);
        errOn += relMse(on, reference);
        errOff += relMse(off, reference);
        worstOn = std::max(worstOn, worstError(on, reference));
        worstOff = std::max(worstOff, worstError(off, reference));
    }
    INFO("relMSE summed over seeds with MIS " << errOn << ", light samples only " << errOff
                                              << "; worst value " << worstOn << " / " << worstOff);
    CHECK(errOn < 0.9 * errOff);
    CHECK(worstOn < 0.6 * worstOff);
}
