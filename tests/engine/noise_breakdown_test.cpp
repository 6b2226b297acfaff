// Path mode's per-pixel noise breakdown (--debug-view noise): the groups' means add up to the
// pixel, each strategy lands in its group, the noise layers add up to about the image's noise
// per sample measured between two seeds, the layers do not depend on the thread count, and the
// command line writes them as EXR layers (and refuses what cannot hold them).
#include "engine/noise_breakdown.h"

#include "test_util.h"

#include <catch2/catch.hpp>

#include <ImfChannelList.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

#include <map>

using namespace rayproc;
using namespace rayproc::test;

namespace {

RenderResult renderWithBreakdown(const Scene& scene, const EmbreeScene& accel, int spp,
                                 std::uint64_t seed, int threads = 2, bool stratify = true) {
    EngineSettings engine;
    engine.stratification = stratify;
    engine.quiet = true;
    engine.threads = threads;
    engine.seed = seed;
    RenderControl control;
    control.noiseBreakdown = true;
    return renderPath(scene, accel, pathSettings(scene.render, ModeOverrides{spp, 0, 0}), engine,
                      control);
}

std::map<std::string, const std::vector<float>*> byName(const RenderResult& r) {
    std::map<std::string, const std::vector<float>*> m;
    for (const ImageLayer& l : r.layers) m[l.name] = &l.values;
    return m;
}

double layerMean(const std::vector<float>& v) {
    double s = 0;
    for (float x : v) s += x;
    return s / double(v.size());
}

} // namespace

TEST_CASE("The noise breakdown's groups add up to the pixel and hold their strategies",
          "[engine]") {
    auto scene = loadSceneAt("cornell-spheres", 32, 32);
    EmbreeScene accel(*scene);
    RenderResult r = renderWithBreakdown(*scene, accel, 16, 1);
    REQUIRE(r.layers.size() == 2 * NoiseBreakdown::kGroups + 1); // and noise.total
    auto layers = byName(r);
    for (int g = 0; g < NoiseBreakdown::kGroups; ++g) {
        const std::string name = NoiseBreakdown::name(NoiseBreakdown::Group(g));
        REQUIRE(layers.count("noise." + name) == 1);
        REQUIRE(layers.count("mean." + name) == 1);
    }
    // Every contribution is in exactly one group: the means add up to the pixel's luminance.
    double worst = 0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            const std::size_t p = std::size_t(y) * 32 + std::size_t(x);
            double sum = 0;
            for (int g = 0; g < NoiseBreakdown::kGroups; ++g)
                sum += (*layers["mean." + std::string(NoiseBreakdown::name(NoiseBreakdown::Group(g)))])[p];
            const float* px = r.image.at(x, y);
            const double lum = luminance(Vec3(px[0], px[1], px[2]));
            worst = std::max(worst, std::abs(sum - lum) / (lum + 1e-3));
        }
    CHECK(worst < 1e-4);
    // The scene has area lights, a mirror and glass, no sky.
    CHECK(layerMean(*layers["mean.light-samples"]) > 0.05);
    CHECK(layerMean(*layers["mean.light-hits"]) > 0); // a small light: BSDF rays rarely win
    CHECK(layerMean(*layers["mean.direct"]) > 0.001);  // the light, seen and in the mirror
    CHECK(layerMean(*layers["mean.caustic"]) > 1e-5);  // the light through the glass sphere
    CHECK(layerMean(*layers["noise.caustic"]) > 0);
    CHECK(layerMean(*layers["mean.sky-samples"]) == 0);
    CHECK(layerMean(*layers["mean.sky-hits"]) == 0);
    CHECK(layerMean(*layers["noise.sky-hits"]) == 0);
}

TEST_CASE("The noise layers add up to about the noise per sample measured between two seeds",
          "[engine]") {
    auto scene = loadSceneAt("cornell-box", 32, 32);
    EmbreeScene accel(*scene);
    const int spp = 32;
    // Independent samples: the variance of the samples is the variance of their mean times n.
    // (Sobol points' mean varies less: by 1.3x less on this image at 32 spp.)
    RenderResult a = renderWithBreakdown(*scene, accel, spp, 1, 2, false);
    RenderResult b = renderWithBreakdown(*scene, accel, spp, 2, 2, false);
    // Two independent renders: E[(A - B)^2] / 2 is one render's variance (in luminance here,
    // as the layers are).
    double measured = 0, predicted = 0;
    auto la = byName(a);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            const float *pa = a.image.at(x, y), *pb = b.image.at(x, y);
            const double ya = luminance(Vec3(pa[0], pa[1], pa[2]));
            const double yb = luminance(Vec3(pb[0], pb[1], pb[2]));
            const double f = 0.5 * (ya + yb);
            measured += spp * 0.5 * (ya - yb) * (ya - yb) / (f * f + 0.01);
        }
    for (int g = 0; g < NoiseBreakdown::kGroups; ++g)
        predicted += layerMean(*la["noise." + std::string(NoiseBreakdown::name(NoiseBreakdown::Group(g)))]);
    const double total = layerMean(*la["noise.total"]);
    measured /= 32.0 * 32.0;
    INFO("measured " << measured << ", total layer " << total << ", groups' sum " << predicted);
    // The total is the pixel's variance per sample: as measured, within the noise of 1024
    // pixels' estimates.
    CHECK(total > 0.75 * measured);
    CHECK(total < 1.33 * measured);
    // The groups leave out their covariances only.
    CHECK(predicted > 0.4 * total);
    CHECK(predicted < 1.5 * total);
}

TEST_CASE("The noise breakdown does not depend on the thread count", "[engine]") {
    auto scene = loadSceneAt("cornell-spheres", 24, 16);
    EmbreeScene accel(*scene);
    RenderResult one = renderWithBreakdown(*scene, accel, 8, 3, 1);
    RenderResult two = renderWithBreakdown(*scene, accel, 8, 3, 2);
    REQUIRE(one.layers.size() == two.layers.size());
    for (std::size_t i = 0; i < one.layers.size(); ++i) {
        INFO(one.layers[i].name);
        CHECK(one.layers[i].values == two.layers[i].values);
    }
    CHECK(sameBits(one.image, two.image));
}

TEST_CASE("The noise debug view writes its layers into the EXR, and only there and in path mode",
          "[engine][cli]") {
    TempDir dir;
    const std::vector<std::string> base{"render", scenePath("cornell-box"), "--width", "16",
                                        "--height", "16", "--spp", "4", "-q"};
    auto run = [&](std::vector<std::string> extra) {
        std::vector<std::string> a = base;
        a.insert(a.end(), extra.begin(), extra.end());
        return runRayproc(a, dir);
    };
    RunResult ok = run({"--mode", "path", "--debug-view", "noise", "-o", dir.file("n.exr")});
    INFO(ok.err);
    REQUIRE(ok.status == 0);
    Imf::InputFile file(dir.file("n.exr").c_str());
    std::size_t layers = 0;
    for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it)
        layers += std::string(it.name()).find(".Y") != std::string::npos;
    CHECK(layers == 2 * NoiseBreakdown::kGroups + 1);
    CHECK(file.header().channels().findChannel("noise.light-samples.Y") != nullptr);
    // The image itself reads as before.
    Image img = readImage(dir.file("n.exr"));
    CHECK(meanValue(img) > 0.01);

    RunResult png = run({"--mode", "path", "--debug-view", "noise", "-o", dir.file("n.png")});
    CHECK(png.status != 0);
    CHECK(png.err.find(".exr") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir.file("n.png")));
    RunResult raytrace = run({"--mode", "raytrace", "--debug-view", "noise", "-o", dir.file("r.exr")});
    CHECK(raytrace.status != 0);
    CHECK(raytrace.err.find("path mode") != std::string::npos);
    RunResult photons = run({"--mode", "path", "--debug-view", "photons", "-o", dir.file("p.exr")});
    CHECK(photons.status != 0);
    CHECK(photons.err.find("gi mode") != std::string::npos);
}
