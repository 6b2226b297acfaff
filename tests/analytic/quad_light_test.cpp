// A one-sided square light of radiance Le and half-size s, horizontal at height hl and facing
// down, over a diffuse floor of albedo a_f (the square [-1, 1]^2 at y = 0).
//  - Direct light: the floor's irradiance is Lambert's polygon formula,
//    E(x) = Le / 2 * sum over the light's edges of (angle subtended by the edge) * (n . unit
//    normal of the plane through x and the edge), and its radiance a_f / pi * E(x). The camera
//    looks straight down at x ~ 0.9, where the far half of the light is seen at more than 45
//    degrees from the vertical: shadow rays there used to be occluded by the light itself (the
//    offset origin kept the unoffset direction and met the light's plane before the ray's end).
//  - Two bounces: a diffuse ceiling of albedo a_c at y = hc, facing down, seen from between
//    the light and the ceiling. The light lights the ceiling only through the floor:
//    L(c) = a_c / pi * integral over the floor of a_f / pi * E(x) * cos_x cos_c / r^2 * V(x, c),
//    with cos_x = cos_c = hc / r; V = 0 where the segment x-c crosses the light's square, an
//    axis-aligned square of the floor for each c, so the floor splits into at most 8 visible
//    rectangles where the integrand is smooth: Gauss-Legendre (8 x 8 nodes) per rectangle is
//    exact to 1e-6 (16 x 16 nodes and 2 x 2 sub-rectangles change nothing at that digit).
//    With --max-depth 1 path mode has exactly these paths (camera -> ceiling -> floor -> light
//    by light sampling at the last vertex, which takes the whole weight there: no BSDF ray
//    follows it); with --max-depth 2 also the BSDF-sampled floor -> light share (the depth-2
//    vertex is the ceiling, which no light sample reaches, or the black back of the light).
// Every pixel value is compared on the image mean; the geometry is symmetric about the
// camera's axis in both modes' pixel orientation (mean over a footprint symmetric about it),
// so the check does not depend on how the image is oriented.
#include "analytic.h"
#include "scene/pbrt/pbrt_transform.h"

#include <algorithm>
#include <array>
#include <vector>

using namespace rayproc;
using namespace rayproc::test;
using rayproc::pbrt::Vec3d; // double precision for the reference integrals

namespace {

constexpr double kPiD = 3.14159265358979323846;

struct QuadLightSetup {
    double height;     // hl
    double halfSize;   // s
    double radiance;   // Le (grey)
};

// Irradiance at floor point (x, 0, z) (normal +y) from the horizontal square light, which lies
// wholly above the floor: Lambert's formula, no clipping needed.
double polygonIrradiance(const QuadLightSetup& l, double x, double z) {
    const double s = l.halfSize;
    const std::array<std::array<double, 2>, 4> q{{{-s, -s}, {s, -s}, {s, s}, {-s, s}}};
    double sum = 0;
    for (int i = 0; i < 4; ++i) {
        const auto& a2 = q[std::size_t(i)];
        const auto& b2 = q[std::size_t((i + 1) % 4)];
        Vec3d a{a2[0] - x, l.height, a2[1] - z}, b{b2[0] - x, l.height, b2[1] - z};
        Vec3d c = cross(a, b);
        double cosAngle = std::clamp(dot(a, b) / (length(a) * length(b)), -1.0, 1.0);
        sum += std::acos(cosAngle) * c.y / length(c);
    }
    return l.radiance * 0.5 * std::abs(sum);
}

// Gauss-Legendre nodes and weights on [-1, 1] (Newton on the Legendre recurrence).
void gaussLegendre(int n, std::vector<double>& nodes, std::vector<double>& weights) {
    nodes.resize(std::size_t(n));
    weights.resize(std::size_t(n));
    for (int i = 0; i < n; ++i) {
        double z = std::cos(kPiD * (i + 0.75) / (n + 0.5)), dp = 1;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1, p1 = z;
            for (int k = 2; k <= n; ++k) {
                double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1);
            double dz = p1 / dp;
            z -= dz;
            if (std::abs(dz) < 1e-15) break;
        }
        nodes[std::size_t(i)] = z;
        weights[std::size_t(i)] = 2 / ((1 - z * z) * dp * dp);
    }
}

// Two-bounce radiance at ceiling point (cx, hc, cz) per unit albedos (a_f = a_c = 1).
double twoBounce(const QuadLightSetup& l, double hc, double cx, double cz,
                 const std::vector<double>& nodes, const std::vector<double>& weights) {
    // The segment from floor point x to c crosses y = hl at x + (c - x) f: blocked where that
    // lies in the light's square, i.e. x in [(-s - c f) / (1 - f), (s - c f) / (1 - f)]^2.
    const double f = l.height / hc, s = l.halfSize;
    const double blocked[2][2] = {{(-s - cx * f) / (1 - f), (s - cx * f) / (1 - f)},
                                  {(-s - cz * f) / (1 - f), (s - cz * f) / (1 - f)}};
    std::vector<double> cuts[2];
    for (int a = 0; a < 2; ++a) {
        cuts[a] = {-1.0};
        for (double v : blocked[a])
            if (v > -1 && v < 1) cuts[a].push_back(v);
        cuts[a].push_back(1.0);
    }
    double sum = 0;
    for (std::size_t i = 0; i + 1 < cuts[0].size(); ++i)
        for (std::size_t j = 0; j + 1 < cuts[1].size(); ++j) {
            double x0 = cuts[0][i], x1 = cuts[0][i + 1], z0 = cuts[1][j], z1 = cuts[1][j + 1];
            double mx = 0.5 * (x0 + x1), mz = 0.5 * (z0 + z1);
            if (mx > blocked[0][0] && mx < blocked[0][1] && mz > blocked[1][0] && mz < blocked[1][1])
                continue;
            double hx = 0.5 * (x1 - x0), hz = 0.5 * (z1 - z0);
            for (std::size_t u = 0; u < nodes.size(); ++u)
                for (std::size_t v = 0; v < nodes.size(); ++v) {
                    double x = mx + hx * nodes[u], z = mz + hz * nodes[v];
                    double r2 = (cx - x) * (cx - x) + hc * hc + (cz - z) * (cz - z);
                    sum += weights[u] * weights[v] * hx * hz * polygonIrradiance(l, x, z) * hc * hc /
                           (r2 * r2);
                }
        }
    return sum / (kPiD * kPiD);
}

std::string quadLightScene(const QuadLightSetup& l, const Vec3& floorAlbedo, bool ceiling,
                           double ceilingAlbedo, const std::string& camera) {
    const double s = l.halfSize, h = l.height;
    std::ostringstream o;
    o.precision(9);
    o << R"({"camera": )" << camera << R"(,
        "materials": {"floor": {"type": "diffuse", "color": )" << jsonVec(floorAlbedo) << R"(},
                      "ceiling": {"type": "diffuse", "color": [)" << ceilingAlbedo << ", "
      << ceilingAlbedo << ", " << ceilingAlbedo << R"(]},
                      "light": {"type": "diffuse", "color": [0, 0, 0]}},
        "nodes": [
          {"type": "quad", "material": "floor",
           "corners": [[-1, 0, -1], [-1, 0, 1], [1, 0, 1], [1, 0, -1]]},)";
    if (ceiling)
        o << R"(
          {"type": "quad", "material": "ceiling",
           "corners": [[1, 2, 1], [-1, 2, 1], [-1, 2, -1], [1, 2, -1]]},)";
    // Corners in this order make the light's normal -y (one-sided: it lights downwards only).
    o << R"(
          {"type": "quad", "material": "light", "emission": [)" << l.radiance << ", " << l.radiance
      << ", " << l.radiance << R"(],
           "corners": [[)" << -s << ", " << h << ", " << -s << "], [" << s << ", " << h << ", " << -s
      << "], [" << s << ", " << h << ", " << s << "], [" << -s << ", " << h << ", " << s << R"(]]}]})";
    return o.str();
}

} // namespace

TEST_CASE("Square light over a floor at grazing angles: Lambert's polygon formula", "[analytic]") {
    const QuadLightSetup light{1.0, 0.25, 10.0};
    const Vec3 albedo(0.8f, 0.5f, 0.2f);
    // Straight down from (0.9, 0.5, 0) with a 2 degree field: floor x in 0.9 +- 0.0087, narrow
    // enough that the pixels' spread (which checkMeanRadiance takes for noise) stays small.
    const double cx = 0.9, camHeight = 0.5, fov = 2.0;
    auto scene = sceneFromJson(quadLightScene(
        light, albedo, false, 0.0,
        R"({"position": [0.9, 0.5, 0], "look_at": [0.9, 0, 0], "up": [0, 0, -1], "fov": 2,
            "resolution": [16, 16]})"));
    EmbreeScene accel(*scene);

    // The image mean is the mean over the square footprint (image-plane coordinates are
    // uniform over the pixels): a 64 x 64 midpoint rule of a smooth function.
    const double t = std::tan(0.5 * fov * kPiD / 180.0);
    const int n = 64;
    double sum = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            double sx = (2.0 * (i + 0.5) / n - 1.0) * t, sy = (2.0 * (j + 0.5) / n - 1.0) * t;
            sum += polygonIrradiance(light, cx + camHeight * sx, camHeight * sy);
        }
    const double e = sum / (n * n);
    const Vec3 expected = albedo * float(e / kPiD);
    // Measured: -0.004% (path), -0.007% (raytrace). Before shadow rays aimed from their offset
    // origin: -14% in both modes.
    SECTION("path") {
        checkMeanRadiance(renderMode(*scene, accel, "path", 256, 1, 1), expected, 0.01, "path");
    }
    SECTION("raytrace") {
        checkMeanRadiance(renderMode(*scene, accel, "raytrace", 64), expected, 0.01, "raytrace");
    }
}

TEST_CASE("Two bounces under a one-sided square light: path mode against numerical integration",
          "[analytic]") {
    const QuadLightSetup light{0.5, 0.5, 10.0};
    const double hc = 2.0, ceilingAlbedo = 0.7;
    const Vec3 floorAlbedo(0.8f, 0.5f, 0.2f);
    // Straight up from between the light and the ceiling (the camera is not an occluder).
    const double camHeight = 1.2, fov = 20.0;
    const int size = 16;
    auto scene = sceneFromJson(quadLightScene(
        light, floorAlbedo, true, ceilingAlbedo,
        R"({"position": [0, 1.2, 0], "look_at": [0, 2, 0], "up": [0, 0, -1], "fov": 20,
            "resolution": [16, 16]})"));
    EmbreeScene accel(*scene);

    std::vector<double> nodes, weights;
    gaussLegendre(8, nodes, weights);
    const double t = std::tan(0.5 * fov * kPiD / 180.0), d = hc - camHeight;
    double sum = 0;
    for (int j = 0; j < 2 * size; ++j)
        for (int i = 0; i < 2 * size; ++i) {
            double sx = (2.0 * (i + 0.5) / (2 * size) - 1.0) * t;
            double sy = (2.0 * (j + 0.5) / (2 * size) - 1.0) * t;
            sum += twoBounce(light, hc, d * sx, d * sy, nodes, weights);
        }
    const double perAlbedo = sum / (4 * size * size);
    const Vec3 expected = floorAlbedo * float(ceilingAlbedo * perAlbedo);
    // Measured: +0.44% (both depths; the pixels' spread gives a standard error of 0.34%).
    // Before shadow rays aimed from their offset origin: -96% (depth 1) and -88% (depth 2):
    // this light, close and wide, reaches most of the floor at grazing angles. With that fixed
    // but the last vertex's light sample keeping only its MIS share: -7.8% at depth 1.
    SECTION("path, max depth 1") {
        checkMeanRadiance(renderMode(*scene, accel, "path", 4096, 1, 1), expected, 0.02, "path md1");
    }
    SECTION("path, max depth 2") {
        checkMeanRadiance(renderMode(*scene, accel, "path", 4096, 1, 2), expected, 0.02, "path md2");
    }
}
