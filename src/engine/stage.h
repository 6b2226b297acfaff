// The interfaces between the processor and its stages. An Emitter creates work (camera rays,
// later photons); a RetraceStage receives a traced batch of one RayKind and spawns successor
// rays through its StageContext. Stages hold no per-thread state of their own.
#pragma once

#include "engine/ray_batch.h"
#include "engine/ray_queue.h"
#include "engine/stats.h"

#include <array>

namespace rayproc {

// Per-thread staging: one open batch per ray kind. Full batches go to the central queue; the
// partial ones are flushed when the thread runs out of work.
class StageContext {
public:
    StageContext(RayQueue& queue, BatchPool& pool) : m_queue(queue), m_pool(pool) {}
    StageContext(const StageContext&) = delete;
    ~StageContext();

    // A batch of `kind` with room for at least one more ray.
    RayBatch& out(RayKind kind) {
        RayBatch*& b = m_open[int(kind)];
        if (b && b->full()) {
            m_queue.push(b);
            b = nullptr;
        }
        if (!b) b = m_pool.acquire(kind);
        return *b;
    }
    // Pushes every non-empty open batch to the queue; returns whether any was pushed.
    bool flush();
    // Pushes the open batch of one kind, if it holds rays.
    void flush(RayKind kind) {
        RayBatch*& b = m_open[int(kind)];
        if (b && b->count > 0) {
            m_queue.push(b);
            b = nullptr;
        }
    }

    // Returns every open batch to the pool unsent (a run that failed drops its work).
    void discard() {
        for (RayBatch*& b : m_open)
            if (b) {
                m_pool.release(b);
                b = nullptr;
            }
    }

    ThreadStats* stats = nullptr; // set by the processor for the running thread

private:
    RayQueue& m_queue;
    BatchPool& m_pool;
    std::array<RayBatch*, kRayKindCount> m_open{};
};

class Emitter {
public:
    virtual ~Emitter() = default;
    // Emits one unit of work (e.g. one tile of one pass) into ctx; false when none is left.
    // Called concurrently from every worker.
    virtual bool emit(StageContext& ctx) = 0;
};

class RetraceStage {
public:
    virtual ~RetraceStage() = default;
    virtual void retrace(RayBatch& batch, StageContext& ctx) = 0;
};

} // namespace rayproc
