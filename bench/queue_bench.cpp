// Queue traffic per batch: what the ray processor pays to move one batch through the central
// queue, outside any stage: BatchPool::acquire, RayQueue::push, RayQueue::tryPop,
// BatchPool::release. One iteration = one batch; the "time/ray" counter divides by kBatchSize.
//
// Batches alternate between camera rays (the primary sub-queue, which tryPop checks second)
// and reflection rays (the secondary one). With ->Threads(2) both threads share one pool and
// one queue, as the processor's workers do; the time per iteration is then wall time over the
// batches of both threads, i.e. the cost per batch at the throughput of the whole machine.
#include "engine/ray_batch.h"
#include "engine/ray_queue.h"

#include <benchmark/benchmark.h>

#include <memory>

namespace rayproc::bench {
namespace {

struct SharedQueue {
    BatchPool pool;
    RayQueue queue;
};

std::unique_ptr<SharedQueue> g_shared; // set up by thread 0, shared by all threads

void queueRoundTrip(benchmark::State& state) {
    if (state.thread_index() == 0) {
        g_shared = std::make_unique<SharedQueue>();
        // Warm the pool: the render reuses batches, so the benchmark should not measure new.
        RayBatch* warm[8];
        for (RayBatch*& b : warm) b = g_shared->pool.acquire<RayBatch>(RayKind::Camera);
        for (RayBatch* b : warm) g_shared->pool.release(b);
    }
    // The benchmark library starts every thread's timed loop together, after thread 0's setup.
    std::uint64_t emptyPops = 0, i = 0;
    for (auto _ : state) {
        SharedQueue& s = *g_shared;
        RayBatch* b = s.pool.acquire<RayBatch>((i++ & 1) ? RayKind::Camera : RayKind::Reflection);
        b->count = kBatchSize;
        s.queue.push(b);
        WorkBatch* popped = nullptr;
        while (!s.queue.tryPop(popped)) ++emptyPops; // never empty: this thread pushed first
        benchmark::DoNotOptimize(popped->count);
        s.pool.release(popped);
    }
    double batches = double(state.iterations());
    state.SetItemsProcessed(std::int64_t(batches) * kBatchSize);
    // Inverted rates: wall seconds per batch and per ray, over the batches of all threads.
    state.counters["time/batch"] =
        benchmark::Counter(batches, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.counters["time/ray"] = benchmark::Counter(
        batches * kBatchSize, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.counters["empty pops"] = double(emptyPops);
}

BENCHMARK(queueRoundTrip)
    ->Name("BM_QueueRoundTrip")
    ->Threads(1)
    ->Threads(2)
    ->UseRealTime()
    ->Unit(benchmark::kNanosecond)
    ->MinTime(0.2);

} // namespace
} // namespace rayproc::bench
