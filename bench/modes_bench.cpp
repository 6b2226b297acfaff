// Whole-frame benchmarks of the modes at 512x512: preview frames per second, and raytrace
// (spp 4) rays per second, where rays are every ray handed to Embree (camera, shadow,
// reflection, refraction: RenderStats' raysTraced) over the wall time of the render call.
// The scene and its EmbreeScene are built once, outside the timed loop; what a frame costs
// here is what runRenderJob costs: light set, film, pipeline, tracing, resolve.
//
//   BM_Preview/scene:cornell/engine_threads:all    fps
//   BM_Raytrace/scene:cornell/engine_threads:1     rays/s on one engine thread
//
// engine_threads is EngineSettings::threads (all = every core), not the benchmark's threads.
#include "bench_scenes.h"

#include "modes/modes.h"

#include <benchmark/benchmark.h>

#include <string>

namespace rayproc::bench {
namespace {

constexpr int kResolution = 512;
constexpr int kRaytraceSpp = 4;

Scene& sceneAt512(const std::string& name) {
    Scene& scene = *loadedScene(name).scene;
    scene.camera.width = kResolution;
    scene.camera.height = kResolution;
    return scene;
}

EngineSettings engineSettings(int threads) {
    EngineSettings e;
    e.threads = threads;
    e.quiet = true;
    return e;
}

void setRayCounters(benchmark::State& state, std::uint64_t rays) {
    state.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
    state.counters["rays/frame"] = double(rays) / double(state.iterations());
}

void preview(benchmark::State& state, std::string sceneName, int threads) {
    Scene& scene = sceneAt512(sceneName);
    const EmbreeScene& accel = *loadedScene(sceneName).accel;
    PreviewSettings settings = previewSettings(scene.render, ModeOverrides{});
    EngineSettings engine = engineSettings(threads);
    std::uint64_t rays = 0;
    for (auto _ : state) {
        RenderResult r = renderPreview(scene, accel, settings, engine);
        rays += r.stats.totals.raysTraced;
        benchmark::DoNotOptimize(r.image);
    }
    state.counters["fps"] =
        benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
    setRayCounters(state, rays);
}

void raytrace(benchmark::State& state, std::string sceneName, int threads) {
    Scene& scene = sceneAt512(sceneName);
    const EmbreeScene& accel = *loadedScene(sceneName).accel;
    ModeOverrides overrides;
    overrides.spp = kRaytraceSpp;
    RaytraceSettings settings = raytraceSettings(scene.render, overrides);
    EngineSettings engine = engineSettings(threads);
    std::uint64_t rays = 0;
    for (auto _ : state) {
        RenderResult r = renderRaytrace(scene, accel, settings, engine);
        rays += r.stats.totals.raysTraced;
        benchmark::DoNotOptimize(r.image);
    }
    setRayCounters(state, rays);
}

template <class Fn>
void registerMode(const char* base, Fn fn, const char* scene, int threads) {
    std::string name = std::string(base) + "/scene:" + scene +
                       "/engine_threads:" + (threads > 0 ? std::to_string(threads) : "all");
    benchmark::RegisterBenchmark(name.c_str(), fn, std::string(scene), threads)
        ->UseRealTime()
        ->Unit(benchmark::kMillisecond)
        ->MinTime(0.2);
}

const bool kRegistered = [] {
    for (int threads : {0, 1}) registerMode("BM_Preview", preview, "cornell", threads);
    for (const char* scene : {"cornell", "million"})
        for (int threads : {0, 1}) registerMode("BM_Raytrace", raytrace, scene, threads);
    return true;
}();

} // namespace
} // namespace rayproc::bench
