// Per-stage throughput on the Cornell box and the million-triangle scene, one thread each
// (inputs made by the pipeline itself, bench/stage_rig.h). Intersection at every packet width
// is in intersect_bench.cpp; kd-tree kNN and irradiance on a synthetic room in
// photon_bench.cpp; irradiance-cache lookups in irradiance_cache_bench.cpp.
//
//   BM_CameraKernel/scene:S    kernels::generateCameraRays alone over 256 tiles   rays/s
//   BM_CameraEmit/scene:S      CameraEmitter::emit, one pass of the scene's image   rays/s
//                              (stratified sub-pixel positions, payload, film sample count)
//   BM_Shading/scene:S/stage:surface   SurfaceStage::retrace on traced camera batches with
//                              raytrace mode's policy: hit resolution, emission, routing,
//                              light sampling and shadow-ray spawning (4 light samples)   rays/s
//   BM_Shading/scene:S/stage:path      PathStage::retrace on the same batches: NEE, MIS,
//                              BSDF sampling of the next ray   rays/s
//   BM_ShadowSpawn/scene:S     ShadowStage::spawn on the diffuse and glossy hits of traced
//                              camera batches: light sampling, one occlusion ray per sample
//                              (raytrace policy, 4 samples per area light)   rays/s spawned
//   BM_ShadowRetrace/scene:S   ShadowStage::retrace on traced shadow batches the surface
//                              stage spawned (film accumulation of the unoccluded)   rays/s
//   BM_PhotonTrace/scene:S     PhotonEmitter + PhotonStage through a 1-thread Pipeline,
//                              50K global-map photons per iteration   photons/s, rays/s
//   BM_Gather/scene:S          GatherStage::retrace on traced final-gather batches (the
//                              global map's precomputed irradiance at every hit)   rays/s,
//                              hit_fraction (gather rays that hit)
//   BM_SceneKnn/scene:S/k:64   PhotonMap::nearest at the gather rays' hit points, on the
//                              scene's own 200K-photon global map   queries/s
//   BM_SceneIcLookup/scene:S   IrradianceCache::lookup at diffuse first hits, on a cache
//                              filled on the scene like one level of gi's prepass (1/8 of
//                              the resolution)   lookups/s, hit_rate, records
#include "stage_rig.h"

#include "engine/path_state.h"
#include "engine/pipeline.h"
#include "gi/irradiance_cache.h"
#include "gi/gi_pipeline.h"
#include "gi/photon_emitter.h"
#include "gi/photon_map.h"
#include "gi/photon_stage.h"

#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace rayproc::bench {
namespace {

constexpr std::size_t kInputBatches = 64;

void setRate(benchmark::State& state, const char* name, double perIteration) {
    state.counters[name] =
        benchmark::Counter(perIteration * double(state.iterations()), benchmark::Counter::kIsRate);
}

void configure(benchmark::internal::Benchmark* b) {
    b->UseRealTime()->Unit(benchmark::kMicrosecond)->MinTime(0.2);
}

// ---- camera rays

void cameraKernel(benchmark::State& state, std::string sceneName) {
    const Camera& cam = nativeScene(sceneName).nativeCamera;
    kernels::CameraFrame frame = cameraFrame(cam);
    // Film positions and lens samples of a 16x16 tile, moved over 256 tiles of the image.
    constexpr int kTile = CameraEmitter::kTile, kTiles = 256;
    alignas(64) float fx[kBatchSize], fy[kBatchSize], lu[kBatchSize], lv[kBatchSize];
    alignas(64) float ox[kBatchSize], oy[kBatchSize], oz[kBatchSize];
    alignas(64) float dx[kBatchSize], dy[kBatchSize], dz[kBatchSize];
    for (int i = 0; i < kBatchSize; ++i) {
        std::uint64_t key = kernels::pathKey(1, std::uint32_t(i), 0);
        fx[i] = float(i % kTile) + kernels::uniform(key, 0);
        fy[i] = float(i / kTile) + kernels::uniform(key, 1);
        lu[i] = kernels::uniform(key, 2);
        lv[i] = kernels::uniform(key, 3);
    }
    int tilesX = std::max(1, cam.width / kTile);
    for (auto _ : state) {
        for (int t = 0; t < kTiles; ++t) {
            float sx = float((t % tilesX) * kTile), sy = float((t / tilesX) * kTile);
            for (int i = 0; i < kBatchSize; ++i) {
                fx[i] += sx;
                fy[i] += sy;
            }
            kernels::generateCameraRays(frame, kBatchSize, fx, fy, lu, lv, ox, oy, oz, dx, dy, dz);
            for (int i = 0; i < kBatchSize; ++i) {
                fx[i] -= sx;
                fy[i] -= sy;
            }
            benchmark::DoNotOptimize(dz[kBatchSize - 1]);
        }
    }
    setRate(state, "rays/s", double(kTiles) * kBatchSize);
}

void cameraEmit(benchmark::State& state, std::string sceneName) {
    StageRig rig(sceneName, raytracePolicy());
    CameraEmitter camera(rig.rc);
    for (auto _ : state) {
        camera.beginPass(0, 1);
        while (camera.emit(rig.ctx)) rig.drainAll();
    }
    const Camera& cam = rig.loaded.scene->camera;
    setRate(state, "rays/s", double(cam.width) * double(cam.height));
}

// ---- shading and shadow

void shading(benchmark::State& state, std::string sceneName, bool pathStage) {
    StageRig rig(sceneName, pathStage ? pathPolicy() : raytracePolicy());
    Batches inputs = rig.cameraBatches(kInputBatches);
    rig.trace(inputs);
    RetraceStage& stage =
        pathStage ? static_cast<RetraceStage&>(rig.path) : static_cast<RetraceStage&>(rig.surface);
    auto work = std::make_unique<RayBatch>();
    for (auto _ : state) {
        for (const auto& in : inputs) {
            *work = *in; // the stage may rewrite its input batch
            stage.retrace(*work, rig.ctx);
            rig.ctx.flush();
            rig.drainAll();
        }
    }
    setRate(state, "rays/s", double(rayCount(inputs)));
}

// The diffuse and glossy hits of each traced camera batch, as the surface stage lists them.
std::vector<std::unique_ptr<HitList>> directHits(const StageRig& rig, const Batches& batches) {
    std::vector<std::unique_ptr<HitList>> lists;
    const auto& materials = rig.loaded.scene->materials;
    for (const auto& b : batches) {
        auto list = std::make_unique<HitList>();
        for (int i = 0; i < b->count; ++i) {
            if (!b->hit(i)) continue;
            Vec3 o{b->ox[i], b->oy[i], b->oz[i]}, d{b->dx[i], b->dy[i], b->dz[i]};
            SurfaceHit h = rig.loaded.accel->surface(b->instId[i], b->geomId[i], b->primId[i],
                                                     b->u[i], b->v[i], o, d, b->t[i]);
            MaterialType type = materials[h.material].type;
            if (type == MaterialType::Diffuse || type == MaterialType::Glossy) list->add(i, h);
        }
        lists.push_back(std::move(list));
    }
    return lists;
}

void shadowSpawn(benchmark::State& state, std::string sceneName) {
    StageRig rig(sceneName, raytracePolicy());
    Batches cameras = rig.cameraBatches(kInputBatches);
    rig.trace(cameras);
    auto lists = directHits(rig, cameras);
    std::size_t points = 0;
    for (const auto& l : lists) points += std::size_t(l->count);
    std::uint64_t before = rig.stats.stages[int(StageId::Shadow)].raysOut;
    for (auto _ : state) {
        for (std::size_t k = 0; k < cameras.size(); ++k) {
            rig.shadow.spawn(*cameras[k], *lists[k], rig.ctx);
            rig.ctx.flush();
            rig.drainAll();
        }
    }
    double spawned = double(rig.stats.stages[int(StageId::Shadow)].raysOut - before);
    state.counters["rays/s"] = benchmark::Counter(spawned, benchmark::Counter::kIsRate);
    setRate(state, "points/s", double(points));
}

void shadowRetrace(benchmark::State& state, std::string sceneName) {
    StageRig rig(sceneName, raytracePolicy());
    Batches cameras = rig.cameraBatches(kInputBatches);
    rig.trace(cameras);
    ShadowBatches inputs =
        rig.spawned<ShadowBatch>(rig.surface, cameras, RayKind::Shadow, 4 * kInputBatches);
    for (auto _ : state) {
        for (const auto& in : inputs) rig.shadow.retraceShadows(*in, rig.ctx); // adds to film
    }
    setRate(state, "rays/s", double(rayCount(inputs)));
    state.counters["occluded"] = [&] {
        std::size_t n = 0;
        for (const auto& b : inputs)
            for (int i = 0; i < b->count; ++i) n += b->occluded(i) ? 1 : 0;
        return double(n) / double(std::max<std::size_t>(1, rayCount(inputs)));
    }();
}

// ---- photons and gather

struct PhotonRun {
    PhotonList photons;
    std::uint64_t raysTraced = 0;
};

PhotonRun tracePhotons(const std::string& sceneName, std::uint32_t count, int threads) {
    LoadedScene& s = nativeScene(sceneName);
    LightSet lights = LightSet::build(*s.scene, *s.accel);
    Film film(1, 1);
    ShadingPolicy policy;
    RenderContext rc{*s.scene, *s.accel, lights, policy, film, 1};
    Stats stats;
    PhotonStage stage(rc, false, GiSettings{}.maxPhotonDepth);
    Pipeline pipeline("photons", "photon", s.accel->root(), 16, stats, threads);
    pipeline.stage("photon", {kPhotonQueue}, stage);
    PhotonEmitter emitter(lights, s.scene->worldBounds(), count, 1, 1);
    pipeline.run(emitter, [] { return false; });
    return {stage.takePhotons(), stats.merged().raysTraced};
}

void photonTrace(benchmark::State& state, std::string sceneName) {
    constexpr std::uint32_t kPhotons = 50000;
    std::uint64_t rays = 0, stored = 0;
    for (auto _ : state) {
        PhotonRun run = tracePhotons(sceneName, kPhotons, 1);
        rays += run.raysTraced;
        stored += run.photons.size();
    }
    setRate(state, "photons/s", double(kPhotons));
    state.counters["rays/s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
    state.counters["stored/photon"] =
        double(stored) / double(kPhotons) / double(state.iterations());
}

// The scene's global photon map (200K photons, gi mode's default) with Christensen's
// precomputed irradiance, and the gi data the gather stage reads. Built once per scene.
struct SceneGi {
    PhotonMap global;
    GiData gi;
};

const SceneGi& sceneGi(const std::string& sceneName) {
    static std::map<std::string, std::unique_ptr<SceneGi>> cache;
    auto& slot = cache[sceneName];
    if (slot) return *slot;
    slot = std::make_unique<SceneGi>();
    GiSettings settings;
    settings.caustics = false;
    settings.irradianceCache = false; // every first diffuse hit makes a final gather
    slot->global.build(tracePhotons(sceneName, std::uint32_t(settings.photons), 0).photons);
    LoadedScene& s = nativeScene(sceneName);
    float diag = std::max(1e-6f, length(s.scene->worldBounds().diagonal()));
    slot->gi.settings = settings;
    slot->gi.globalRadius = 0.05f * diag; // gi mode's default
    slot->global.precomputeIrradiance(settings.globalK, slot->gi.globalRadius, 4);
    slot->gi.global = &slot->global;
    return *slot;
}

void gather(benchmark::State& state, std::string sceneName) {
    const SceneGi& g = sceneGi(sceneName);
    StageRig rig(sceneName, raytracePolicy(), &g.gi);
    Batches cameras = rig.cameraBatches(kInputBatches);
    rig.trace(cameras);
    Batches inputs = rig.spawned(rig.surface, cameras, kGatherRay, kInputBatches);
    for (auto _ : state) {
        for (const auto& in : inputs) rig.gather->retrace(*in, rig.ctx);
    }
    setRate(state, "rays/s", double(rayCount(inputs)));
    std::size_t hits = 0;
    for (const auto& b : inputs)
        for (int i = 0; i < b->count; ++i) hits += b->hit(i) ? 1 : 0;
    state.counters["hit_fraction"] =
        double(hits) / double(std::max<std::size_t>(1, rayCount(inputs)));
}

void sceneKnn(benchmark::State& state, std::string sceneName) {
    const SceneGi& g = sceneGi(sceneName);
    int k = int(state.range(0));
    std::vector<Vec3> points;
    {
        StageRig rig(sceneName, raytracePolicy(), &g.gi);
        Batches cameras = rig.cameraBatches(kInputBatches);
        rig.trace(cameras);
        Batches gathers = rig.spawned(rig.surface, cameras, kGatherRay, kInputBatches);
        const EmbreeScene& accel = *rig.loaded.accel;
        for (const auto& b : gathers)
            for (int i = 0; i < b->count; ++i)
                if (b->hit(i)) {
                    Vec3 o{b->ox[i], b->oy[i], b->oz[i]}, d{b->dx[i], b->dy[i], b->dz[i]};
                    points.push_back(accel
                                         .surface(b->instId[i], b->geomId[i], b->primId[i], b->u[i],
                                                  b->v[i], o, d, b->t[i])
                                         .p);
                }
    }
    if (points.empty()) {
        state.SkipWithError("no gather hits");
        return;
    }
    PhotonMap::Neighbours nb;
    std::size_t i = 0, found = 0;
    for (auto _ : state) {
        g.global.nearest(points[i++ % points.size()], k, g.gi.globalRadius, nb);
        found += nb.index.size();
    }
    setRate(state, "queries/s", 1.0);
    state.counters["found"] = double(found) / double(state.iterations());
}

// Ward's cache filled on the scene the way gi's prepass fills one level: camera rays at 1/8 of
// the scene's resolution; at each first diffuse hit a record from 64 final-gather rays
// (irradiance from the scene's global photon map at the gather hits, radius the harmonic mean
// distance clamped to gi's [0.005, 0.15] x diagonal), inserted in a fixed order. Lookups at
// the diffuse first hits of full-resolution camera rays (64 tiles), with their shading normals.
struct SceneCache {
    std::unique_ptr<IrradianceCache> cache;
    std::vector<std::pair<Vec3, Vec3>> queries; // (point, normal)
};

const SceneCache& sceneCache(const std::string& sceneName) {
    static std::map<std::string, std::unique_ptr<SceneCache>> cached;
    auto& slot = cached[sceneName];
    if (slot) return *slot;
    slot = std::make_unique<SceneCache>();
    GiData gi = sceneGi(sceneName).gi; // the global map for the gather rays
    LoadedScene& s = nativeScene(sceneName);
    float diag = std::max(1e-6f, length(s.scene->worldBounds().diagonal()));
    gi.icMinRadius = 0.005f * diag;
    gi.icMaxRadius = 0.15f * diag;
    IcRequests requests;
    Camera coarse = s.nativeCamera;
    coarse.width = std::max(1, coarse.width / 8);
    coarse.height = std::max(1, coarse.height / 8);
    requests.beginLevel(std::size_t(coarse.width) * coarse.height * 2);
    ShadingPolicy policy = raytracePolicy();
    policy.handlersOnly = true;
    {
        StageRig rig(sceneName, policy, &gi, &requests);
        CameraEmitter camera(rig.rc, &coarse);
        camera.beginPass(0, 1);
        while (camera.emit(rig.ctx)) {
            // Trace every queued batch and hand it to its stage until nothing is left.
            WorkBatch* b = nullptr;
            for (;;) {
                if (!rig.queue.tryPop(b)) {
                    if (!rig.ctx.flush()) break;
                    continue;
                }
                if (b->type == BatchType::Shadow) {
                    auto& shadows = static_cast<ShadowBatch&>(*b);
                    rig.intersector.trace(shadows, rig.stats);
                    if (b->kind == kGatherShadowRay) rig.gather->retraceShadows(shadows, rig.ctx);
                } else {
                    auto& rays = static_cast<RayBatch&>(*b);
                    rig.intersector.trace(rays, rig.stats);
                    if (b->kind == kGatherRay) rig.gather->retrace(rays, rig.ctx);
                    else rig.surface.retrace(rays, rig.ctx);
                }
                rig.pool.release(b);
            }
        }
    }
    std::vector<IrradianceRecord> records;
    std::size_t n = requests.claimed();
    for (std::size_t i = 0; i < n; ++i) {
        const IcRequest& r = requests[std::uint32_t(i)];
        double rays = r.rays.load();
        if (rays <= 0) continue;
        IrradianceRecord rec;
        rec.position = r.position;
        rec.normal = r.normal;
        for (int c = 0; c < 3; ++c)
            rec.irradiance[c] =
                float(kPi * double(r.radiance[c].load()) / IcRequest::kScale / rays);
        double inv = double(r.inverseDistance.load()) / IcRequest::kScale;
        float harmonic = inv > 0 ? float(rays / inv) : gi.icMaxRadius;
        rec.radius = std::clamp(harmonic, gi.icMinRadius, gi.icMaxRadius);
        records.push_back(rec);
    }
    IrradianceCacheSettings cs;
    cs.accuracy = GiSettings{}.icAccuracy;
    slot->cache = std::make_unique<IrradianceCache>(s.scene->worldBounds(), cs);
    slot->cache->insert(records);

    StageRig rig(sceneName, raytracePolicy());
    Batches cameras = rig.cameraBatches(kInputBatches);
    rig.trace(cameras);
    for (const auto& b : cameras)
        for (int i = 0; i < b->count; ++i) {
            if (!b->hit(i)) continue;
            Vec3 o{b->ox[i], b->oy[i], b->oz[i]}, d{b->dx[i], b->dy[i], b->dz[i]};
            SurfaceHit h = rig.loaded.accel->surface(b->instId[i], b->geomId[i], b->primId[i],
                                                     b->u[i], b->v[i], o, d, b->t[i]);
            if (rig.loaded.scene->materials[h.material].type != MaterialType::Diffuse) continue;
            Vec3 ng, ns;
            facingNormals(h, -d, ng, ns);
            slot->queries.push_back({h.p, ns});
        }
    return *slot;
}

void sceneIcLookup(benchmark::State& state, std::string sceneName) {
    const SceneCache& c = sceneCache(sceneName);
    if (c.queries.empty() || c.cache->size() == 0) {
        state.SkipWithError("no records or no diffuse hits");
        return;
    }
    IrradianceCache::LookupResult r;
    std::size_t i = 0, hits = 0;
    for (auto _ : state) {
        const auto& q = c.queries[i++ % c.queries.size()];
        hits += c.cache->lookup(q.first, q.second, r) ? 1 : 0;
    }
    setRate(state, "lookups/s", 1.0);
    state.counters["hit_rate"] = double(hits) / double(state.iterations());
    state.counters["records"] = double(c.cache->size());
}

const bool kRegistered = [] {
    for (const char* scene : {"cornell", "million"}) {
        std::string s = std::string("/scene:") + scene;
        configure(benchmark::RegisterBenchmark(("BM_CameraKernel" + s).c_str(), cameraKernel,
                                               std::string(scene)));
        configure(benchmark::RegisterBenchmark(("BM_CameraEmit" + s).c_str(), cameraEmit,
                                               std::string(scene)));
        configure(benchmark::RegisterBenchmark(("BM_Shading" + s + "/stage:surface").c_str(),
                                               shading, std::string(scene), false));
        configure(benchmark::RegisterBenchmark(("BM_Shading" + s + "/stage:path").c_str(), shading,
                                               std::string(scene), true));
        configure(benchmark::RegisterBenchmark(("BM_ShadowSpawn" + s).c_str(), shadowSpawn,
                                               std::string(scene)));
        configure(benchmark::RegisterBenchmark(("BM_ShadowRetrace" + s).c_str(), shadowRetrace,
                                               std::string(scene)));
        configure(benchmark::RegisterBenchmark(("BM_PhotonTrace" + s).c_str(), photonTrace,
                                               std::string(scene)));
        configure(
            benchmark::RegisterBenchmark(("BM_Gather" + s).c_str(), gather, std::string(scene)));
        configure(benchmark::RegisterBenchmark(("BM_SceneIcLookup" + s).c_str(), sceneIcLookup,
                                               std::string(scene)));
        auto* knn =
            benchmark::RegisterBenchmark(("BM_SceneKnn" + s).c_str(), sceneKnn, std::string(scene));
        configure(knn);
        knn->ArgName("k")->Arg(64);
    }
    return true;
}();

} // namespace
} // namespace rayproc::bench
