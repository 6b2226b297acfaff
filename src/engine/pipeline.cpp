#include "engine/pipeline.h"

#include <utility>

namespace rayproc {

Pipeline::Pipeline(std::string name, std::string emitter, RTCScene scene, int packetWidth,
                   Stats& stats, int threads)
    : m_stats(stats), m_intersector(scene, packetWidth),
      m_processor(m_intersector, stats, threads) {
    m_layout.name = std::move(name);
    m_layout.emitter = std::move(emitter);
    m_layout.packetWidth = packetWidth;
}

bool Pipeline::routes(RayKind kind) const {
    for (const StageLayout& s : m_layout.stages)
        for (const QueueLayout& q : s.queues)
            if (q.kind == kind) return true;
    return false;
}

Pipeline& Pipeline::stage(std::string name, std::vector<RayRoute> queues, RetraceStage& stage) {
    StageLayout layout{std::move(name), {}};
    for (const RayRoute& route : queues) {
        for (const StageLayout& s : m_layout.stages)
            for (const QueueLayout& q : s.queues)
                if (q.kind == route.kind)
                    throw PipelineError("pipeline " + m_layout.name + ": the " + route.name +
                                        " rays go to stage " + s.name +
                                        " already, not also to " + layout.name);
        m_processor.setStage(route.kind, &stage, route.batch);
        layout.queues.push_back(
            {route.kind, route.name, queryOf(route.batch) == RayQuery::Occlusion});
    }
    m_layout.stages.push_back(std::move(layout));
    return *this;
}

Pipeline& Pipeline::stage(std::string name, std::vector<RayRoute> queues,
                          std::unique_ptr<RetraceStage> stage) {
    RetraceStage& borrowed = *stage;
    m_owned.push_back(std::move(stage));
    return this->stage(std::move(name), std::move(queues), borrowed);
}

Pipeline& Pipeline::timedAs(PhaseLog* log, std::string phase) {
    m_phases = log;
    m_phase = std::move(phase);
    return *this;
}

void Pipeline::run(Emitter& emitter, const std::function<bool()>& stopEmitting) {
    // --stats lists the pipelines counted into this Stats (a shape built again under the
    // same name adds its new stages to the first).
    m_stats.addPipeline(m_layout);
    try {
        timeWorkers(m_phases, m_phase, m_stats, m_processor.threads(),
                    [&] { m_processor.run(emitter, stopEmitting); });
    } catch (const UnroutedRayKind& e) {
        throw PipelineError("pipeline " + m_layout.name + ": a stage spawned rays of kind " +
                            rayKindName(e.kind) + " but no stage takes them (" +
                            describe() + ")");
    }
}

std::string Pipeline::describe() const { return pipelineShape(m_layout); }

} // namespace rayproc
