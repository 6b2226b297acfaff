// A diffuse plane seen from straight above, lit by
//  - a constant sky of radiance L: every point reflects a * L (the plane sees only the sky,
//    the sky sees the plane from no direction that matters);
//  - a point light of intensity I at height h above the origin: L = a / pi * I cos / d^2
//    = a / pi * I h / (h^2 + r^2)^(3/2) at distance r from the foot of the light (inverse
//    square and Lambert's cosine). Nothing else is in the scene, so there is no indirect light
//    and every mode must give this.
// The point-light radiance varies across a pixel (by up to 5% here), so each pixel is compared
// with the closed form averaged over the pixel's footprint (a 32 x 32 midpoint rule: the box
// filter of the film), not with its value at the pixel centre.
#include "analytic.h"

using namespace rayproc;
using namespace rayproc::test;

namespace {

constexpr int kSize = 64;
constexpr double kCameraHeight = 3.0, kFovDegrees = 60.0;

std::string planeScene(const Vec3& albedo, const std::string& lights) {
    return R"({"camera": {"position": [0, 3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1],
                          "fov": 60, "resolution": [64, 64]},
               "materials": {"plane": {"type": "diffuse", "color": )" +
           jsonVec(albedo) + R"(}},
               "lights": )" + lights + R"(,
               "nodes": [{"type": "rectangle", "material": "plane", "size": [200, 200]}]})";
}

// The point-light radiance averaged over pixel (px, py): film position (fx, fy) looks at the
// plane point at r^2 = H^2 (sx^2 + sy^2) with sx, sy the pinhole's image-plane coordinates.
double pixelAverage(int px, int py, double albedo, double intensity, double h) {
    const double t = std::tan(0.5 * kFovDegrees * kPi / 180.0);
    const int n = 32;
    double sum = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            double fx = px + (i + 0.5) / n, fy = py + (j + 0.5) / n;
            double sx = (2.0 * fx / kSize - 1.0) * t, sy = (1.0 - 2.0 * fy / kSize) * t;
            double r2 = kCameraHeight * kCameraHeight * (sx * sx + sy * sy);
            sum += albedo / kPi * intensity * h / std::pow(h * h + r2, 1.5);
        }
    return sum / (n * n);
}

} // namespace

TEST_CASE("Diffuse plane under a constant sky: a * L", "[analytic]") {
    const Vec3 albedo(0.5f, 0.8f, 0.2f), sky(0.8f, 0.6f, 1.0f);
    auto scene = sceneFromJson(
        planeScene(albedo, R"([{"type": "environment", "radiance": )" + jsonVec(sky) + "}]"));
    REQUIRE(scene->camera.width == kSize);
    EmbreeScene accel(*scene);
    const Vec3 expected = albedo * sky;
    // Path mode's two MIS strategies have the same pdf (cosine), so each takes half and the
    // sum is exact; raytrace's cosine-weighted sky samples are exact; preview's ambient term
    // is a * L by definition.
    SECTION("path") { checkMeanRadiance(renderMode(*scene, accel, "path", 4), expected, 0.01, "path"); }
    SECTION("gi") {
        // Direct sky light by shadow rays; nothing else reaches an infinite plane (photons
        // from the sky land on it, but the gather rays all escape).
        checkMeanRadiance(renderGiMode(*scene, accel, 4).image, expected, kGiTolerance, "gi");
    }
    SECTION("raytrace") {
        checkMeanRadiance(renderMode(*scene, accel, "raytrace", 4), expected, 0.01, "raytrace");
    }
    SECTION("preview") {
        checkMeanRadiance(renderMode(*scene, accel, "preview", 1), expected, 1e-5, "preview");
    }
}

TEST_CASE("Point light over a diffuse plane: a/pi I cos / d^2 per pixel", "[analytic]") {
    const double albedo = 0.6, h = 1.0, intensity = 10.0;
    auto scene = sceneFromJson(planeScene(
        Vec3(float(albedo)),
        R"([{"type": "point", "position": [0, 1, 0], "intensity": [10, 10, 10]}])"));
    EmbreeScene accel(*scene);
    // The centre, a diagonal and an edge: d from 1 to 2.8, cos from 1 to 0.36, radiance over
    // a range of 25.
    const int pixels[][2] = {{32, 32}, {31, 31}, {40, 24}, {48, 48}, {56, 8}, {63, 63},
                             {0, 0},   {0, 32},  {63, 40}, {16, 60}};
    // 64 stratified samples per pixel in every mode (preview accepts --spp too): with one
    // sample the jittered position alone would move a pixel by up to 2.5%. The 8 x 8 jittered
    // grid integrates the pixel to ~0.1% (measured worst case below).
    for (const std::string mode : {"path", "raytrace", "preview"}) {
        Image img = renderMode(*scene, accel, mode, 64);
        double worst = 0;
        for (auto& p : pixels) {
            double expected = pixelAverage(p[0], p[1], albedo, intensity, h);
            double v = img.at(p[0], p[1])[0];
            worst = std::max(worst, std::abs(v / expected - 1.0));
            INFO(mode << " pixel (" << p[0] << ", " << p[1] << "): " << v << " expected "
                      << expected);
            CHECK(v == Approx(expected).epsilon(0.005));
        }
        INFO(mode << ": worst relative error " << worst);
        CHECK(worst < 0.005);
    }
}
