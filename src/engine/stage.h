// The interfaces between the processor and its stages. An Emitter creates work (camera rays,
// photons); a RetraceStage receives a traced batch of one RayKind and spawns successor rays
// through its StageContext. Stages hold no per-thread state of their own.
#pragma once

#include "core/error.h"
#include "engine/ray_batch.h"
#include "engine/ray_queue.h"
#include "engine/stats.h"

#include <array>
#include <atomic>

namespace rayproc {

// Per-thread staging: one open batch per ray kind. Full batches go to the central queue; the
// partial ones are flushed when the thread runs out of work.
//
// Under a processor (keepLocal) a thread also keeps what stays hot in its own caches: up to
// kLocalReady full batches of secondary rays, which it traces next itself (last in, first out)
// instead of handing them through the central queue to another core, and up to kLocalFree
// spent batches of each type, which it fills again before taking one from the shared pool.
// Camera batches, what overflows and everything once the emitter is done (`tail`) go to the
// central queue, so other threads find work whenever there is any to share.
class StageContext {
public:
    static constexpr int kLocalReady = 4;
    static constexpr int kLocalFree = 8;

    StageContext(RayQueue& queue, BatchPool& pool) : m_queue(queue), m_pool(pool) {}
    StageContext(const StageContext&) = delete;
    ~StageContext();

    // Keep full secondary batches on this thread while *tail is false (the processor's "the
    // emitter is done" flag).
    void keepLocal(const std::atomic<bool>* tail) { m_tail = tail; }

    // A batch of `kind` with room for at least one more ray, of the type its route says: rays
    // traced to their closest hit (out), occlusion rays (outShadow) or photons (outPhotons).
    RayBatch& out(RayKind kind) { return open<RayBatch>(kind); }
    ShadowBatch& outShadow(RayKind kind) { return open<ShadowBatch>(kind); }
    PhotonBatch& outPhotons(RayKind kind) { return open<PhotonBatch>(kind); }
    // Pushes every non-empty open batch to the queue; returns whether any was pushed.
    bool flush();
    // Pushes the open batch of one kind, if it holds rays.
    void flush(RayKind kind) {
        WorkBatch*& b = m_open[int(kind)];
        if (b && b->count > 0) {
            push(b);
            b = nullptr;
        }
    }
    // Whether this thread holds no full batch of its own.
    bool noneReady() const { return m_readyCount == 0; }
    // Hands the batches this thread kept to the central queue (once the emitter is done, so
    // that the last of a run's work is shared).
    void shareKept() {
        while (m_readyCount > 0) m_queue.push(m_ready[--m_readyCount]);
    }
    // The batch this thread queued last for itself, if any.
    bool popLocal(WorkBatch*& b) {
        if (m_readyCount == 0) return false;
        b = m_ready[--m_readyCount];
        return true;
    }
    // A traced batch back to this thread's spent batches (the pool's when they are full).
    void release(WorkBatch* b) {
        LocalFree& free = m_free[int(b->type)];
        if (m_tail && free.count < kLocalFree) free.batches[free.count++] = b;
        else m_pool.release(b);
    }

    // Returns every open, ready and spent batch to the pool unsent (a run that failed drops
    // its work).
    void discard();

    ThreadStats* stats = nullptr; // set by the processor for the running thread

private:
    template <class Batch> Batch& open(RayKind kind) {
        WorkBatch*& b = m_open[int(kind)];
        if (b && b->full()) {
            push(b);
            b = nullptr;
        }
        if (!b) b = acquire<Batch>(kind);
        // One kind, one type: a kind's rays are all traced as its route says.
        RAYPROC_CHECK(b->type == Batch::kType);
        return *static_cast<Batch*>(b);
    }
    void push(WorkBatch* b) {
        if (m_tail && !b->fresh && m_readyCount < kLocalReady &&
            !m_tail->load(std::memory_order_relaxed))
            m_ready[m_readyCount++] = b;
        else
            m_queue.push(b);
    }
    template <class Batch> Batch* acquire(RayKind kind) {
        LocalFree& free = m_free[int(Batch::kType)];
        if (free.count == 0) return m_pool.acquire<Batch>(kind);
        WorkBatch* b = free.batches[--free.count];
        BatchPool::reuse(b, kind);
        return static_cast<Batch*>(b);
    }

    // Spent batches of one type, kept for this thread's next batches of that type.
    struct LocalFree {
        std::array<WorkBatch*, kLocalFree> batches{};
        int count = 0;
    };

    RayQueue& m_queue;
    BatchPool& m_pool;
    std::array<WorkBatch*, kRayKindCount> m_open{};
    const std::atomic<bool>* m_tail = nullptr;
    std::array<WorkBatch*, kLocalReady> m_ready{};
    int m_readyCount = 0;
    std::array<LocalFree, kBatchTypeCount> m_free{};
};

class Emitter {
public:
    virtual ~Emitter() = default;
    // Emits one unit of work (e.g. one tile of one pass) into ctx; false when none is left.
    // Called concurrently from every worker.
    virtual bool emit(StageContext& ctx) = 0;
};

// A stage takes the batches of the kinds routed to it: rays with their closest hits (retrace),
// occlusion rays with whether each was blocked (retraceShadows), or photons with their closest
// hits (retracePhotons). A stage implements what its routes carry; being handed another type
// is a wiring error (std::logic_error).
class RetraceStage {
public:
    virtual ~RetraceStage() = default;
    virtual void retrace(RayBatch& batch, StageContext& ctx);
    virtual void retraceShadows(ShadowBatch& batch, StageContext& ctx);
    virtual void retracePhotons(PhotonBatch& batch, StageContext& ctx);
};

} // namespace rayproc
