// Choosing among several area lights (ShadingPolicy::lightChoice, LightSet::areaSampler): a
// shading point takes lightSamples samples per light that matters there, each picking a light
// by its power over its squared distance. Unbiased, so raytrace's mean must not move (a single
// lit plane has no indirect light: raytrace's expectation is path mode's), the glossy MIS
// weights must still sum to one, and along a row of lights it must buy accuracy per shadow ray.
#include "test_util.h"

#include "engine/stats.h"
#include "image/metrics.h"
#include "lighting/light_set.h"

#include <catch2/catch.hpp>

#include <sstream>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// A 1 x 1 quad light facing down (one-sided) centred at (x, height, z).
std::string downLight(float x, float height, float z, float emission) {
    std::ostringstream o;
    o << R"(, {"type": "quad", "emission": [)" << emission << ", " << emission << ", " << emission
      << R"(], "corners": [[)" << x - 0.5f << ", " << height << ", " << z - 0.5f << "], ["
      << x + 0.5f << ", " << height << ", " << z - 0.5f << "], [" << x + 0.5f << ", " << height
      << ", " << z + 0.5f << "], [" << x - 0.5f << ", " << height << ", " << z + 0.5f << "]]}";
    return o.str();
}

// A floor of `material` from x = -width/2 to width/2 (z in [-2, 2]) seen from above, under
// the given lights (JSON nodes, each starting with a comma).
std::string floorScene(const std::string& material, float width, const std::string& lights,
                       int resolution) {
    std::ostringstream o;
    float h = 0.5f * width;
    o << R"({"camera": {"position": [0, )" << 0.9f * width << R"(, 0.01], "look_at": [0, 0, 0],
             "fov": 60, "resolution": [)" << resolution << ", " << resolution << R"(]},
          "materials": {"m": )" << material << R"(},
          "nodes": [{"type": "quad", "material": "m",
                     "corners": [[)" << -h << ", 0, -2], [" << -h << ", 0, 2], [" << h << ", 0, 2], ["
      << h << ", 0, -2]]}" << lights << "]}";
    return o.str();
}

RenderResult renderWith(const Scene& scene, const EmbreeScene& accel, const char* mode, int spp,
                        bool choice) {
    RenderOptions o;
    o.mode = mode;
    o.spp = spp;
    o.lightChoice = choice;
    return render(scene, accel, o);
}

std::uint64_t shadowRays(const RenderResult& r) {
    return r.stats.totals.stages[int(StageId::Shadow)].raysOut;
}

} // namespace

TEST_CASE("Light choice: selection weights, the lights that matter, and lights facing away",
          "[modes][lights]") {
    // Two lights over a floor and one above it facing up: that one cannot light the floor.
    auto scene = sceneFromJson(floorScene(R"({"type": "diffuse", "color": [0.5, 0.5, 0.5]})", 4,
                                          downLight(-1, 1, 0, 4) + downLight(1, 1, 0, 4) +
                                              R"(, {"type": "quad", "emission": [9, 9, 9], "corners": [[-0.5, 2, -0.5], [-0.5, 2, 0.5], [0.5, 2, 0.5], [0.5, 2, -0.5]]})",
                                          8));
    EmbreeScene accel(*scene);
    LightSet lights = LightSet::build(*scene, accel);
    REQUIRE(lights.lights.size() == 3);
    REQUIRE(lights.choosesAreaLights());
    Vec3 onFloor(-1, 0, 0), above(0, 3, 0);
    std::size_t up = 0;
    for (std::size_t i = 0; i < 3; ++i)
        if (lights.lights[i].boundCenter.y > 1.5f) up = i;
    CHECK(lights.lights[up].selectionWeight(onFloor) == 0.0f);
    CHECK(lights.lights[up].selectionWeight(above) > 0.0f);
    // The nearer of the two down-facing lights weighs more; together about 1.x lights matter.
    CHECK(lights.areaSampler.pmf(onFloor, up) == 0.0f);
    int samples = lights.areaSamples(onFloor, 4);
    CHECK(samples >= 4);
    CHECK(samples < 8);
    LightSet::Choice c = lights.choiceAt(up, onFloor, 4);
    CHECK(c.probability == 0.0f);
    // A two-sided light lights both sides.
    LightSource twoSided = lights.lights[up];
    twoSided.twoSided = true;
    twoSided.bounds = twoSided.makeBounds(1.0);
    CHECK(twoSided.selectionWeight(onFloor) > 0.0f);
}

TEST_CASE("Light choice: raytrace agrees with path and with sampling every light, diffuse and glossy",
          "[modes][lights][mis]") {
    // Five lights of different power along the floor, one facing away (up).
    std::string lights = downLight(-3, 1, 0, 2) + downLight(-1.5f, 1.5f, 1, 8) +
                         downLight(0, 0.8f, -1, 1) + downLight(2, 1, 0.5f, 4) +
                         R"(, {"type": "quad", "emission": [20, 20, 20], "corners": [[2.5, 2, -0.5], [2.5, 2, 0.5], [3.5, 2, 0.5], [3.5, 2, -0.5]]})";
    const char* materials[] = {
        R"({"type": "diffuse", "color": [0.5, 0.5, 0.5]})",
        R"({"type": "conductor", "metal": "Ag", "roughness": 0.15, "remap_roughness": false})",
    };
    for (const char* material : materials) {
        auto scene = sceneFromJson(floorScene(material, 8, lights, 24));
        EmbreeScene accel(*scene);
        Vec3 path = imageMean(renderWith(*scene, accel, "path", 1024, true).image);
        Vec3 on = imageMean(renderWith(*scene, accel, "raytrace", 256, true).image);
        Vec3 off = imageMean(renderWith(*scene, accel, "raytrace", 256, false).image);
        for (int c = 0; c < 3; ++c) {
            INFO(material << " channel " << c << ": path " << path[c] << " light choice " << on[c]
                          << " every light " << off[c]);
            CHECK(on[c] == Approx(path[c]).epsilon(0.02));
            CHECK(on[c] == Approx(off[c]).epsilon(0.01));
        }
    }
}

TEST_CASE("Light choice: along a row of lights it costs fewer shadow rays per unit of accuracy",
          "[modes][lights]") {
    // Twelve equal lights over a long floor: at any point two or three matter. Sampling every
    // light spends 48 shadow rays per hit; choosing spends about n per light that matters.
    // Measured (24x24, 16 spp): see the INFO line.
    std::string lights;
    for (int k = 0; k < 12; ++k) lights += downLight(-11.0f + 2.0f * float(k), 0.6f, 0, 3);
    auto scene = sceneFromJson(floorScene(R"({"type": "diffuse", "color": [0.5, 0.5, 0.5]})", 24,
                                          lights, 24));
    EmbreeScene accel(*scene);
    Image reference = renderWith(*scene, accel, "raytrace", 512, false).image;
    RenderResult on = renderWith(*scene, accel, "raytrace", 16, true);
    RenderResult off = renderWith(*scene, accel, "raytrace", 16, false);
    double errOn = compareImages(on.image, reference).relmse;
    double errOff = compareImages(off.image, reference).relmse;
    INFO("relMSE at 16 spp: choice " << errOn << " (" << shadowRays(on) << " shadow rays), every "
                                     << "light " << errOff << " (" << shadowRays(off) << ")");
    CHECK(shadowRays(on) * 3 < shadowRays(off));
    // Error times rays (variance per unit of work) at least 2x lower.
    CHECK(errOn * double(shadowRays(on)) < 0.5 * errOff * double(shadowRays(off)));
}

TEST_CASE("Light choice: path mode's hierarchy of many lights agrees with sampling every light",
          "[modes][lights][mis]") {
    // 20 lights of different power over a floor, more than LightSampler weighs one by one:
    // path mode descends the hierarchy for its light sample and takes the same probability for
    // the MIS weight of a BSDF ray that finds a light; raytrace without choice samples each.
    std::string lights;
    for (int k = 0; k < 20; ++k)
        lights += downLight(-4.75f + 0.5f * float(k), 0.6f + 0.1f * float(k % 3), float(k % 2) - 0.5f,
                            1.0f + float(k % 5));
    const char* materials[] = {
        R"({"type": "diffuse", "color": [0.5, 0.5, 0.5]})",
        R"({"type": "conductor", "metal": "Ag", "roughness": 0.2, "remap_roughness": false})",
    };
    for (const char* material : materials) {
        auto scene = sceneFromJson(floorScene(material, 10, lights, 16));
        EmbreeScene accel(*scene);
        LightSet set = LightSet::build(*scene, accel);
        REQUIRE(set.sampler.usesHierarchy());
        // The conductor measured at 8192 / 2048 spp: within 0.3% in every channel.
        Vec3 path = imageMean(renderWith(*scene, accel, "path", 2048, true).image);
        Vec3 every = imageMean(renderWith(*scene, accel, "raytrace", 256, false).image);
        for (int c = 0; c < 3; ++c) {
            INFO(material << " channel " << c << ": path " << path[c] << " every light " << every[c]);
            CHECK(path[c] == Approx(every[c]).epsilon(0.02));
        }
    }
}
