// Whole frames of every mode on 1 and 2 engine threads: the thread scaling of the ray
// processor, and (on one thread) the engine rays/s that engine_efficiency_bench.cpp compares
// with raw Embree on the same rays. Frames as in bench_modes.h.
//
//   BM_Mode/mode:path/scene:cornell/engine_threads:1
//
// engine_threads is EngineSettings::threads (the benchmark itself runs on one thread).
// Counters:
//   rays/s             every ray handed to Embree (RenderStats raysTraced; gi: photon, cache
//                      and render passes) over the wall time of the render call
//   rays/frame         the same count per frame (identical for 1 and 2 threads: deterministic)
//   intersector_share  the Intersector's seconds (Intersect + Occlude stage timers: packet
//                      load, Embree, hit write-back), summed over threads, over the render
//                      phase's wall time x threads (gi: the final render pass only)
//   staged_share       every stage timer's seconds (emitters, Intersector, retrace stages;
//                      none is nested in another), summed over threads, over the render
//                      phase's wall time x threads. On one thread, 1 - staged_share is the
//                      part of the frame spent outside the processor's stages: light set,
//                      film, pass commits, resolve, queue traffic: the serial fraction's
//                      estimate from a 1-thread profile (queue traffic would parallelise)
#include "bench_modes.h"

#include <benchmark/benchmark.h>

#include <string>

namespace rayproc::bench {
namespace {

void modeFrameBench(benchmark::State& state, std::string mode, std::string sceneName, int threads) {
    std::uint64_t rays = 0;
    double intersectorSeconds = 0, stagedSeconds = 0, phaseSeconds = 0;
    for (auto _ : state) {
        RenderResult r = renderModeFrame(mode, sceneName, threads);
        rays += r.stats.totals.raysTraced;
        intersectorSeconds += r.stats.totals.stages[int(StageId::Intersect)].seconds +
                              r.stats.totals.stages[int(StageId::Occlude)].seconds;
        for (const StageCounters& c : r.stats.totals.stages) stagedSeconds += c.seconds;
        phaseSeconds += renderPhaseSeconds(r) * threads;
        benchmark::DoNotOptimize(r.image);
    }
    state.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
    state.counters["rays/frame"] = double(rays) / double(state.iterations());
    state.counters["intersector_share"] = phaseSeconds > 0 ? intersectorSeconds / phaseSeconds : 0;
    state.counters["staged_share"] = phaseSeconds > 0 ? stagedSeconds / phaseSeconds : 0;
}

const bool kRegistered = [] {
    struct Case {
        const char* mode;
        const char* scene;
    };
    for (Case c : {Case{"preview", "cornell"}, Case{"raytrace", "cornell"}, Case{"path", "cornell"},
                   Case{"gi", "cornell"}, Case{"raytrace", "million"}, Case{"path", "million"},
                   Case{"gi", "million"}}) {
        for (int threads : {1, 2}) {
            std::string name = std::string("BM_Mode/mode:") + c.mode + "/scene:" + c.scene +
                               "/engine_threads:" + std::to_string(threads);
            benchmark::RegisterBenchmark(name.c_str(), modeFrameBench, std::string(c.mode),
                                         std::string(c.scene), threads)
                ->UseRealTime()
                ->Unit(benchmark::kMillisecond)
                ->MinTime(0.2);
        }
    }
    return true;
}();

} // namespace
} // namespace rayproc::bench
