// rayproc serve's interactivity (docs/serve.md): how soon a change shows, and how fast the live
// preview renders, on the Cornell box with all cores.
//
//   BM_ServeEditToFrame/edit:camera     a camera move -> the first frame (the coarse 1/4 one)
//   BM_ServeEditToFrame/edit:transform  an object moved (the scene re-loaded and re-built) ->
//                                       the first frame
//   BM_ServePreviewFrame/side:512       one full 512x512 preview frame (frames/s = 1 / time)
//   BM_ServePreviewFrame/side:128       the coarse frame
//
// The edit benchmarks go through Session::handle and its worker, as a page's messages do; each
// iteration waits for the preview to finish (waitIdle) outside the timing.
#include "accel/embree_scene.h"
#include "modes/modes.h"
#include "scene/scene_loader.h"
#include "serve/session.h"

#include <benchmark/benchmark.h>

#include <chrono>
#include <condition_variable>
#include <mutex>

namespace rayproc::bench {
namespace {

const std::string kScene = std::string(RAYPROC_SOURCE_DIR) + "/scenes/cornell-box.json";

void BM_ServeEditToFrame(benchmark::State& state) {
    const bool camera = state.range(0) == 0;
    std::mutex mutex;
    std::condition_variable arrived;
    int frames = 0;
    serve::Session session(kScene, serve::Session::Options{0, 512});
    session.start({[](const std::string&) {},
                   [&](const std::vector<std::uint8_t>&) {
                       std::lock_guard<std::mutex> lk(mutex);
                       ++frames;
                       arrived.notify_all();
                   }});
    session.waitIdle();
    int step = 0;
    for (auto _ : state) {
        int before;
        {
            std::lock_guard<std::mutex> lk(mutex);
            before = frames;
        }
        ++step;
        double s = (step % 2) ? 1.0 : -1.0;
        serve::Json message =
            camera ? serve::Json{{"type", "camera"}, {"position", {0.2 * s, 1, 6.8}}}
                   : serve::Json{{"type", "transform"}, {"object", 6}, {"translate", {0.05 * s, 0, 0}}};
        auto start = std::chrono::steady_clock::now();
        std::string reply = session.handle(message.dump(), 1);
        {
            std::unique_lock<std::mutex> lk(mutex);
            arrived.wait(lk, [&] { return frames > before; });
        }
        state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        if (reply.find("error") != std::string::npos) state.SkipWithError(reply.c_str());
        session.waitIdle();
    }
}
BENCHMARK(BM_ServeEditToFrame)->ArgNames({"edit"})->Arg(0)->Arg(1)->UseManualTime()->Unit(benchmark::kMillisecond);

void BM_ServePreviewFrame(benchmark::State& state) {
    std::unique_ptr<Scene> scene = loadScene(kScene);
    scene->camera.width = scene->camera.height = int(state.range(0));
    EmbreeScene accel(*scene);
    EngineSettings engine;
    engine.quiet = true;
    PreviewSettings s = previewSettings(scene->render, {});
    for (auto _ : state) benchmark::DoNotOptimize(renderPreview(*scene, accel, s, engine).image.pixels.data());
    state.counters["frames_per_second"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ServePreviewFrame)->ArgNames({"side"})->Arg(512)->Arg(128)->UseRealTime()->Unit(benchmark::kMillisecond);

} // namespace
} // namespace rayproc::bench
