// Spectral mode (--spectral, engine/spectral_render.h, docs/spectral.md): path mode with three
// hero wavelengths per path. Where the answer is known it must come out: a grey furnace lit by
// a white emitter, a grey scene as in RGB, a Lambertian orange under white light as its RGB
// (a Lambertian surface is linear in the reflectance, so the upsampling's round trip is all
// that may differ); and images stay bit-identical across thread counts. gi refuses it.
#include "../analytic/analytic.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

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

// The Cornell box with every colour (materials and emission) replaced by its channel mean.
std::string greyCornellBox() {
    std::ifstream in(scenePath("cornell-box"));
    std::stringstream text;
    text << in.rdbuf();
    std::string json = text.str(), out;
    std::regex triple(R"re("(color|emission)": \[([0-9.]+), ([0-9.]+), ([0-9.]+)\])re");
    auto it = std::sregex_iterator(json.begin(), json.end(), triple);
    std::size_t last = 0;
    int replaced = 0;
    for (; it != std::sregex_iterator(); ++it) {
        const std::smatch& m = *it;
        double mean = (std::stod(m[2]) + std::stod(m[3]) + std::stod(m[4])) / 3;
        out += json.substr(last, std::size_t(m.position()) - last);
        out += "\"" + m[1].str() + "\": " + jsonVec(Vec3(float(mean)));
        last = std::size_t(m.position() + m.length());
        ++replaced;
    }
    REQUIRE(replaced >= 8); // every material and the light
    return out + json.substr(last);
}

// Checks per channel that two renders of one scene (different random numbers) have the same
// mean over the pixels that see no emitter (RGB below 1 in `a`): their per-pixel difference's
// mean within 4 of its standard errors (the renders' noise, not the image's content) plus
// `slack` of the mean, and that the check can see a 1% difference.
void checkSameMean(const Image& a, const Image& b, const std::string& label,
                   double slack = 2e-3) {
    REQUIRE(a.pixels.size() == b.pixels.size());
    for (int c = 0; c < 3; ++c) {
        double sum = 0, sumSq = 0, meanA = 0;
        std::size_t n = 0;
        for (std::size_t p = 0; p < a.pixels.size() / 3; ++p) {
            if (a.pixels[3 * p] > 1 || a.pixels[3 * p + 1] > 1 || a.pixels[3 * p + 2] > 1)
                continue;
            ++n;
            double d = double(b.pixels[3 * p + c]) - a.pixels[3 * p + c];
            sum += d;
            sumSq += d * d;
            meanA += a.pixels[3 * p + c];
        }
        double mean = sum / double(n), var = sumSq / double(n) - mean * mean;
        double stdError = std::sqrt(std::max(var, 0.0) / double(n - 1));
        meanA /= double(n);
        INFO(label << " channel " << c << ": mean " << meanA << ", difference " << mean
                   << " +- " << stdError);
        CHECK(std::abs(mean) <= 4 * stdError + slack * meanA);
        CHECK(n > a.pixels.size() / 3 / 2);
        CHECK(stdError < 0.0025 * meanA);
    }
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

TEST_CASE("Spectral rendering fails in gi mode, which cannot render it yet", "[spectral-mode][cli]") {
    TempDir dir;
    RunResult r = runRayproc({"render", scenePath("cornell-box"), "--mode", "gi", "--spectral",
                              "--width", "16", "--height", "16", "--spp", "1", "-o",
                              dir.file("gi.exr")},
                             dir);
    INFO(r.err);
    CHECK(r.status != 0);
    CHECK(r.err.find("not supported in gi mode") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir.file("gi.exr")));
    // Through the library too (before any photon is traced).
    auto scene = loadSceneAt("cornell-box", 16, 16);
    EmbreeScene accel(*scene);
    EngineSettings engine;
    engine.quiet = true;
    engine.spectral = true;
    CHECK_THROWS_WITH(renderGi(*scene, accel, giSettings(*scene, ModeOverrides{1, 0, 0}), engine),
                      Catch::Contains("not supported in gi mode"));
    // The other modes render it, and the render log says so.
    for (const std::string mode : {"path", "raytrace", "preview"}) {
        RunResult ok = runRayproc({"render", scenePath("cornell-box"), "--mode", mode,
                                   "--spectral", "--width", "16", "--height", "16", "--spp", "1",
                                   "-o", dir.file(mode + ".exr")},
                                  dir);
        INFO(mode << ": " << ok.err);
        CHECK(ok.status == 0);
        CHECK(ok.err.find("spectral=on") != std::string::npos);
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
