// The ray processor (Farnsworth & Erbacher's "centralized ray processor"): emitters push ray
// batches into the central queue; TBB tasks drain it, hand each batch to the one intersection
// handler, then to the retrace stage of the batch's ray kind (by the batch's type: rays,
// occlusion rays or photons), which pushes the rays it spawns back into the queue. Ray depth
// never recurses on the C++ stack.
#pragma once

#include "engine/intersect.h"
#include "engine/ray_queue.h"
#include "engine/stage.h"
#include "engine/stats.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/task_arena.h>

#include <array>
#include <atomic>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>

namespace rayproc {

// A batch of a kind that no stage takes: run() rethrows it (the pipeline names its stages).
class UnroutedRayKind : public std::logic_error {
public:
    explicit UnroutedRayKind(RayKind kind);
    RayKind kind;
};

class RayProcessor {
public:
    RayProcessor(const Intersector& intersector, Stats& stats, int threads);

    // Routes the rays of `kind` to `stage` (null: no stage; a batch of that kind ends the
    // run with UnroutedRayKind), in batches of type `type`, which also says how they are
    // traced (a mode's occlusion and photon kinds say so here). Passes build their processor
    // through a Pipeline (engine/pipeline.h).
    void setStage(RayKind kind, RetraceStage* stage, BatchType type) {
        m_stages[int(kind)] = stage;
        m_types[int(kind)] = type;
    }
    void setStage(RayKind kind, RetraceStage* stage) {
        setStage(kind, stage, defaultBatchType(kind));
    }
    int threads() const { return m_threads; }
    std::size_t batchesAllocated() const { return m_pool.allocated(); }

    // Drains the emitter and all the work it causes. `stopEmitting` is polled before each
    // emission (cancel); work already in flight is always finished, so every emitted sample
    // is complete when run() returns. When a stage or the emitter throws (out of memory),
    // every worker stops, the run's rays are dropped and run() rethrows the first exception.
    void run(Emitter& emitter, const std::function<bool()>& stopEmitting);

private:
    void worker(Emitter& emitter, const std::function<bool()>& stopEmitting);
    void process(WorkBatch* batch, StageContext& ctx);

    const Intersector& m_intersector;
    Stats& m_stats;
    int m_threads;
    tbb::task_arena m_arena;
    RayQueue m_queue;
    BatchPool m_pool;
    std::array<RetraceStage*, kRayKindCount> m_stages{};
    std::array<BatchType, kRayKindCount> m_types{};
    tbb::enumerable_thread_specific<std::unique_ptr<StageContext>> m_contexts;
    std::atomic<int> m_busy{0};
    std::atomic<bool> m_emitterDone{false};
    // Workers that have left run()'s loop: each adds one (release) as it leaves, and run()
    // reads it (acquire) after the join, so what a worker last did is seen to happen before
    // what follows (the join inside TBB is invisible to ThreadSanitizer).
    std::atomic<int> m_left{0};
    // A worker's exception: the others stop, run() rethrows it.
    std::atomic<bool> m_failed{false};
    std::mutex m_failureMutex;
    std::exception_ptr m_failure;
};

} // namespace rayproc
