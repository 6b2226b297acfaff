// Engine efficiency: the rays of one frame of path or gi mode (bench_modes.h), recorded as the
// engine traced them (engine/ray_recorder.h: every batch of every pass, gi's photon and cache
// passes included), replayed on one thread in the same order and batching:
//
//   BM_Replay/mode:path/scene:cornell/via:engine   the engine's Intersector (packets of 16,
//                                                  load, trace, hit write-back, statistics)
//   BM_Replay/mode:path/scene:cornell/via:embree   bare rtcIntersect16 / rtcOccluded16 on
//                                                  16-ray chunks of each batch, the same
//                                                  context flags (coherent for camera batches)
//
// Together with BM_Mode/mode:M/scene:S/engine_threads:1 (scaling_bench.cpp: the same frame
// rendered, shading and all, on one thread):
//   engine rays/s / raw Embree rays/s  =  (rays / T_frame) / (rays / T_embree)
//                                      =  T_embree / T_frame,
// i.e. the ratio is also the fraction of the frame's wall time that bare Embree traversal of
// its rays needs (replayed out of context: caches are warmer than inside a render).
// scripts/bench-throughput prints both as a table.
#include "bench_modes.h"

#include "engine/intersect.h"
#include "engine/ray_recorder.h"
#include "engine/stats.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

namespace rayproc::bench {
namespace {

struct Recording {
    std::string key;
    std::vector<RecordedBatch> batches; // padded to a multiple of 16 lanes (last ray repeated)
    std::uint64_t rays = 0;
    std::uint64_t raysTracedByRender = 0;
};

void padTo16(RecordedBatch& b) {
    int padded = (b.count + 15) / 16 * 16;
    for (std::vector<float>* v : {&b.ox, &b.oy, &b.oz, &b.dx, &b.dy, &b.dz, &b.tnear, &b.tfar})
        v->resize(std::size_t(padded), v->back());
}

// One recording at a time (a frame's rays take up to a few hundred MB): the benchmarks of one
// (mode, scene) are registered next to each other.
const Recording& recording(const std::string& mode, const std::string& sceneName) {
    static Recording current;
    std::string key = mode + "/" + sceneName;
    if (current.key == key) return current;
    current = Recording{};
    RayRecorder recorder;
    {
        RayRecorder::Scope scope(recorder);
        RenderResult r = renderModeFrame(mode, sceneName, 1);
        current.raysTracedByRender = r.stats.totals.raysTraced;
    }
    current.batches = recorder.batches();
    for (RecordedBatch& b : current.batches) {
        current.rays += std::uint64_t(b.count);
        if (b.count > 0) padTo16(b);
    }
    current.key = key;
    return current;
}

void setCounters(benchmark::State& state, const Recording& rec) {
    state.counters["rays/s"] = benchmark::Counter(double(rec.rays) * double(state.iterations()),
                                                  benchmark::Counter::kIsRate);
    state.counters["rays"] = double(rec.rays);
    state.counters["rays_by_render"] = double(rec.raysTracedByRender);
}

void replayEngine(benchmark::State& state, std::string mode, std::string sceneName) {
    const Recording& rec = recording(mode, sceneName);
    Intersector intersector(loadedScene(sceneName).accel->root(), 16);
    auto batch = std::make_unique<RayBatch>();
    auto shadows = std::make_unique<ShadowBatch>();
    ThreadStats stats;
    std::uint64_t hits = 0;
    for (auto _ : state) {
        for (const RecordedBatch& r : rec.batches) {
            WorkBatch& b = r.occlusion ? static_cast<WorkBatch&>(*shadows) : *batch;
            b.kind = r.kind;
            b.count = r.count;
            std::copy_n(r.ox.data(), r.count, b.ox.data());
            std::copy_n(r.oy.data(), r.count, b.oy.data());
            std::copy_n(r.oz.data(), r.count, b.oz.data());
            std::copy_n(r.dx.data(), r.count, b.dx.data());
            std::copy_n(r.dy.data(), r.count, b.dy.data());
            std::copy_n(r.dz.data(), r.count, b.dz.data());
            std::copy_n(r.tnear.data(), r.count, b.tnear.data());
            std::copy_n(r.tfar.data(), r.count, b.tfar.data());
            if (r.occlusion) {
                intersector.trace(*shadows, stats);
                hits += shadows->occluded(0) ? 1 : 0;
            } else {
                intersector.trace(*batch, stats);
                hits += batch->hit(0) ? 1 : 0;
            }
        }
    }
    benchmark::DoNotOptimize(hits);
    setCounters(state, rec);
}

// Bare Embree: each batch's 16-ray chunks loaded straight from the recording. The stores
// mirror what the engine keeps (all hit fields; for occlusion, tfar).
void replayEmbree(benchmark::State& state, std::string mode, std::string sceneName) {
    const Recording& rec = recording(mode, sceneName);
    RTCScene scene = loadedScene(sceneName).accel->root();
    std::vector<float> t(kBatchSize), u(kBatchSize), v(kBatchSize);
    std::vector<unsigned> geomId(kBatchSize), primId(kBatchSize), instId(kBatchSize);
    for (auto _ : state) {
        for (const RecordedBatch& r : rec.batches) {
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            ctx.flags = r.kind == RayKind::Camera ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT
                                                  : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
            for (int base = 0; base < r.count; base += 16) {
                alignas(64) int valid[16];
                for (int k = 0; k < 16; ++k) valid[k] = base + k < r.count ? -1 : 0;
                alignas(64) RTCRayHit16 rh;
                loadRay16(r, base, rh.ray);
                if (r.occlusion) {
                    rtcOccluded16(valid, scene, &ctx, &rh.ray);
                    std::copy_n(rh.ray.tfar, 16, &t[base]);
                } else {
                    for (int k = 0; k < 16; ++k) {
                        rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
                        rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
                    }
                    rtcIntersect16(valid, scene, &ctx, &rh);
                    std::copy_n(rh.ray.tfar, 16, &t[base]);
                    std::copy_n(rh.hit.u, 16, &u[base]);
                    std::copy_n(rh.hit.v, 16, &v[base]);
                    std::copy_n(rh.hit.geomID, 16, &geomId[base]);
                    std::copy_n(rh.hit.primID, 16, &primId[base]);
                    std::copy_n(rh.hit.instID[0], 16, &instId[base]);
                }
            }
            benchmark::DoNotOptimize(t.data());
            benchmark::ClobberMemory();
        }
    }
    setCounters(state, rec);
}

const bool kRegistered = [] {
    for (const char* mode : {"path", "gi"}) {
        for (const char* scene : {"cornell", "million"}) {
            std::string base = std::string("BM_Replay/mode:") + mode + "/scene:" + scene;
            for (bool engine : {true, false}) {
                std::string name = base + (engine ? "/via:engine" : "/via:embree");
                benchmark::RegisterBenchmark(name.c_str(), engine ? replayEngine : replayEmbree,
                                             std::string(mode), std::string(scene))
                    ->UseRealTime()
                    ->Unit(benchmark::kMillisecond)
                    ->MinTime(0.2);
            }
        }
    }
    return true;
}();

} // namespace
} // namespace rayproc::bench
