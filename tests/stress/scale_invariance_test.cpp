// Scale invariance: the Cornell box scaled uniformly by 1e-4 ... 1e6, at the origin and
// translated 1e5 box-scales away, renders the same image in every mode as at unit scale.
// Criterion: relMSE(scaled, unit) at the same seed stays below half the noise level,
// relMSE(unit at seed 2, unit at seed 1), measured in the same test (docs/robustness.md).
#include "stress/stress_scenes.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace rayproc::test::stress {

namespace {

bool reportFigures() { return std::getenv("RAYPROC_STRESS_REPORT") != nullptr; }

struct ModeCase {
    const char* mode;
    int spp;
};

// 32 x 32 keeps the suite fast; the spp give a noise level well above float differences.
// relMSE leaves out the kDrop worst pixels (of 1024): far from the origin the box's input
// coordinates themselves round to float's spacing there (0.4% of the box), which moves the
// light's edge across a pixel or two; one pixel seeing the light (radiance 17) instead of the
// ceiling would outweigh the whole image's noise. Offsets cannot hide in 8 pixels: acne or leaks
// darken or brighten whole walls.
constexpr std::size_t kDrop = 8;

const ModeCase kModes[] = {{"preview", 1}, {"raytrace", 4}, {"path", 8}, {"gi", 4}};

// The lower half of an image: in the ground-plane scenes below, the floor, the sphere and its
// shadow, where a plane 1e3 wide and one 1e9 wide look the same (the upper half holds the
// smaller plane's horizon).
Image lowerHalf(const Image& img) {
    Image out(img.width, img.height / 2);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < 3; ++c) out.at(x, y)[c] = img.at(x, y + img.height / 2)[c];
    return out;
}

std::unique_ptr<Scene> cornellAt(double scale, double translation) {
    auto scene = loadSceneAt("cornell-box", 32, 32);
    placeScene(*scene, Frame::make(scale, {translation, -translation, translation}, false));
    return scene;
}

// A diffuse ground plane `size` wide under a unit sphere resting on it at the origin, lit by a
// point and a directional light (and a sky), tilted `degrees` about the x axis, towards the
// camera (+) or away from it (-). Its corners are A, B, -A, -B, so the plane through the rounded
// corners contains the origin exactly at every size.
std::unique_ptr<Scene> groundPlaneScene(double size, double degrees, bool sky) {
    double t = std::tan(degrees * 3.14159265358979323846 / 180.0), y = size * t;
    double nl = std::sqrt(1 + t * t);
    char corners[512], centre[128];
    std::snprintf(corners, sizeof corners,
                  "[[%.17g, %.17g, %.17g], [%.17g, %.17g, %.17g], [%.17g, %.17g, %.17g], "
                  "[%.17g, %.17g, %.17g]]",
                  -size, -y, size, size, -y, size, size, y, -size, -size, y, -size);
    std::snprintf(centre, sizeof centre, "[0, %.17g, %.17g]", 1 / nl, t / nl);
    std::string text =
        R"({"camera": {"position": [0, 3, 8], "look_at": [0, 0.5, 0], "resolution": [32, 24],
                       "fov": 40},
            "materials": {"g": {"type": "diffuse", "color": [0.5, 0.5, 0.5]},
                          "s": {"type": "diffuse", "color": [0.8, 0.3, 0.2]}},
            "lights": [{"type": "point", "position": [2, 5, 3], "intensity": [30, 30, 30]},
                       {"type": "directional", "direction": [-0.3, -1, -0.2],
                        "irradiance": [1, 1, 1]})" +
        std::string(sky ? R"(, {"type": "environment", "radiance": [0.2, 0.3, 0.6]})" : "") +
        R"(],
            "nodes": [{"type": "quad", "material": "g", "corners": )" +
        corners + R"(},
                      {"type": "sphere", "material": "s", "center": )" +
        centre + R"(, "radius": 1}]})";
    return loadSceneFromString(text, "ground-plane.json");
}

} // namespace

TEST_CASE("The Cornell box renders the same at every scale and far from the origin",
          "[stress][scale]") {
    const double scales[] = {1e-4, 1e-2, 1.0, 1e2, 1e4, 1e6};
    auto unit = cornellAt(1.0, 0.0);
    EmbreeScene unitAccel(*unit);
    for (const ModeCase& m : kModes) {
        RenderResult ref = renderStress(*unit, unitAccel, m.mode, m.spp, 1);
        RenderResult alt = renderStress(*unit, unitAccel, m.mode, m.spp, 2);
        double noise = relMseTrimmed(alt.image, ref.image, kDrop);
        INFO("mode " << m.mode << ": noise level (seed 2 vs seed 1) relMSE " << noise);
        REQUIRE(noise > 0);
        CHECK(ref.stats.totals.invalidSamples == 0);
        if (reportFigures())
            std::printf("scale %-8s noise %.3e\n", m.mode, noise);
        for (double s : scales) {
            for (bool far : {false, true}) {
                // 1e5 scene scales from the origin: at unit scale 1e5 units, where float's
                // spacing is 2^-7 (0.4% of the box's width of 2).
                auto scene = cornellAt(s, far ? 1e5 * s : 0.0);
                EmbreeScene accel(*scene);
                CHECK(accel.stats().exactTriangles == 0); // Embree's float test throughout
                RenderResult r = renderStress(*scene, accel, m.mode, m.spp, 1);
                double e = relMseTrimmed(r.image, ref.image, kDrop);
                if (reportFigures())
                    std::printf("scale %-8s s=%-6g far=%d relMSE %.3e (%.3f of noise) invalid %llu\n",
                                m.mode, s, int(far), e, e / noise,
                                (unsigned long long)r.stats.totals.invalidSamples);
                INFO("scale " << s << (far ? " translated 1e5 scales" : " at the origin")
                              << ": relMSE " << e << " = " << e / noise << " of the noise level");
                CHECK(allFinite(r.image));
                CHECK(r.stats.totals.invalidSamples == 0);
                CHECK(e <= 0.5 * noise);
            }
        }
        // Scaled by 1e11 (at the origin; 1e5 scales away would pass Embree's range): the
        // light's triangle areas are 1e22 and their cross products' squared lengths, 1e44,
        // overflowed a float, so the light had area inf and the scene was judged to emit
        // nothing (a black image).
        auto huge = cornellAt(1e11, 0.0);
        EmbreeScene hugeAccel(*huge);
        CHECK(hugeAccel.stats().exactTriangles == 0);
        RenderResult r = renderStress(*huge, hugeAccel, m.mode, m.spp, 1);
        double e = relMseTrimmed(r.image, ref.image, kDrop);
        INFO("scale 1e11: relMSE " << e << " = " << e / noise << " of the noise level");
        CHECK(meanValue(r.image) > 0.5 * meanValue(ref.image));
        CHECK(e <= 0.5 * noise);
    }
}

TEST_CASE("A ground plane 1e9 wide is lit and shadowed like a small one", "[stress][scale]") {
    // Seen from near the origin, the barycentric hit point on a 1e9 quad cancels to errors of
    // tens of units: the floor came out 80% darker in raytrace and path mode. Compared: the
    // lower half of the image (floor, sphere and its shadow), where both planes look the same.
    auto small = groundPlaneScene(100, 0, false), huge = groundPlaneScene(1e9, 0, false);
    EmbreeScene smallAccel(*small), hugeAccel(*huge);
    for (const ModeCase& m : {ModeCase{"raytrace", 4}, ModeCase{"path", 8}}) {
        INFO("mode " << m.mode);
        Image ref = lowerHalf(renderStress(*small, smallAccel, m.mode, m.spp, 1).image);
        Image alt = lowerHalf(renderStress(*small, smallAccel, m.mode, m.spp, 2).image);
        Image img = lowerHalf(renderStress(*huge, hugeAccel, m.mode, m.spp, 1).image);
        double noise = relMseTrimmed(alt, ref, 0);
        double e = relMseTrimmed(img, ref, 0);
        INFO("relMSE " << e << ", noise level " << noise);
        CHECK(meanValue(img) == Approx(meanValue(ref)).epsilon(0.01));
        CHECK(e <= 0.5 * noise + 1e-9); // raytrace's point light: no noise, the same image
    }
}

TEST_CASE("A tilted ground plane 1e9 wide is lit and shadowed like a small one",
          "[stress][scale]") {
    // Embree's float triangle test rounds a 1e9 triangle's vertices relative to the ray's origin
    // to ~60 units: tilted by a few degrees the plane vanished from the camera's rays (the sky
    // showed through, black without one) or was lit and shadowed wrong (1-4% off in the lower
    // half's mean here; 24% in the hardening audit's scene). Huge triangles are now intersected
    // in double precision (accel/huge_triangles.h, docs/robustness.md).
    //
    // The plane tilts about the x axis, towards the camera (+) or away from it (-); its corners
    // are A, B, -A, -B, so the plane through the rounded corners contains the origin exactly
    // at every size and the unit sphere rests on it at the origin, in both scenes.
    for (bool sky : {false, true}) {
        for (double degrees : {-10.0, -5.0, 5.0, 10.0}) {
            auto small = groundPlaneScene(1e3, degrees, sky), huge = groundPlaneScene(1e9, degrees, sky);
            EmbreeScene smallAccel(*small), hugeAccel(*huge);
            for (const ModeCase& m : {ModeCase{"raytrace", 4}, ModeCase{"path", 8}}) {
                Image ref = lowerHalf(renderStress(*small, smallAccel, m.mode, m.spp, 1).image);
                Image alt = lowerHalf(renderStress(*small, smallAccel, m.mode, m.spp, 2).image);
                RenderResult r = renderStress(*huge, hugeAccel, m.mode, m.spp, 1);
                Image img = lowerHalf(r.image);
                double noise = relMseTrimmed(alt, ref, 0);
                double e = relMseTrimmed(img, ref, 0);
                double mean = meanValue(img) / meanValue(ref) - 1;
                if (reportFigures())
                    std::printf("tilted plane %-8s sky=%d %+5.1f deg: mean %+.4f%%, relMSE %.3e "
                                "(%.4f of noise %.3e)\n",
                                m.mode, int(sky), degrees, 100 * mean, e, e / noise, noise);
                INFO("mode " << m.mode << (sky ? ", sky" : ", no sky") << ", tilted " << degrees
                             << " degrees: mean " << 100 * mean << "% off, relMSE " << e
                             << ", noise level " << noise);
                CHECK(r.stats.totals.invalidSamples == 0);
                // Measured (32x24): means within 0.001%, relMSE below 1e-6 of the noise (the same
                // seed traces the same paths over both planes). Before the fix every case failed
                // the mean by 0.7% (path, -10 degrees, no sky) to 100% (+5 and +10 degrees, no
                // sky: the plane was gone), and all but one the relMSE (0.46 to 390 times the
                // noise). 0.2% leaves room for other compilers' rounding, not for those.
                CHECK(std::abs(mean) <= 0.002);
                CHECK(e <= 0.5 * noise);
            }
        }
    }
}

} // namespace rayproc::test::stress
