// Specular surfaces against light of known radiance:
//  - a mirror of reflectance c facing a constant sky L: c * L in every mode;
//  - a lossless glass slab (a closed box, ior n) between the camera and an emitter behind it,
//    with a second emitter where the slab's specular reflection goes, each in its own colour
//    channel, so one render gives the slab's reflectance R and transmittance T. A ray crossing
//    the slab loses F at each interface and the internally reflected part bounces on: summing
//    the bounces, T = (1 - F)^2 (1 + F^2 + F^4 + ...) = (1 - F) / (1 + F) and R = 2F / (1 + F),
//    with F = fresnelDielectric(cos theta, n) the same at both faces (the exit angle inside is
//    the refraction angle, and Fresnel reflectance is reciprocal). Raytrace splits every hit
//    Whitted-style and sums the bounces to its depth limit (8: F^16 is negligible); path mode
//    picks one lobe with probability F and must converge to the same. At normal incidence
//    F = ((n - 1) / (n + 1))^2.
//    Rayproc's Fresnel term is the unpolarised average, and so is the expected value: the
//    exact slab sums each polarisation separately (a 0.1% difference at 45 degrees).
//  - Preview's glass is an approximation by design (straight through, no bending, no internal
//    bounces, one reflection): at normal incidence it must give R = F and T = (1 - F)^2; at 45
//    degrees the physics does not apply (its unbent ray leaves the slab beyond the critical
//    angle), and it is not checked.
#include "analytic.h"

#include "kernels/bsdf.h"

using namespace rayproc;
using namespace rayproc::test;

namespace {

constexpr int kSize = 16;

// A glass box 10 x 10 x 1 rotated by `angle` degrees about y, in front of a camera looking down
// -z with a 2-degree field of view (ray directions within 1 degree of the axis). Emitters:
// behind the slab [0, 1, 0] (what is transmitted), where its reflection goes [1, 0, 0].
// `tint`: more keys of the glass, e.g. `, "color": [1, 0.5, 0.5]`; `textures`: a top-level
// textures entry, e.g. `"textures": {...},`.
std::string slabScene(float angle, float ior, const std::string& tint = "",
                      const std::string& textures = "") {
    // The reflection of the -z camera direction off a slab turned by `angle` about y.
    float a = angle * kPi / 180.0f;
    Vec3 n(std::sin(a), 0.0f, std::cos(a));
    Vec3 d(0.0f, 0.0f, -1.0f);
    Vec3 r = d - n * (2.0f * dot(d, n));
    Vec3 rc = r * 12.0f; // the reflection emitter's centre: beyond the camera at normal incidence
    std::string box = R"({"type": "group", "transform": {"rotate": {"angle": )" +
                      std::to_string(angle) + R"(, "axis": [0, 1, 0]}}, "children": [
        {"type": "rectangle", "material": "glass", "center": [0, 0, 0.5], "size": [10, 10], "normal": [0, 0, 1]},
        {"type": "rectangle", "material": "glass", "center": [0, 0, -0.5], "size": [10, 10], "normal": [0, 0, -1]},
        {"type": "rectangle", "material": "glass", "center": [5, 0, 0], "size": [1, 10], "normal": [1, 0, 0]},
        {"type": "rectangle", "material": "glass", "center": [-5, 0, 0], "size": [1, 10], "normal": [-1, 0, 0]},
        {"type": "rectangle", "material": "glass", "center": [0, 5, 0], "size": [10, 1], "normal": [0, 1, 0]},
        {"type": "rectangle", "material": "glass", "center": [0, -5, 0], "size": [10, 1], "normal": [0, -1, 0]}]})";
    return R"({"camera": {"position": [0, 0, 10], "look_at": [0, 0, 0], "fov": 2,
                          "resolution": [16, 16]},
               "materials": {"glass": {"type": "dielectric", "ior": )" +
           std::to_string(ior) + tint + R"(}}, )" + textures + R"(
               "nodes": [)" + box + R"(,
        {"type": "rectangle", "emission": [0, 1, 0], "center": [0, 0, -4], "size": [40, 40],
         "normal": [0, 0, 1]},
        {"type": "rectangle", "emission": [1, 0, 0], "center": )" +
           jsonVec(rc) + R"(, "size": [40, 40], "normal": )" + jsonVec(-r) + "}]}";
}

} // namespace

TEST_CASE("Mirror under a constant sky: c * L", "[analytic]") {
    const Vec3 c(0.9f, 0.5f, 0.25f), sky(0.8f, 0.6f, 1.0f);
    auto scene = sceneFromJson(R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0],
                                              "resolution": [16, 16]},
        "materials": {"mirror": {"type": "mirror", "color": )" + jsonVec(c) + R"(}},
        "lights": [{"type": "environment", "radiance": )" + jsonVec(sky) + R"(}],
        "nodes": [{"type": "rectangle", "material": "mirror", "size": [100, 100],
                   "normal": [0, 0.2, 1]}]})");
    EmbreeScene accel(*scene);
    for (const std::string mode : {"path", "raytrace", "preview"})
        checkMeanRadiance(renderMode(*scene, accel, mode, 4), c * sky, 1e-5, mode);
}

// The reflection stage samples rayproc's mirror and glossy through the BSDF kernels, as path
// mode does: their colour textures count there too (it once read the material's constant colour,
// the default grey under a texture, while light samples read the texture).
TEST_CASE("Textured mirror and glossy reflect in their texture's colour", "[analytic]") {
    const Vec3 c(0.9f, 0.5f, 0.25f), sky(0.8f, 0.6f, 1.0f);
    auto sceneWith = [&](const std::string& type, const std::string& color) {
        const std::string extra = type == "glossy" ? ", \"roughness\": 0.3" : "";
        return sceneFromJson(R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0],
                                            "resolution": [16, 16]},
            "textures": {"tint": {"type": "constant", "value": )" + jsonVec(c) + R"(}},
            "materials": {"m": {"type": ")" + type + "\"" + extra + R"(, "color": )" + color + R"(}},
            "lights": [{"type": "environment", "radiance": )" + jsonVec(sky) + R"(}],
            "nodes": [{"type": "rectangle", "material": "m", "size": [100, 100],
                       "normal": [0, 0.2, 1]}]})");
    };
    auto mirror = sceneWith("mirror", "\"tint\"");
    EmbreeScene mirrorAccel(*mirror);
    for (const std::string mode : {"path", "raytrace", "preview"})
        checkMeanRadiance(renderMode(*mirror, mirrorAccel, mode, 4), c * sky, 1e-5, mode);
    auto textured = sceneWith("glossy", "\"tint\""), constant = sceneWith("glossy", jsonVec(c));
    EmbreeScene texturedAccel(*textured), constantAccel(*constant);
    const Vec3 a = imageMean(renderMode(*textured, texturedAccel, "raytrace", 4));
    const Vec3 b = imageMean(renderMode(*constant, constantAccel, "raytrace", 4));
    for (int ch = 0; ch < 3; ++ch) {
        INFO("channel " << ch << ": textured " << a[ch] << ", constant " << b[ch]);
        CHECK(std::abs(a[ch] - b[ch]) <= 1e-6 * b[ch]);
    }
}

// The refraction stage takes the glass's tint from the BSDF kernels' parameters, textures
// evaluated, as path mode does (it read the material's constant colour: white under a texture).
TEST_CASE("A textured glass tint equals the same constant tint in raytrace", "[analytic]") {
    const std::string textures = R"("textures": {"tint": {"type": "constant", "value": [1, 0.3, 0.25]}},)";
    auto textured = sceneFromJson(slabScene(0.0f, 1.5f, R"(, "color": "tint")", textures));
    auto constant = sceneFromJson(slabScene(0.0f, 1.5f, R"(, "color": [1, 0.3, 0.25])"));
    auto clear = sceneFromJson(slabScene(0.0f, 1.5f));
    EmbreeScene texturedAccel(*textured), constantAccel(*constant), clearAccel(*clear);
    const Vec3 a = imageMean(renderMode(*textured, texturedAccel, "raytrace", 2));
    const Vec3 b = imageMean(renderMode(*constant, constantAccel, "raytrace", 2));
    const Vec3 c = imageMean(renderMode(*clear, clearAccel, "raytrace", 2));
    for (int ch = 0; ch < 3; ++ch) {
        INFO("channel " << ch << ": textured " << a[ch] << ", constant " << b[ch]);
        CHECK(std::abs(a[ch] - b[ch]) <= 1e-6 * std::max(b[ch], 1e-6f));
    }
    // The emitter behind the slab is green: what comes through is tinted by 0.3 on entering.
    CHECK(std::abs(b.y - 0.3f * c.y) <= 1e-4f * c.y);
}

TEST_CASE("Glass slab: R = 2F / (1 + F), T = (1 - F) / (1 + F)", "[analytic]") {
    // A diamond-like index: F = 0.17 at normal incidence, so the internal bounces matter
    // (F^2 = 3% of T, against 0.2% for n = 1.5) and R is large enough to measure in path mode
    // without millions of samples.
    const float ior = 2.4f;
    for (float angle : {0.0f, 45.0f}) {
        auto scene = sceneFromJson(slabScene(angle, ior));
        EmbreeScene accel(*scene);
        double f = kernels::fresnelDielectric(std::cos(angle * kPi / 180.0f), ior);
        Vec3 expected(float(2 * f / (1 + f)), float((1 - f) / (1 + f)), 0.0f);
        INFO("angle " << angle << ", F " << f);
        if (angle == 0.0f) CHECK(f == Approx(std::pow((ior - 1) / (ior + 1), 2)).epsilon(1e-5));
        // Raytrace is deterministic but for Russian roulette of the weak internal bounces.
        checkMeanRadiance(renderMode(*scene, accel, "raytrace", 64), expected, 0.01,
                          "raytrace angle " + std::to_string(angle));
        // Path mode's lobe choice is a coin flip per bounce: R is a Bernoulli fraction near
        // 0.3, with a per-sample relative deviation of sqrt((1 - R) / R) = 1.5; 256 pixels
        // x 2048 samples bring its standard error to about 0.2%.
        checkMeanRadiance(renderMode(*scene, accel, "path", 2048), expected, 0.01,
                          "path angle " + std::to_string(angle));
        if (angle == 0.0f)
            checkMeanRadiance(renderMode(*scene, accel, "preview", 1),
                              Vec3(float(f), float((1 - f) * (1 - f)), 0.0f), 1e-5, "preview");
    }
}
