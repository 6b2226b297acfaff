// Scale invariance: the Cornell box scaled uniformly by 1e-4 ... 1e6, at the origin and
// translated 1e5 box-scales away, renders the same image in every mode as at unit scale.
// Criterion: relMSE(scaled, unit) at the same seed stays below half the noise level,
// relMSE(unit at seed 2, unit at seed 1), measured in the same test (docs/robustness.md).
#include "stress/stress_scenes.h"

#include <cstdio>
#include <cstdlib>

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

std::unique_ptr<Scene> cornellAt(double scale, double translation) {
    auto scene = loadSceneAt("cornell-box", 32, 32);
    placeScene(*scene, Frame::make(scale, {translation, -translation, translation}, false));
    return scene;
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
    }
}

} // namespace rayproc::test::stress
