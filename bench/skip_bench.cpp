// What the scene analysis (modes/render_plan.h) saves: whole renders with the analysis on and
// off (--no-scene-analysis), wall time per frame, on scenes where it skips something.
//
//   BM_SkipGi/scene:cornell/analysis:on|off      gi, Cornell box (all diffuse): no caustic map
//   BM_SkipGi/scene:glossy/analysis:on|off       gi, glossy walls, mirror and glass spheres,
//                                                no diffuse surface: no global map, no cache
//   BM_SkipRaytrace/scene:points/analysis:on|off raytrace at 16 spp, diffuse box lit by two
//                                                point lights and two area lights facing away
//
// 128x128, gi at 4 spp with its default photon counts (200000 + 200000), 2 engine threads.
#include "modes/modes.h"
#include "scene/scene_loader.h"

#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>

namespace rayproc::bench {
namespace {

constexpr int kResolution = 128;

std::string box(const std::string& wall, const std::string& nodes, const std::string& lights) {
    return R"({"camera": {"position": [0, 1, 3.6], "look_at": [0, 1, 0], "fov": 40, "resolution": [128, 128]},
      "materials": {"wall": )" + wall + R"(,
        "black": {"type": "diffuse", "color": [0, 0, 0]},
        "mirror": {"type": "mirror", "color": [0.9, 0.9, 0.9]},
        "glass": {"type": "dielectric", "ior": 1.5, "color": [1, 1, 1]},
        "glossy": {"type": "glossy", "color": [0.8, 0.7, 0.5], "roughness": 0.4}},
      "lights": )" + lights + R"(,
      "nodes": [
        {"type": "rectangle", "material": "wall", "center": [0, 0, 0], "size": [2, 2]},
        {"type": "rectangle", "material": "wall", "center": [0, 2, 0], "size": [2, 2], "normal": [0, -1, 0]},
        {"type": "rectangle", "material": "wall", "center": [0, 1, -1], "size": [2, 2], "normal": [0, 0, 1]},
        {"type": "rectangle", "material": "wall", "center": [-1, 1, 0], "size": [2, 2], "normal": [1, 0, 0]},
        {"type": "rectangle", "material": "wall", "center": [1, 1, 0], "size": [2, 2], "normal": [-1, 0, 0]},
        )" + nodes + "]}";
}

struct Loaded {
    std::unique_ptr<Scene> scene;
    std::unique_ptr<EmbreeScene> accel;
};

Loaded& scene(const std::string& name) {
    static std::map<std::string, Loaded> cache;
    auto it = cache.find(name);
    if (it != cache.end()) return it->second;
    Loaded l;
    if (name == "cornell") {
        l.scene = loadScene(std::string(RAYPROC_SOURCE_DIR) + "/scenes/cornell-box.json");
    } else if (name == "glossy") {
        l.scene = loadSceneFromString(
            box(R"({"type": "glossy", "color": [0.8, 0.8, 0.8], "roughness": 0.5})",
                R"({"type": "rectangle", "material": "glossy", "emission": [12, 12, 12], "center": [0, 1.98, 0], "size": [0.6, 0.6], "normal": [0, -1, 0]},
                   {"type": "sphere", "material": "mirror", "center": [0.4, 0.4, 0.1], "radius": 0.3},
                   {"type": "sphere", "material": "glass", "center": [-0.4, 0.4, 0.2], "radius": 0.3})",
                "[]"),
            "glossy.json");
    } else { // points
        l.scene = loadSceneFromString(
            box(R"({"type": "diffuse", "color": [0.7, 0.6, 0.5]})",
                R"({"type": "rectangle", "material": "black", "emission": [40, 40, 40], "center": [0, 2.5, 0], "size": [0.6, 0.6]},
                   {"type": "rectangle", "material": "black", "emission": [40, 40, 40], "center": [0, 1, -1.5], "size": [0.6, 0.6], "normal": [0, 0, -1]})",
                R"([{"type": "point", "position": [0.2, 1.7, 0.3], "intensity": [2, 2, 2]},
                    {"type": "point", "position": [-0.5, 1.5, 0.2], "intensity": [1, 1, 1]}])"),
            "points.json");
    }
    l.scene->camera.width = kResolution;
    l.scene->camera.height = kResolution;
    l.accel = std::make_unique<EmbreeScene>(*l.scene);
    return cache.emplace(name, std::move(l)).first->second;
}

EngineSettings engine(bool analysis) {
    EngineSettings e;
    e.threads = 2;
    e.quiet = true;
    e.sceneAnalysis = analysis;
    return e;
}

void BM_SkipGi(benchmark::State& state, std::string name, bool analysis) {
    Loaded& l = scene(name);
    GiSettings s = giSettings(*l.scene, ModeOverrides{4, 0, 0});
    EngineSettings e = engine(analysis);
    for (auto _ : state) {
        RenderResult r = renderGi(*l.scene, *l.accel, s, e);
        benchmark::DoNotOptimize(r.image);
    }
}

void BM_SkipRaytrace(benchmark::State& state, std::string name, bool analysis) {
    Loaded& l = scene(name);
    RaytraceSettings s = raytraceSettings(l.scene->render, ModeOverrides{16, 0, 0});
    EngineSettings e = engine(analysis);
    for (auto _ : state) {
        RenderResult r = renderRaytrace(*l.scene, *l.accel, s, e);
        benchmark::DoNotOptimize(r.image);
    }
}

BENCHMARK_CAPTURE(BM_SkipGi, scene:cornell/analysis:on, "cornell", true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_SkipGi, scene:cornell/analysis:off, "cornell", false)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_SkipGi, scene:glossy/analysis:on, "glossy", true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_SkipGi, scene:glossy/analysis:off, "glossy", false)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_SkipRaytrace, scene:points/analysis:on, "points", true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_SkipRaytrace, scene:points/analysis:off, "points", false)->Unit(benchmark::kMillisecond)->UseRealTime();

} // namespace
} // namespace rayproc::bench
