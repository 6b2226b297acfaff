#include "engine/processor.h"

#include "core/error.h"

#include <tbb/parallel_for.h>

#include <exception>
#include <mutex>
#include <string>
#include <thread>

namespace rayproc {

// Every batch must have been flushed, except when an exception (out of memory in a stage)
// unwinds the processor: then the partial batches are simply dropped with the render.
StageContext::~StageContext() {
    if (std::uncaught_exceptions() == 0) RAYPROC_CHECK(noneReady() && !flush());
}

void StageContext::discard() {
    for (WorkBatch*& b : m_open)
        if (b) {
            m_pool.release(b);
            b = nullptr;
        }
    while (m_readyCount > 0) m_pool.release(m_ready[--m_readyCount]);
    for (LocalFree& free : m_free)
        while (free.count > 0) m_pool.release(free.batches[--free.count]);
}

bool StageContext::flush() {
    bool any = false;
    for (WorkBatch*& b : m_open) {
        if (b && b->count > 0) {
            m_queue.push(b);
            b = nullptr;
            any = true;
        }
    }
    return any;
}

UnroutedRayKind::UnroutedRayKind(RayKind k)
    : std::logic_error(std::string("no stage takes the rays of kind ") + rayKindName(k)),
      kind(k) {}

RayProcessor::RayProcessor(const Intersector& intersector, Stats& stats, int threads)
    : m_intersector(intersector), m_stats(stats),
      m_threads(threads > 0 ? threads : tbb::this_task_arena::max_concurrency()),
      m_arena(m_threads) {}

void RetraceStage::retrace(RayBatch& batch, StageContext&) {
    throw std::logic_error(std::string("a stage that takes no closest-hit rays was given the ") +
                           rayKindName(batch.kind) + " queue");
}

void RetraceStage::retraceShadows(ShadowBatch& batch, StageContext&) {
    throw std::logic_error(std::string("a stage that takes no occlusion rays was given the ") +
                           rayKindName(batch.kind) + " queue");
}

void RetraceStage::retracePhotons(PhotonBatch& batch, StageContext&) {
    throw std::logic_error(std::string("a stage that takes no photons was given the ") +
                           rayKindName(batch.kind) + " queue");
}

namespace {

// A traced batch to its stage's method for its type.
void retraceBy(RetraceStage& stage, RayBatch& b, StageContext& ctx) { stage.retrace(b, ctx); }
void retraceBy(RetraceStage& stage, ShadowBatch& b, StageContext& ctx) {
    stage.retraceShadows(b, ctx);
}
void retraceBy(RetraceStage& stage, PhotonBatch& b, StageContext& ctx) {
    stage.retracePhotons(b, ctx);
}

} // namespace

// Trace, then hand the batch to its kind's stage by its type: rays and photons with their
// closest hits, occlusion rays with whether each was blocked (a kind's route says which type
// its batches are).
void RayProcessor::process(WorkBatch* batch, StageContext& ctx) {
    ThreadStats& stats = *ctx.stats;
    ++stats.batches;
    QueueCounters& queue = stats.queues[int(batch->kind)];
    ++queue.batches;
    queue.rays += std::uint64_t(batch->count);
    RetraceStage* stage = m_stages[int(batch->kind)];
    if (!stage || batch->type != m_types[int(batch->kind)]) {
        m_pool.release(batch);
        if (!stage) throw UnroutedRayKind(batch->kind);
        throw std::logic_error(std::string("the ") + rayKindName(batch->kind) +
                               " queue was given batches of another type than its route's");
    }
    visitBatch(*batch, [&](auto& b) {
        m_intersector.trace(b, stats);
        retraceBy(*stage, b, ctx);
    });
    ctx.release(batch);
}

// One worker: pop and process its own kept batches, then queued ones, first (finish work in
// flight), emit new work only when there are none, and flush its own partial batches before it
// leaves. A worker that keeps batches counts as busy until it has traced them, and hands them
// to the queue once the emitter is done, so no other worker leaves while work remains that it
// could share. It leaves when nothing is queued, nothing can be emitted and no other worker is
// busy, or when any worker failed: an exception (out of memory in a stage) is kept for run()
// to rethrow, and the others must not wait for the busy count the failed worker can no longer
// lower.
void RayProcessor::worker(Emitter& emitter, const std::function<bool()>& stopEmitting) {
    struct Leaving {
        std::atomic<int>& left;
        ~Leaving() { left.fetch_add(1, std::memory_order_release); }
    } leaving{m_left};
    auto& slot = m_contexts.local();
    if (!slot) slot = std::make_unique<StageContext>(m_queue, m_pool);
    StageContext& ctx = *slot;
    ctx.keepLocal(&m_emitterDone);
    ctx.stats = &m_stats.local();
    bool counted = false; // this worker is in m_busy
    for (;;) {
        if (m_failed.load(std::memory_order_acquire)) {
            if (counted) m_busy.fetch_sub(1, std::memory_order_acq_rel);
            return;
        }
        if (!counted) m_busy.fetch_add(1, std::memory_order_acq_rel);
        counted = true;
        bool worked = false;
        try {
            if (!ctx.noneReady() && m_emitterDone.load(std::memory_order_acquire))
                ctx.shareKept();
            WorkBatch* b = nullptr;
            if (ctx.popLocal(b) || m_queue.tryPop(b)) {
                process(b, ctx);
                worked = true;
            } else if (!m_emitterDone.load(std::memory_order_acquire)) {
                if (stopEmitting() || !emitter.emit(ctx)) m_emitterDone.store(true);
                else worked = true;
            }
            if (!worked) worked = ctx.flush();
        } catch (...) {
            {
                std::lock_guard<std::mutex> lock(m_failureMutex);
                if (!m_failure) m_failure = std::current_exception();
            }
            m_failed.store(true, std::memory_order_release);
            m_busy.fetch_sub(1, std::memory_order_acq_rel);
            return;
        }
        if (ctx.noneReady()) {
            m_busy.fetch_sub(1, std::memory_order_acq_rel);
            counted = false;
        }
        if (worked) continue;
        if (m_busy.load(std::memory_order_acquire) == 0 && m_queue.empty() &&
            m_emitterDone.load(std::memory_order_acquire))
            return;
        std::this_thread::yield();
    }
}

void RayProcessor::run(Emitter& emitter, const std::function<bool()>& stopEmitting) {
    m_emitterDone.store(false);
    m_failed.store(false);
    m_failure = nullptr;
    m_left.store(0);
    m_arena.execute([&] {
        tbb::parallel_for(0, m_threads, [&](int) { worker(emitter, stopEmitting); },
                          tbb::simple_partitioner());
    });
    RAYPROC_CHECK(m_left.load(std::memory_order_acquire) == m_threads);
    if (m_failed.load()) {
        // The run's work is dropped with it: queued and staged batches go back to the pool.
        WorkBatch* b = nullptr;
        while (m_queue.tryPop(b)) m_pool.release(b);
        for (auto& c : m_contexts) c->discard();
        std::rethrow_exception(m_failure);
    }
    // Workers flush their own staging before leaving; nothing may remain.
    RAYPROC_CHECK(m_queue.empty());
    for (auto& c : m_contexts) RAYPROC_CHECK(c->noneReady() && !c->flush());
}

} // namespace rayproc
