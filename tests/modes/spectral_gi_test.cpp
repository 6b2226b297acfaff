// Spectral gi (--spectral --mode gi, docs/spectral.md): photons with wavelengths of their own,
// maps of their XYZ, gathers and the cache's estimates taken at a path's wavelengths. Where the
// answer is known it must come out: the inside-out furnace lit by white emission, a grey
// Cornell box as gi renders it in RGB; and images stay bit-identical across thread counts.
#include "gi/glossy_ceiling_scene.h"
#include "spectral_checks.h"

using namespace rayproc;
using namespace rayproc::test;

namespace {

RenderResult renderGiWith(const Scene& scene, const EmbreeScene& accel, int spp, bool spectral,
                          int threads = 2, bool mapCorrection = false) {
    EngineSettings engine;
    engine.threads = threads;
    engine.seed = 1;
    engine.quiet = true;
    engine.spectral = spectral;
    GiSettings s = giSettings(scene, ModeOverrides{spp, 0, 0});
    s.mapCorrection = mapCorrection;
    return renderGi(scene, accel, s, engine);
}

// The inside-out furnace of tests/analytic/furnace_test.cpp, grey: a sphere of albedo 0.8
// emitting RGB (1, 1, 1), the colour space's illuminant, whose sRGB is (1, 1, 1).
std::unique_ptr<Scene> greyFurnace() {
    return sceneFromJson(R"({"camera": {"position": [0, 0, 0], "look_at": [0, 0, -1],
                                   "fov": 70, "resolution": [32, 32]},
        "materials": {"wall": {"type": "diffuse", "color": [0.8, 0.8, 0.8]}},
        "lights": [],
        "nodes": [{"type": "sphere", "material": "wall", "radius": 1,
                   "emission": [1, 1, 1], "two_sided": true}]})");
}

} // namespace

TEST_CASE("Spectral gi furnace: white emission and albedo 0.8 give Le / (1 - a)",
          "[spectral-mode][gi]") {
    // Direct light by shadow rays at the lane's wavelengths; the rest, a^2 Le / (1 - a) = 3.2
    // of the 5, from the cache's gathers reading the map of the photons' XYZ, taken back to
    // the wavelengths as the illuminant's spectrum: a flat-spectrum reflectance under the
    // illuminant's light, which the film turns into white. (An unbounded RGB spectrum without
    // the illuminant would be flat: the equal-energy white's colour, not the illuminant's.)
    auto scene = greyFurnace();
    EmbreeScene accel(*scene);
    RenderResult r = renderGiWith(*scene, accel, 16, true);
    checkMeanRadiance(r.image, Vec3(5.0f), kGiTolerance, "spectral gi furnace");
    CHECK(r.stats.totals.invalidSamples == 0);
    // With the map's bias corrected by paths (the correction stage at the lane's wavelengths;
    // noisier: more samples).
    RenderResult corrected = renderGiWith(*scene, accel, 64, true, 2, true);
    checkMeanRadiance(corrected.image, Vec3(5.0f), kGiTolerance, "spectral gi furnace, corrected");
}

TEST_CASE("Spectral gi: a grey Cornell box has gi's RGB mean", "[spectral-mode][gi]") {
    // Grey colours are flat spectra and the light is the illuminant: the photons take the same
    // paths in both modes, so the maps differ only by their wavelengths' colour noise.
    auto scene = sceneFromJson(greyCornellBox());
    scene->camera.width = scene->camera.height = 48;
    EmbreeScene accel(*scene);
    checkSameMean(renderGiWith(*scene, accel, 64, false).image,
                  renderGiWith(*scene, accel, 64, true).image, "gi", 5e-3);
}

TEST_CASE("Spectral gi images do not depend on the thread count", "[spectral-mode][gi]") {
    auto scene = loadSceneAt("cornell-box", 48, 48);
    EmbreeScene accel(*scene);
    RenderResult one = renderGiWith(*scene, accel, 2, true, 1);
    RenderResult two = renderGiWith(*scene, accel, 2, true, 2);
    RenderResult rgb = renderGiWith(*scene, accel, 2, false, 2);
    CHECK(meanValue(one.image) > 0.01);
    CHECK(sameBits(one.image, two.image));
    CHECK_FALSE(sameBits(one.image, rgb.image)); // it did render spectrally
}

TEST_CASE("Spectral gi lights a floor through a glossy silver ceiling as spectral path does",
          "[spectral-mode][gi][glossy]") {
    // tests/gi/glossy_gather_test.cpp's scene: the floor's light comes only through the
    // ceiling's glossy lobe (L G D), which the gathers read with the map's luminance-weighted
    // radiance estimate and silver's eta and k at the lane's wavelengths
    // (PhotonMap::luminanceRadiance).
    auto scene = glossyCeilingScene();
    EmbreeScene accel(*scene);
    EngineSettings engine;
    engine.threads = 2;
    engine.seed = 1;
    engine.quiet = true;
    engine.spectral = true;
    const Vec3 path = imageMean(
        renderPath(*scene, accel, pathSettings(scene->render, ModeOverrides{1024, 0, 0}), engine)
            .image);
    const Vec3 gi = imageMean(renderGiWith(*scene, accel, 16, true).image);
    for (int c = 0; c < 3; ++c) {
        INFO("channel " << c << ": gi " << gi[c] << " path " << path[c]);
        CHECK(gi[c] == Approx(path[c]).epsilon(0.05)); // gi RGB's bar against RGB path
    }
}
