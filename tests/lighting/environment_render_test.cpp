// Image skies through the renderer (path mode): a diffuse sphere under a constant image sky
// matches the constant sky (a L on the sphere), and a single bright pixel (a "sun") gives the
// analytic irradiance E = L * (4 pi / N) * cos(theta) on a plane: radiance a / pi * E.
#include "analytic/analytic.h"
#include "image/image.h"
#include "lighting/sphere_mapping.h"

#include <filesystem>
#include <unistd.h>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// A per-process folder, removed at exit.
struct TempFolder {
    std::filesystem::path path;
    explicit TempFolder(const std::string& name)
        : path(std::filesystem::temp_directory_path() / (name + std::to_string(::getpid()))) {
        std::filesystem::create_directories(path);
    }
    ~TempFolder() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
};

std::string tempImage(const std::string& name, const Image& img) {
    static TempFolder folder("rayproc-lights-tests-");
    const std::filesystem::path& dir = folder.path;
    std::string path = (dir / name).string();
    writeImage(path, img);
    return path;
}

// A sphere of albedo `a` filling the view, lit by `sky` (a JSON light).
std::string sphereUnderSky(const Vec3& a, const std::string& sky) {
    return R"({"camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov": 20,
                          "resolution": [16, 16]},
               "materials": {"m": {"type": "diffuse", "color": )" + jsonVec(a) + R"(}},
               "lights": [)" + sky + R"(],
               "nodes": [{"type": "sphere", "material": "m", "radius": 1}]})";
}

// A plane z = 0 of albedo 0.5 seen from above, lit by the image sky at `path` alone.
std::unique_ptr<Scene> planeUnderSky(const std::string& path) {
    return sceneFromJson(
        R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 20,
                       "resolution": [16, 16]},
            "materials": {"m": {"type": "diffuse", "color": [0.5, 0.5, 0.5]}},
            "lights": [{"type": "environment", "image": ")" + path + R"("}],
            "nodes": [{"type": "quad", "material": "m",
                       "corners": [[-50, -50, 0], [50, -50, 0], [50, 50, 0], [-50, 50, 0]]}]})");
}

} // namespace

TEST_CASE("A diffuse sphere under a constant image sky renders as under the constant sky",
          "[lights]") {
    const Vec3 albedo(0.5f, 0.8f, 0.2f);
    const float L = 1.5f;
    Image flat(8, 8);
    for (float& v : flat.pixels) v = 1.0f;
    std::string path = tempImage("flat.pfm", flat);
    // A convex object sees only sky: irradiance pi L everywhere, radiance a L.
    Vec3 expected = albedo * L;
    for (std::string sky : {std::string(R"({"type": "environment", "radiance": [1.5, 1.5, 1.5]})"),
                            R"({"type": "environment", "image": ")" + path +
                                R"(", "scale": 1.5, "transform": {"rotate": {"angle": 40, "axis": [0, 1, 0]}}})"}) {
        auto scene = sceneFromJson(sphereUnderSky(albedo, sky));
        EmbreeScene accel(*scene);
        checkMeanRadiance(renderMode(*scene, accel, "path", 64), expected, 0.01, "path " + sky);
        checkMeanRadiance(renderMode(*scene, accel, "raytrace", 256), expected, 0.01,
                          "raytrace " + sky);
        // 128 spp: gi's 2 light samples (its default) leave the mean's standard error at 0.6%
        // at 64 spp, above the quarter of the tolerance that makes the check meaningful.
        checkMeanRadiance(renderGiMode(*scene, accel, 128).image, expected, kGiTolerance,
                          "gi " + sky);
    }
}

TEST_CASE("One bright pixel of an image sky lights a plane with E = L * 4pi/N * cos", "[lights]") {
    const int res = 32;
    const int sx = 13, sy = 18; // the "sun" pixel
    const float sun = 5000.0f, albedo = 0.5f;
    Image sky(res, res);
    float* p = sky.at(sx, sy);
    p[0] = p[1] = p[2] = sun;
    std::string path = tempImage("sun.pfm", sky);
    Vec3 d = equalAreaSquareToSphere({(sx + 0.5f) / res, (sy + 0.5f) / res});
    REQUIRE(d.z > 0.3f); // above the plane z = 0 (light space = world space)
    double E = sun * (4 * kPi / (res * res)) * d.z;
    double expected = albedo / kPi * E;
    auto scene = planeUnderSky(path);
    EmbreeScene accel(*scene);
    Image img = renderMode(*scene, accel, "path", 16);
    INFO("analytic radiance " << expected << " (sun direction z " << d.z << ")");
    checkMeanRadiance(img, Vec3(float(expected)), 0.02, "sun");
}

// Path mode's light samples of an image sky go only where it is brighter than its mean (MIS
// compensation), its BSDF samples see the rest: together they must still give a plane under a
// varied sky its irradiance, integrated here over the hemisphere from the sky's radiance.
TEST_CASE("A plane under a varied image sky gets the irradiance the sky gives it", "[lights]") {
    const int res = 16;
    Image sky(res, res);
    for (int y = 0; y < res; ++y)
        for (int x = 0; x < res; ++x) {
            float* p = sky.at(x, y);
            p[0] = 0.2f + 0.15f * float((x * 7 + y * 3) % 11);
            p[1] = 0.1f + 0.1f * float((x + 2 * y) % 5);
            p[2] = 0.5f + 0.05f * float(y);
        }
    sky.at(4, 9)[0] = 60.0f; // a sun, above the plane
    std::string path = tempImage("varied.pfm", sky);
    auto scene = planeUnderSky(path);
    EmbreeScene accel(*scene);
    // E = integral over the upper hemisphere of L cos theta: a fine (cos theta, phi) midpoint
    // rule over the sky's own lookup.
    EnvironmentLight env;
    for (const Light& l : scene->lights) env.add(l);
    Vec3 E(0.0f);
    const int n = 600;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < 4 * n; ++i) {
            const double z = (j + 0.5) / n, phi = (i + 0.5) * 2 * kPi / (4 * n);
            const double r = std::sqrt(1 - z * z);
            Vec3 L = env.radiance({float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)});
            E += L * float(z * (1.0 / n) * (2 * kPi / (4 * n)));
        }
    Vec3 expected = E * float(0.5 / kPi);
    INFO("analytic radiance " << expected.x << " " << expected.y << " " << expected.z);
    checkMeanRadiance(renderMode(*scene, accel, "path", 256), expected, 0.01, "path");
}
