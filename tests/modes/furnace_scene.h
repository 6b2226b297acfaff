// What the dispersion and determinism tests share: a pbrt-v4 furnace around a sphere of a
// given material, path renders of pbrt-v4 text at seed 1 on two threads, and the furnace check.
#pragma once

#include "../analytic/analytic.h"
#include "pbrt/pbrt_test_util.h"
#include "test_util.h"

#include <string>

namespace rayproc::test {

// The furnace (a closed sphere of radius 3, emission RGB (1, 1, 1), albedo 0.8: every ray
// carries 5, through lossless glass too, its radiance's eta^2 cancelling on leaving) around a
// sphere of radius 0.6 at (0, 0, -2) of `material` (a pbrt-v4 Material directive's rest, e.g.
// "\"dielectric\" \"float eta\" 1.5"), which fills the camera's 32x32 view.
inline std::string furnaceAround(const std::string& material) {
    return "LookAt 0 0 0  0 0 -1  0 1 0\n"
           "Camera \"perspective\" \"float fov\" 24\n"
           "Film \"rgb\" \"integer xresolution\" 32 \"integer yresolution\" 32\n"
           "WorldBegin\n"
           "AttributeBegin\n"
           "Material \"diffuse\" \"rgb reflectance\" [0.8 0.8 0.8]\n"
           "AreaLightSource \"diffuse\" \"rgb L\" [1 1 1] \"bool twosided\" true\n"
           "Shape \"sphere\" \"float radius\" 3\n"
           "AttributeEnd\n"
           "AttributeBegin\n"
           "Material " +
           material +
           "\n"
           "Translate 0 0 -2\n"
           "Shape \"sphere\" \"float radius\" 0.6\n"
           "AttributeEnd\n";
}

// Seed 1, two threads, quiet; spectral or RGB.
inline EngineSettings seedOneEngine(bool spectral) {
    EngineSettings e = quietTwoThreads(spectral);
    e.seed = 1;
    return e;
}

// Path mode's render of pbrt-v4 `text` (which must load without a warning) at `spp`.
inline Image renderPbrtPath(const std::string& text, int spp, bool spectral) {
    auto r = loadPbrt(text, "scene.pbrt");
    REQUIRE(r.warnings.empty());
    EmbreeScene accel(*r.scene);
    return renderPath(*r.scene, accel, pathSettings(r.scene->render, ModeOverrides{spp, 0, 0}),
                      seedOneEngine(spectral))
        .image;
}

// Spectral path mode in the furnace around `material` (1024 spp): every ray carries 5, so the
// image's mean must be 5 within 1% in every channel, with no invalid sample.
inline void checkSpectralPathFurnace(const std::string& material, const std::string& label) {
    auto r = loadPbrt(furnaceAround(material), "furnace.pbrt");
    REQUIRE(r.warnings.empty());
    EmbreeScene accel(*r.scene);
    RenderResult res = renderPath(*r.scene, accel,
                                  pathSettings(r.scene->render, ModeOverrides{1024, 0, 0}),
                                  seedOneEngine(true));
    checkMeanRadiance(res.image, Vec3(5.0f), 0.01, label);
    CHECK(res.stats.totals.invalidSamples == 0);
}

} // namespace rayproc::test
