// The ray processor when a stage throws (out of memory mid-pass): every worker must stop and
// run() rethrow, whatever the other workers were doing. A worker that threw used to leave the
// busy count raised, and the others spun in their wait for it forever (a 1.4 GiB cap on a
// 6M-photon gi render: no exit in 100 s; now "out of memory" in 1.6 s).
#include "engine/intersect.h"
#include "engine/processor.h"
#include "gi/gi_pipeline.h"
#include "gi/photon_emitter.h"
#include "gi/photon_stage.h"

#include "../analytic/analytic.h"

#include <atomic>
#include <chrono>
#include <future>
#include <new>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// The photon stage, except that the n-th batch it is handed throws std::bad_alloc.
class FailingStage : public RetraceStage {
public:
    FailingStage(RetraceStage& inner, int failAt) : m_inner(inner), m_failAt(failAt) {}
    void retracePhotons(PhotonBatch& batch, StageContext& ctx) override {
        if (m_seen.fetch_add(1) + 1 == m_failAt) throw std::bad_alloc();
        m_inner.retracePhotons(batch, ctx);
    }

private:
    RetraceStage& m_inner;
    int m_failAt;
    std::atomic<int> m_seen{0};
};

// Runs the processor on another thread: 0 when it completes, 1 when it rethrows bad_alloc. A
// run that does not return within a minute fails the test and ends the process (its workers
// would keep it alive).
int runWithin(RayProcessor& processor, Emitter& emitter) {
    auto run = std::async(std::launch::async, [&] {
        try {
            processor.run(emitter, [] { return false; });
        } catch (const std::bad_alloc&) {
            return 1;
        }
        return 0;
    });
    if (run.wait_for(std::chrono::seconds(60)) != std::future_status::ready) {
        FAIL_CHECK("run() did not return within 60 s: the workers wait for each other");
        std::_Exit(1);
    }
    return run.get();
}

} // namespace

TEST_CASE("Ray processor: a stage's exception stops every worker and run() rethrows it",
          "[engine][processor]") {
    auto scene = sceneFromJson(kClosedSphere);
    EmbreeScene accel(*scene);
    LightSet lights = LightSet::build(*scene, accel);
    Film film(1, 1);
    ShadingPolicy policy;
    RenderContext rc{*scene, accel, lights, policy, film, 1};
    Intersector intersector(accel.root(), 16);
    Stats stats;
    const int threads = GENERATE(1, 2, 4);
    const int failAt = GENERATE(1, 7, 40);
    INFO(threads << " threads, failing at batch " << failAt);
    RayProcessor processor(intersector, stats, threads);
    PhotonStage photons(rc, /*causticPass=*/false, 16);
    FailingStage failing(photons, failAt);
    processor.setStage(kPhotonRay, &failing, BatchType::Photons);
    PhotonEmitter emitter(lights, scene->worldBounds(), 200000, 1, 1);
    CHECK(runWithin(processor, emitter) == 1);

    // The processor is usable again: a run that does not fail completes.
    FailingStage never(photons, -1);
    processor.setStage(kPhotonRay, &never, BatchType::Photons);
    PhotonEmitter again(lights, scene->worldBounds(), 1000, 2, 1);
    CHECK(runWithin(processor, again) == 0);
}

namespace {

// One batch of `kind`: a ray from the sphere's centre out through its wall.
class OneBatchEmitter : public Emitter {
public:
    // `type`: the batch the ray travels in.
    OneBatchEmitter(RayKind kind, BatchType type) : m_kind(kind), m_type(type) {}
    bool emit(StageContext& ctx) override {
        if (m_done.exchange(true)) return false;
        open(ctx).push(0, 0, 0, 0, 0, -1, 0.0f, 100.0f);
        ctx.flush(m_kind);
        return true;
    }

private:
    WorkBatch& open(StageContext& ctx) {
        switch (m_type) {
        case BatchType::Shadow: return ctx.outShadow(m_kind);
        case BatchType::Photons: return ctx.outPhotons(m_kind);
        case BatchType::Rays: break;
        }
        return ctx.out(m_kind);
    }
    RayKind m_kind;
    BatchType m_type;
    std::atomic<bool> m_done{false};
};

// Keeps what the intersection handler wrote into the one ray it is handed, and the type of
// the batch the stage was handed.
class ResultStage : public RetraceStage {
public:
    void retrace(RayBatch& b, StageContext&) override { took(b, b.hit(0)); }
    void retraceShadows(ShadowBatch& b, StageContext&) override {
        occluded = b.occluded(0);
        took(b, false);
    }
    void retracePhotons(PhotonBatch& b, StageContext&) override { took(b, b.hit(0)); }
    bool occluded = false, hit = false;
    BatchType type = BatchType::Rays;
    int batches = 0;

private:
    void took(const WorkBatch& b, bool h) {
        hit = h;
        type = b.type;
        ++batches;
    }
};

const char* typeName(BatchType t) {
    return t == BatchType::Shadow ? "occlusion rays" : t == BatchType::Photons ? "photons" : "rays";
}

} // namespace

TEST_CASE("A mode's ray kind travels and is traced as its route says: rays and photons to "
          "their closest hit, occlusion rays",
          "[engine][processor]") {
    auto scene = sceneFromJson(kClosedSphere);
    EmbreeScene accel(*scene);
    Intersector intersector(accel.root(), GENERATE(1, 16));
    Stats stats;
    RayProcessor processor(intersector, stats, 1);
    const RayKind kind = modeRayKind(2);
    const BatchType type = GENERATE(BatchType::Rays, BatchType::Shadow, BatchType::Photons);
    const bool occlusion = type == BatchType::Shadow;
    INFO(typeName(type) << ", width " << intersector.width());
    ResultStage result;
    processor.setStage(kind, &result, type);
    OneBatchEmitter emitter(kind, type);
    processor.run(emitter, [] { return false; });
    REQUIRE(result.batches == 1);
    CHECK(result.type == type);
    // An occlusion query writes only tfar (negative: occluded); a closest-hit query writes the
    // hit (the wall) and leaves tfar.
    CHECK(result.occluded == occlusion);
    const ThreadStats t = stats.merged();
    CHECK(t.stages[int(StageId::Occlude)].raysIn == (occlusion ? 1u : 0u));
    CHECK(t.stages[int(StageId::Intersect)].raysIn == (occlusion ? 0u : 1u));
    if (!occlusion) CHECK(result.hit);
}

TEST_CASE("A batch of another type than its kind's route is refused: each queue takes only "
          "the batches its route names",
          "[engine][processor]") {
    auto scene = sceneFromJson(kClosedSphere);
    EmbreeScene accel(*scene);
    Intersector intersector(accel.root(), 16);
    Stats stats;
    RayProcessor processor(intersector, stats, 1);
    const RayKind kind = modeRayKind(2);
    const BatchType route = GENERATE(BatchType::Rays, BatchType::Shadow, BatchType::Photons);
    const BatchType given = BatchType((int(route) + GENERATE(1, 2)) % kBatchTypeCount);
    INFO("a route of " << typeName(route) << " given " << typeName(given));
    ResultStage result;
    processor.setStage(kind, &result, route);
    OneBatchEmitter emitter(kind, given);
    CHECK_THROWS_WITH(processor.run(emitter, [] { return false; }),
                      Catch::Matchers::Contains("another type than its route's"));
    CHECK(result.batches == 0);
}
