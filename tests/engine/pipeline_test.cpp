// The pipeline builder (engine/pipeline.h): each queue's rays reach the stage listed for them,
// traced as the queue says; a kind no stage takes ends the run with a message that names it;
// the pipeline describes itself in order, and counts what each queue carried.
#include "engine/pipeline.h"

#include "../analytic/analytic.h"

#include <atomic>
#include <map>
#include <string>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// One batch of `count` rays of each of `kinds`, from the centre out through the wall.
class KindsEmitter : public Emitter {
public:
    KindsEmitter(std::vector<RayKind> kinds, int count) : m_kinds(std::move(kinds)), m_count(count) {}
    bool emit(StageContext& ctx) override {
        if (m_done.exchange(true)) return false;
        for (RayKind kind : m_kinds) {
            const bool occlusion = kind == RayKind::Shadow || kind == modeRayKind(3);
            WorkBatch& b = occlusion ? static_cast<WorkBatch&>(ctx.outShadow(kind)) : ctx.out(kind);
            for (int i = 0; i < m_count; ++i) b.push(0, 0, 0, 0, 0, -1, 0.0f, 100.0f);
            ctx.flush(kind);
        }
        return true;
    }

private:
    std::vector<RayKind> m_kinds;
    int m_count;
    std::atomic<bool> m_done{false};
};

// Keeps the kinds it is handed (in kind order: the queue pops rays in flight before an
// emitter's) and how their first ray was traced.
class RecordingStage : public RetraceStage {
public:
    struct Traced {
        bool occluded, hit;
    };
    void retrace(RayBatch& b, StageContext&) override { traced[b.kind] = {false, b.hit(0)}; }
    void retraceShadows(ShadowBatch& b, StageContext&) override {
        traced[b.kind] = {b.occluded(0), false};
    }
    std::vector<RayKind> kinds() const {
        std::vector<RayKind> out;
        for (const auto& [kind, how] : traced) out.push_back(kind);
        return out;
    }
    std::map<RayKind, Traced> traced;
};

struct SphereScene {
    std::unique_ptr<Scene> scene = sceneFromJson(kClosedSphere);
    EmbreeScene accel{*scene};
};

constexpr RayRoute kProbeQueue{modeRayKind(1), "probe", BatchType::Rays};
constexpr RayRoute kProbeShadowQueue{modeRayKind(3), "probe-shadow", BatchType::Shadow};

} // namespace

TEST_CASE("Pipeline: each queue's rays reach the stage listed for them, traced as it says",
          "[engine][pipeline]") {
    SphereScene s;
    Stats stats;
    Pipeline pipeline("test", "kinds", s.accel.root(), GENERATE(1, 8), stats, 1);
    RecordingStage radiance, shadow, probe;
    pipeline
        .stage("radiance", {engineRoute(RayKind::Camera), engineRoute(RayKind::Reflection)},
               radiance)
        .stage("shadow", {engineRoute(RayKind::Shadow)}, shadow)
        .stage("probe", {kProbeQueue, kProbeShadowQueue}, probe);
    KindsEmitter emitter({RayKind::Camera, RayKind::Shadow, modeRayKind(1), RayKind::Reflection,
                          modeRayKind(3)},
                         3);
    pipeline.run(emitter, [] { return false; });
    CHECK(radiance.kinds() == std::vector<RayKind>{RayKind::Camera, RayKind::Reflection});
    CHECK(shadow.kinds() == std::vector<RayKind>{RayKind::Shadow});
    REQUIRE(probe.kinds() == std::vector<RayKind>{modeRayKind(1), modeRayKind(3)});
    // Closest-hit queues find the wall; occlusion queues only say the ray is blocked.
    CHECK(radiance.traced[RayKind::Camera].hit);
    CHECK(radiance.traced[RayKind::Reflection].hit);
    CHECK(shadow.traced[RayKind::Shadow].occluded);
    CHECK(probe.traced[modeRayKind(1)].hit);
    CHECK_FALSE(probe.traced[modeRayKind(1)].occluded);
    CHECK(probe.traced[modeRayKind(3)].occluded);
    // Each queue counted its batch and rays; an unrouted kind none.
    const ThreadStats t = stats.merged();
    for (RayKind k : {RayKind::Camera, RayKind::Reflection, RayKind::Shadow, modeRayKind(1),
                      modeRayKind(3)}) {
        INFO("kind " << int(k));
        CHECK(t.queues[int(k)].batches == 1);
        CHECK(t.queues[int(k)].rays == 3);
    }
    CHECK(t.queues[int(RayKind::Refraction)].batches == 0);
}

TEST_CASE("Pipeline: a kind that no stage takes is an error that names it, not a crash",
          "[engine][pipeline]") {
    SphereScene s;
    Stats stats;
    Pipeline pipeline("test", "kinds", s.accel.root(), 8, stats, GENERATE(1, 2));
    RecordingStage radiance;
    pipeline.stage("radiance", {engineRoute(RayKind::Camera)}, radiance);
    KindsEmitter emitter({RayKind::Camera, RayKind::Shadow}, 2);
    std::string message;
    try {
        pipeline.run(emitter, [] { return false; });
    } catch (const PipelineError& e) {
        message = e.what();
    }
    INFO(message);
    CHECK(message.find("pipeline test") != std::string::npos);
    CHECK(message.find("rays of kind shadow but no stage takes them") != std::string::npos);
    CHECK(message.find("radiance [camera]") != std::string::npos);
    // The pipeline runs again once the kind has its stage.
    RecordingStage shadow;
    pipeline.stage("shadow", {engineRoute(RayKind::Shadow)}, shadow);
    KindsEmitter again({RayKind::Camera, RayKind::Shadow}, 2);
    pipeline.run(again, [] { return false; });
    CHECK(shadow.kinds() == std::vector<RayKind>{RayKind::Shadow});
}

TEST_CASE("Pipeline: a kind listed for two stages is refused with both names",
          "[engine][pipeline]") {
    SphereScene s;
    Stats stats;
    Pipeline pipeline("test", "kinds", s.accel.root(), 8, stats, 1);
    RecordingStage a, b;
    pipeline.stage("first", {engineRoute(RayKind::Camera)}, a);
    CHECK(pipeline.routes(RayKind::Camera));
    CHECK_FALSE(pipeline.routes(RayKind::Shadow));
    CHECK_THROWS_WITH(pipeline.stage("second", {engineRoute(RayKind::Camera)}, b),
                      Catch::Matchers::Contains("camera rays go to stage first already") &&
                          Catch::Matchers::Contains("second"));
}

TEST_CASE("Pipeline: it describes its stages in order with their queues", "[engine][pipeline]") {
    SphereScene s;
    Stats stats;
    Pipeline pipeline("render", "camera", s.accel.root(), 16, stats, 1);
    RecordingStage surface, shadow;
    pipeline
        .stage("surface", {engineRoute(RayKind::Camera), engineRoute(RayKind::Reflection)},
               surface)
        .stage("shadow", {engineRoute(RayKind::Shadow)}, shadow)
        .stage("probe", {kProbeQueue, kProbeShadowQueue}, std::make_unique<RecordingStage>());
    CHECK(pipeline.describe() ==
          "camera emitter -> queue -> intersect (packets of 16) -> surface [camera, reflection] "
          "-> shadow [shadow: occlusion] -> probe [probe, probe-shadow: occlusion]");
    const PipelineLayout& layout = pipeline.layout();
    REQUIRE(layout.stages.size() == 3);
    CHECK(layout.stages[0].name == "surface");
    CHECK(layout.stages[2].queues[1].name == "probe-shadow");
    CHECK(layout.stages[2].queues[1].occlusion);

    // After a run the Stats knows the pipeline, and the table prints it with its counts.
    KindsEmitter emitter({RayKind::Camera, RayKind::Shadow}, 5);
    pipeline.run(emitter, [] { return false; });
    REQUIRE(stats.pipelines().size() == 1);
    RenderStats r;
    r.totals = stats.merged();
    r.pipelines = stats.pipelineRuns(r.totals);
    const std::string table = r.toTable();
    INFO(table);
    CHECK(table.find("pipeline render: camera emitter -> queue -> intersect") !=
          std::string::npos);
    CHECK(table.find("  surface          camera           closest               1              5") !=
          std::string::npos);
    CHECK(table.find("  shadow           shadow           occlusion             1              5") !=
          std::string::npos);
    CHECK(table.find("  probe            probe-shadow     occlusion             0              0") !=
          std::string::npos);
}

TEST_CASE("Pipeline: one of the same name built again adds its new stages to the first",
          "[engine][pipeline]") {
    PipelineLayout first{"refine", "record", 8, {{"gather", {{modeRayKind(1), "gather", false}}}}};
    PipelineLayout second{"refine", "record", 8,
                          {{"gather", {{modeRayKind(1), "gather", false},
                                       {modeRayKind(2), "gather-shadow", true}}},
                           {"correction", {{modeRayKind(3), "correction", false}}}}};
    Stats stats;
    stats.addPipeline(first);
    stats.addPipeline(second);
    stats.addPipeline(first);
    REQUIRE(stats.pipelines().size() == 1);
    const PipelineLayout& p = stats.pipelines()[0];
    CHECK(pipelineShape(p) == "record emitter -> queue -> intersect (packets of 8) -> gather "
                              "[gather, gather-shadow: occlusion] -> correction [correction]");
}

TEST_CASE("Pipeline: each run is one entry of the Workers phase it is timed as",
          "[engine][pipeline]") {
    SphereScene s;
    Stats stats;
    PhaseLog log;
    Pipeline pipeline("test", "kinds", s.accel.root(), 8, stats, 2);
    RecordingStage radiance;
    pipeline.stage("radiance", {engineRoute(RayKind::Camera)}, radiance)
        .timedAs(&log, "test_passes");
    for (int run = 0; run < 3; ++run) {
        KindsEmitter emitter({RayKind::Camera}, 4);
        pipeline.run(emitter, [] { return false; });
    }
    REQUIRE(log.phases().size() == 1);
    const PhaseStats& phase = log.phases()[0];
    CHECK(phase.name == "test_passes");
    CHECK(phase.kind == PhaseKind::Workers);
    CHECK(phase.count == 3);
    CHECK(phase.threads == 2);
    CHECK(phase.seconds > 0);
}
