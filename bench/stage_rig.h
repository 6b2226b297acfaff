// A stand-alone copy of the render pipeline's stages for the per-stage benchmarks: one scene
// at its own resolution, the raytrace or path shading policy, a film, one StageContext with
// its queue and pool, the Intersector (packets of 16) and every retrace stage, all on the
// benchmark's one thread. Inputs are made by the pipeline itself: camera batches from the
// CameraEmitter, traced; shadow and gather batches as the surface stage spawns them, traced.
// So a stage benchmark times the stage on the batches it receives in a render.
#pragma once

#include "bench_scenes.h"

#include "engine/camera_emitter.h"
#include "engine/film.h"
#include "engine/intersect.h"
#include "engine/path_stage.h"
#include "engine/ray_queue.h"
#include "engine/reflection_stage.h"
#include "engine/refraction_stage.h"
#include "engine/shadow_stage.h"
#include "engine/stage.h"
#include "engine/stats.h"
#include "engine/surface_stage.h"
#include "gi/gather_stage.h"
#include "gi/gi_context.h"
#include "lighting/light_set.h"

#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace rayproc::bench {

template <class B> using BatchesOf = std::vector<std::unique_ptr<B>>;
using Batches = BatchesOf<RayBatch>;
using ShadowBatches = BatchesOf<ShadowBatch>;

inline LoadedScene& nativeScene(const std::string& name) {
    LoadedScene& s = loadedScene(name);
    s.scene->camera = s.nativeCamera; // other benchmarks resize it
    return s;
}

// raytrace mode's defaults (spp 1 here: one camera pass per benchmark input).
inline ShadingPolicy raytracePolicy() {
    ShadingPolicy p;
    p.maxDepth = 8;
    p.lightSamples = 4;
    return p;
}

// path mode's defaults.
inline ShadingPolicy pathPolicy() {
    ShadingPolicy p;
    p.maxDepth = 64;
    p.rrStartDepth = 3;
    p.sppTotal = 1;
    return p;
}

struct StageRig {
    LoadedScene& loaded;
    LightSet lights;
    ShadingPolicy policy;
    Film film;
    RenderContext rc;
    RayQueue queue;
    BatchPool pool;
    StageContext ctx;
    ThreadStats stats;
    Intersector intersector;
    ShadowStage shadow;
    ReflectionStage reflection;
    RefractionStage refraction;
    std::optional<GatherStage> gather; // with gi's data: the surface stage's diffuse handler
    SurfaceStage surface;
    PathStage path;

    // With `gi` the surface stage hands diffuse hits to a gather stage (its prepass's when
    // `requests` is given).
    StageRig(const std::string& sceneName, const ShadingPolicy& p, const GiData* gi = nullptr,
             IcRequests* requests = nullptr)
        : loaded(nativeScene(sceneName)), lights(LightSet::build(*loaded.scene, *loaded.accel)),
          policy(p), film(loaded.scene->camera.width, loaded.scene->camera.height),
          rc{*loaded.scene, *loaded.accel, lights, policy, film, 1}, ctx(queue, pool),
          intersector(loaded.accel->root(), 16), shadow(rc), reflection(rc), refraction(rc),
          surface(rc, shadow, reflection, refraction), path(rc) {
        if (gi) {
            gather.emplace(rc, *gi, requests);
            surface.addDiffuseHandler(*gather);
        }
        ctx.stats = &stats;
    }
    ~StageRig() {
        ctx.flush();
        drainAll();
    }
    StageRig(const StageRig&) = delete;

    // Pops every queued batch and returns it to the pool.
    void drainAll() { drain(RayKind::Camera, 0); }
    // Pops every queued batch; keeps copies of those of `kind`, at most `keep` of them
    // (appended to `out` when given; their type is the kind's); returns them to the pool.
    template <class B = RayBatch>
    void drain(RayKind kind, std::size_t keep, BatchesOf<B>* out = nullptr) {
        WorkBatch* b = nullptr;
        while (queue.tryPop(b)) {
            if (out && b->kind == kind && out->size() < keep)
                out->push_back(std::make_unique<B>(static_cast<const B&>(*b)));
            pool.release(b);
        }
    }

    // Camera batches (tiles) of one pass, spread evenly over the image, untraced.
    Batches cameraBatches(std::size_t count) {
        CameraEmitter camera(rc);
        camera.beginPass(0, 1);
        std::uint64_t units = camera.unitsPerPass();
        std::uint64_t stride = std::max<std::uint64_t>(1, units / count);
        Batches out;
        for (std::uint64_t u = 0; camera.emit(ctx); ++u) {
            if (u % stride == 0)
                drain(RayKind::Camera, count, &out);
            else
                drainAll();
        }
        return out;
    }

    template <class B> void trace(BatchesOf<B>& batches) {
        for (auto& b : batches) intersector.trace(*b, stats);
    }

    // The batches of `kind` that `stage` spawns from each of `inputs` (retraced on copies),
    // at most `keep`, traced; B is the kind's type (ShadowBatch for occlusion rays).
    template <class B = RayBatch>
    BatchesOf<B> spawned(RetraceStage& stage, const Batches& inputs, RayKind kind,
                         std::size_t keep) {
        BatchesOf<B> out;
        auto work = std::make_unique<RayBatch>();
        for (const auto& in : inputs) {
            if (out.size() >= keep) break;
            *work = *in;
            stage.retrace(*work, ctx);
            ctx.flush();
            drain<B>(kind, keep, &out);
        }
        trace(out);
        return out;
    }
};

template <class B> std::size_t rayCount(const BatchesOf<B>& batches) {
    std::size_t n = 0;
    for (const auto& b : batches) n += std::size_t(b->count);
    return n;
}

} // namespace rayproc::bench
