// Spectral mode (--spectral, engine/spectral_render.h, docs/spectral.md): path mode with three
// hero wavelengths per path. Where the answer is known it must come out: a grey furnace lit by
// a white emitter, a grey scene as in RGB, a Lambertian orange under white light as its RGB
// (a Lambertian surface is linear in the reflectance, so the upsampling's round trip is all
// that may differ); and images stay bit-identical across thread counts. gi: spectral_gi_test.cpp.
#include "spectral_checks.h"

#include <cstring>
#include <filesystem>

using namespace rayproc;
using namespace rayproc::test;

namespace {

EngineSettings engineFor(bool spectral, int threads) {
    EngineSettings engine;
    engine.threads = threads;
    engine.seed = 1;
    engine.quiet = true;
    engine.spectral = spectral;
    return engine;
}

RenderResult renderPathMode(const Scene& scene, const EmbreeScene& accel, int spp, bool spectral,
                            int threads = 2) {
    return renderPath(scene, accel, pathSettings(scene.render, ModeOverrides{spp, 0, 0}),
                      engineFor(spectral, threads));
}

// raytrace or preview.
Image renderOther(const Scene& scene, const EmbreeScene& accel, const std::string& mode, int spp,
                  bool spectral) {
    ModeOverrides o{spp, 0, 0};
    if (mode == "preview")
        return renderPreview(scene, accel, previewSettings(scene.render, o), engineFor(spectral, 2))
            .image;
    return renderRaytrace(scene, accel, raytraceSettings(scene.render, o), engineFor(spectral, 2))
        .image;
}

} // namespace

TEST_CASE("Spectral furnace: a grey sphere of albedo 0.8 lit by white emission gives Le / (1 - a)",
          "[spectral-mode]") {
    // RGB (1, 1, 1) emission is the colour space's illuminant (D65 at luminance 1), whose sRGB
    // is (1, 1, 1); grey 0.8 is a flat spectrum. So every pixel is 1 / (1 - 0.8) = 5.
    auto scene = sceneFromJson(R"({"camera": {"position": [0, 0, 0], "look_at": [0, 0, -1],
                                   "fov": 70, "resolution": [32, 32]},
        "materials": {"wall": {"type": "diffuse", "color": [0.8, 0.8, 0.8]}},
        "lights": [],
        "nodes": [{"type": "sphere", "material": "wall", "radius": 1,
                   "emission": [1, 1, 1], "two_sided": true}]})");
    EmbreeScene accel(*scene);
    RenderResult r = renderPathMode(*scene, accel, 256, true);
    checkMeanRadiance(r.image, Vec3(5.0f), 0.01, "spectral furnace");
    CHECK(r.stats.totals.invalidSamples == 0);
}

TEST_CASE("Spectral mode: a grey Cornell box has RGB mode's mean", "[spectral-mode]") {
    auto scene = sceneFromJson(greyCornellBox());
    scene->camera.width = scene->camera.height = 48;
    EmbreeScene accel(*scene);
    checkSameMean(renderPathMode(*scene, accel, 64, false).image,
                  renderPathMode(*scene, accel, 64, true).image, "path");
}

TEST_CASE("Spectral mode: an orange Lambertian under white light keeps its RGB",
          "[spectral-mode]") {
    // A plane facing the camera, lit head-on by a white directional light of irradiance 1:
    // radiance albedo / pi in RGB. Spectrally the orange is upsampled, reflected at three
    // wavelengths and integrated back, so it must come out as the RGB within the
    // upsampling's round trip (1e-3) and the wavelengths' noise.
    const Vec3 orange(1.0f, 0.378676f, 0.013473f); // coffee's orange plastic's base
    auto scene = sceneFromJson(R"({"camera": {"position": [0, 0, 2], "look_at": [0, 0, 0],
                                   "fov": 30, "resolution": [24, 24]},
        "materials": {"orange": {"type": "diffuse", "color": )" + jsonVec(orange) + R"(}},
        "lights": [{"type": "directional", "direction": [0, 0, -1], "irradiance": [1, 1, 1]}],
        "nodes": [{"type": "quad", "material": "orange",
                   "corners": [[-4, -4, 0], [4, -4, 0], [4, 4, 0], [-4, 4, 0]]}]})");
    EmbreeScene accel(*scene);
    Image rgb = renderPathMode(*scene, accel, 16, false).image;
    Image spec = renderPathMode(*scene, accel, 256, true).image;
    for (int c = 0; c < 3; ++c) {
        PixelStats a = pixelStats(rgb, c), b = pixelStats(spec, c);
        INFO("channel " << c << ": RGB " << a.mean << " spectral " << b.mean << " +- "
                        << b.stdError);
        CHECK(a.mean == Approx(orange[c] / kPi).epsilon(1e-4));
        CHECK(std::abs(b.mean - a.mean) <= 4 * b.stdError + 2e-3 / kPi);
        CHECK(b.stdError < 0.003); // 1% of the orange's green: the check can see that
    }
}

TEST_CASE("Spectral images do not depend on the thread count", "[spectral-mode]") {
    auto scene = loadSceneAt("cornell-box", 48, 48);
    EmbreeScene accel(*scene);
    RenderResult one = renderPathMode(*scene, accel, 4, true, 1);
    RenderResult two = renderPathMode(*scene, accel, 4, true, 2);
    RenderResult rgb = renderPathMode(*scene, accel, 4, false, 2);
    CHECK(meanValue(one.image) > 0.01);
    CHECK(sameBits(one.image, two.image));
    CHECK_FALSE(sameBits(one.image, rgb.image)); // it did render spectrally
}

TEST_CASE("Every mode renders spectrally from the command line", "[spectral-mode][cli]") {
    TempDir dir;
    for (const std::string mode : {"path", "raytrace", "preview", "gi"}) {
        RunResult ok = runRayproc({"render", scenePath("cornell-box"), "--mode", mode,
                                   "--spectral", "--width", "16", "--height", "16", "--spp", "1",
                                   "-o", dir.file(mode + ".exr")},
                                  dir);
        INFO(mode << ": " << ok.err);
        CHECK(ok.status == 0);
        CHECK(ok.err.find("spectral=on") != std::string::npos);
        CHECK(std::filesystem::exists(dir.file(mode + ".exr")));
    }
}

TEST_CASE("Spectral raytrace and preview: a grey Cornell box has RGB mode's mean",
          "[spectral-mode]") {
    // They shade through the same bsdfAt, light conversions and film as path mode.
    auto scene = sceneFromJson(greyCornellBox());
    scene->camera.width = scene->camera.height = 48;
    EmbreeScene accel(*scene);
    for (const std::string mode : {"raytrace", "preview"}) {
        // Preview's one sample per pixel has no noise but the wavelengths'; they need samples
        // (and RGB the same, or the edges' antialiasing differs).
        const int spp = mode == "raytrace" ? 32 : 64;
        checkSameMean(renderOther(*scene, accel, mode, spp, false),
                      renderOther(*scene, accel, mode, spp, true), mode);
    }
}
