// Renders with pbrt-v4's coatedconductor:
//  - a smooth coat (index n) over a lossless smooth mirror (k = 1000), an absorbing slab of
//    optical thickness t between, facing a constant sky L at angle theta: every pixel is
//    L (R + (1 - R)^2 a / (1 - R a)), R = Fresnel(theta, n), a = exp(-2 t / cos theta_t) (the
//    slab's closed form: each round trip inside meets the coat again at theta_t). The surface
//    is all delta, so path and raytrace follow its sampled walk;
//  - the Cornell box with rough coated conductors in every mode: finite, non-negative images.
#include "analytic.h"

#include "kernels/bsdf.h"

#include <cmath>

using namespace rayproc;
using namespace rayproc::test;

TEST_CASE("Coated mirror under a constant sky: the slab's closed form",
          "[analytic][coated-conductor]") {
    const Vec3 sky(0.8f, 0.6f, 1.0f);
    const float n = 1.5f, t = 0.2f;
    // The plane's normal at 40 degrees from the view axis.
    const float theta = 40.0f * kPi / 180.0f;
    Vec3 normal(0.0f, std::sin(theta), std::cos(theta));
    auto scene = sceneFromJson(R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0],
                                              "fov": 2, "resolution": [16, 16]},
        "materials": {"coated": {"type": "coatedconductor", "eta": [1, 1, 1],
                                 "k": [1000, 1000, 1000], "ior": 1.5, "thickness": 0.2,
                                 "max_depth": 200}},
        "lights": [{"type": "environment", "radiance": )" + jsonVec(sky) + R"(}],
        "nodes": [{"type": "rectangle", "material": "coated", "size": [100, 100],
                   "normal": )" + jsonVec(normal) + "}]}");
    double r = kernels::fresnelDielectric(std::cos(theta), n);
    double sinT = std::sin(theta) / n, cosT = std::sqrt(1 - sinT * sinT);
    double a = std::exp(-2.0 * t / cosT);
    double albedo = r + (1 - r) * (1 - r) * a / (1 - r * a);
    INFO("closed form albedo " << albedo);
    EmbreeScene accel(*scene);
    for (const std::string mode : {"path", "raytrace"})
        checkMeanRadiance(renderMode(*scene, accel, mode, 64), sky * float(albedo), 0.01, mode);
}

TEST_CASE("Coated conductors in the Cornell box render in every mode",
          "[coated-conductor][modes]") {
    auto scene = loadSceneAt("cornell-spheres", 24, 24);
    for (Material& m : scene->materials) {
        if (m.type != MaterialType::Mirror && m.type != MaterialType::Dielectric) continue;
        const bool mirror = m.type == MaterialType::Mirror;
        m.type = MaterialType::CoatedConductor;
        m.uRoughness = m.vRoughness = FloatParam{mirror ? 0.0f : 0.05f};
        m.conductorURoughness = m.conductorVRoughness = FloatParam{0.1f};
        m.albedo = ColorParam{mirror ? Vec3(0.0f) : Vec3(0.6f, 0.5f, 0.3f)};
        m.thickness = FloatParam{0.05f};
    }
    EmbreeScene accel(*scene);
    for (const std::string mode : {"path", "raytrace", "gi", "preview"}) {
        Image img = mode == "gi" ? renderGiMode(*scene, accel, 2).image
                                 : renderMode(*scene, accel, mode, 8);
        int bad = 0;
        for (float v : img.pixels) bad += !(std::isfinite(v) && v >= 0);
        Vec3 mean = imageMean(img);
        INFO(mode << ": " << bad << " bad values, mean " << mean.x << " " << mean.y << " "
                  << mean.z);
        CHECK(bad == 0);
        CHECK(mean.x > 0.01f);
    }
}
