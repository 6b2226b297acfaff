// Intersection throughput: the engine's Intersector over RayBatches at packet widths 1, 4, 8
// and 16, against the same rays through bare Embree calls (no batch), on coherent camera rays
// and incoherent surface-to-anywhere rays of the Cornell box and the million-triangle scene.
//
// Each iteration traces the scene's precomputed ray set of kRaySetSize rays on the benchmark's
// one thread. Engine: copy 256 rays into a batch, Intersector::trace (which loads packets,
// traces, writes hits back and counts statistics). Raw: load each packet straight from the
// ray set's arrays, trace, store the same hit fields. The difference is the engine's overhead
// per traced ray, outside Embree.
//
//   BM_Intersect/scene:cornell/width:16/coherent:1   engine, packets of 16, camera rays
//   BM_EmbreeRaw/scene:million/width:1/coherent:0    rtcIntersect1, incoherent rays
#include "bench_scenes.h"

#include "engine/intersect.h"
#include "engine/ray_batch.h"
#include "engine/stats.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

namespace rayproc::bench {
namespace {

// Where the hits go, so that the raw loops do the same stores as the engine.
struct HitArrays {
    std::vector<float> t, u, v;
    std::vector<unsigned> geomId, primId, instId;
    explicit HitArrays(int n) : t(n), u(n), v(n), geomId(n), primId(n), instId(n) {}
};

void setCounters(benchmark::State& state, int raysPerIteration) {
    std::int64_t rays = std::int64_t(state.iterations()) * raysPerIteration;
    state.SetItemsProcessed(rays);
    state.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
}

void contextFor(RTCIntersectContext& ctx, bool coherent) {
    rtcInitIntersectContext(&ctx);
    ctx.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
}

// The engine: batches of kBatchSize through Intersector::trace. Camera batches are traced with
// the coherent flag, every other kind with the incoherent one (Intersector's rule).
void intersectEngine(benchmark::State& state, std::string sceneName, int width, bool coherent) {
    const RaySet& rays = raySet(sceneName, coherent);
    RTCScene scene = loadedScene(sceneName).accel->root();
    Intersector intersector(scene, width);
    auto batch = std::make_unique<RayBatch>();
    ThreadStats stats;
    std::uint64_t hits = 0;
    for (auto _ : state) {
        for (int base = 0; base < rays.size(); base += kBatchSize) {
            RayBatch& b = *batch;
            b.kind = coherent ? RayKind::Camera : RayKind::Reflection;
            b.count = std::min(kBatchSize, rays.size() - base);
            std::copy_n(&rays.ox[base], b.count, b.ox.data());
            std::copy_n(&rays.oy[base], b.count, b.oy.data());
            std::copy_n(&rays.oz[base], b.count, b.oz.data());
            std::copy_n(&rays.dx[base], b.count, b.dx.data());
            std::copy_n(&rays.dy[base], b.count, b.dy.data());
            std::copy_n(&rays.dz[base], b.count, b.dz.data());
            std::copy_n(&rays.tnear[base], b.count, b.tnear.data());
            std::copy_n(&rays.tfar[base], b.count, b.tfar.data());
            intersector.trace(b, stats);
            hits += b.hit(0) ? 1 : 0;
        }
    }
    benchmark::DoNotOptimize(hits);
    setCounters(state, rays.size());
}

// Bare rtcIntersect16: packets loaded straight from the ray set, all 16 lanes valid.
void embreeRaw16(benchmark::State& state, std::string sceneName, bool coherent) {
    const RaySet& rays = raySet(sceneName, coherent);
    RTCScene scene = loadedScene(sceneName).accel->root();
    HitArrays out(rays.size());
    alignas(64) int valid[16];
    std::fill_n(valid, 16, -1);
    for (auto _ : state) {
        RTCIntersectContext ctx;
        contextFor(ctx, coherent);
        for (int base = 0; base + 16 <= rays.size(); base += 16) {
            alignas(64) RTCRayHit16 rh;
            loadRay16(rays, base, rh.ray);
            for (int k = 0; k < 16; ++k) {
                rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
            }
            rtcIntersect16(valid, scene, &ctx, &rh);
            std::copy_n(rh.ray.tfar, 16, &out.t[base]);
            std::copy_n(rh.hit.u, 16, &out.u[base]);
            std::copy_n(rh.hit.v, 16, &out.v[base]);
            std::copy_n(rh.hit.geomID, 16, &out.geomId[base]);
            std::copy_n(rh.hit.primID, 16, &out.primId[base]);
            std::copy_n(rh.hit.instID[0], 16, &out.instId[base]);
        }
        benchmark::DoNotOptimize(out.t.data());
        benchmark::ClobberMemory();
    }
    setCounters(state, rays.size());
}

// Bare rtcIntersect1, one ray at a time from the ray set.
void embreeRaw1(benchmark::State& state, std::string sceneName, bool coherent) {
    const RaySet& rays = raySet(sceneName, coherent);
    RTCScene scene = loadedScene(sceneName).accel->root();
    HitArrays out(rays.size());
    for (auto _ : state) {
        RTCIntersectContext ctx;
        contextFor(ctx, coherent);
        for (int i = 0; i < rays.size(); ++i) {
            RTCRayHit rh;
            rh.ray.org_x = rays.ox[i]; rh.ray.org_y = rays.oy[i]; rh.ray.org_z = rays.oz[i];
            rh.ray.dir_x = rays.dx[i]; rh.ray.dir_y = rays.dy[i]; rh.ray.dir_z = rays.dz[i];
            rh.ray.tnear = rays.tnear[i]; rh.ray.tfar = rays.tfar[i];
            rh.ray.time = 0; rh.ray.mask = 0xffffffffu; rh.ray.id = unsigned(i); rh.ray.flags = 0;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(scene, &ctx, &rh);
            out.t[i] = rh.ray.tfar;
            out.u[i] = rh.hit.u;
            out.v[i] = rh.hit.v;
            out.geomId[i] = rh.hit.geomID;
            out.primId[i] = rh.hit.primID;
            out.instId[i] = rh.hit.instID[0];
        }
        benchmark::DoNotOptimize(out.t.data());
        benchmark::ClobberMemory();
    }
    setCounters(state, rays.size());
}

std::string benchName(const char* base, const std::string& scene, int width, bool coherent) {
    return std::string(base) + "/scene:" + scene + "/width:" + std::to_string(width) +
           "/coherent:" + (coherent ? "1" : "0");
}

void configure(benchmark::internal::Benchmark* b) {
    b->UseRealTime()->Unit(benchmark::kMillisecond)->MinTime(0.2);
}

// Registered in this order: per scene, the engine's widths then the raw baselines, coherent
// before incoherent, so that a run reads as one table per scene.
const bool kRegistered = [] {
    for (const char* scene : {"cornell", "million"}) {
        for (bool coherent : {true, false}) {
            for (int width : {1, 4, 8, 16}) {
                configure(benchmark::RegisterBenchmark(
                    benchName("BM_Intersect", scene, width, coherent).c_str(), intersectEngine,
                    std::string(scene), width, coherent));
            }
            configure(benchmark::RegisterBenchmark(
                benchName("BM_EmbreeRaw", scene, 1, coherent).c_str(), embreeRaw1,
                std::string(scene), coherent));
            configure(benchmark::RegisterBenchmark(
                benchName("BM_EmbreeRaw", scene, 16, coherent).c_str(), embreeRaw16,
                std::string(scene), coherent));
        }
    }
    return true;
}();

} // namespace
} // namespace rayproc::bench
