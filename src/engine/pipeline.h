// The pipeline: the one place a pass builds its ray processor, its intersector and the routes
// from ray kinds to retrace stages. A pass names its emitter and lists its stages in order,
// each with the queues (ray kinds) that feed it and how their rays are traced:
//
//     emitter -> queue -> intersect -> stage 1 [kinds], stage 2 [kinds], ...
//
// and the pipeline describes itself so (--stats prints each pipeline of a render with the
// batches and rays each queue carried). Every pass of every mode builds through it: the
// render job's camera passes (so serve, bench and MPI runs), gi's photon passes, the
// irradiance cache's prepass and refinement.
#pragma once

#include "engine/intersect.h"
#include "engine/phases.h"
#include "engine/processor.h"
#include "engine/stats.h"

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace rayproc {

// A pipeline that cannot be built as listed, or a stage that spawned rays of a kind no stage
// of the pipeline takes: the message names the pipeline and its stages.
class PipelineError : public std::logic_error {
public:
    using std::logic_error::logic_error;
};

class Pipeline {
public:
    // A pipeline named `name` ("render", "photons", ...) fed by the emitter named `emitter`,
    // tracing on `scene` with packets of `packetWidth`, run on `threads` workers.
    Pipeline(std::string name, std::string emitter, RTCScene scene, int packetWidth,
             Stats& stats, int threads);
    Pipeline(const Pipeline&) = delete;
    Pipeline& operator=(const Pipeline&) = delete;

    // Appends a stage fed by `queues`. The stage is borrowed (it must outlive the pipeline's
    // runs) or owned. A kind that another stage already takes is a PipelineError.
    Pipeline& stage(std::string name, std::vector<RayRoute> queues, RetraceStage& stage);
    Pipeline& stage(std::string name, std::vector<RayRoute> queues,
                    std::unique_ptr<RetraceStage> stage);
    // Whether some stage takes the rays of `kind`.
    bool routes(RayKind kind) const;
    // Times every run as an entry of the Workers phase `phase` in `log` (engine/phases.h:
    // "render_passes", "photon_tracing"...; --stats' phase table); a null log times nothing.
    Pipeline& timedAs(PhaseLog* log, std::string phase);

    // Drains the emitter and the work it causes (RayProcessor::run), timed as timedAs says.
    // A batch of a kind that no stage takes ends the run with a PipelineError that names it.
    void run(Emitter& emitter, const std::function<bool()>& stopEmitting);

    int threads() const { return m_processor.threads(); }
    const Intersector& intersector() const { return m_intersector; }
    std::size_t batchesAllocated() const { return m_processor.batchesAllocated(); }

    // The pipeline's shape: its stages in order with their queues.
    const PipelineLayout& layout() const { return m_layout; }
    // One line: "camera emitter -> queue -> intersect (packets of 8) -> surface [camera,
    // reflection] -> shadow [shadow: occlusion]".
    std::string describe() const;

private:
    Stats& m_stats;
    Intersector m_intersector;
    RayProcessor m_processor;
    PipelineLayout m_layout;
    PhaseLog* m_phases = nullptr;
    std::string m_phase;
    std::vector<std::unique_ptr<RetraceStage>> m_owned;
};

} // namespace rayproc
