// Ray recorder: a benchmarking hook that captures every batch the Intersector traces, so the
// same rays can be replayed later through bare Embree calls (engine efficiency: the engine's
// rays/s against raw Embree's on identical rays, bench/engine_efficiency_bench.cpp).
//
// Off by default and free when off: an Intersector looks up the active recorder once, when it
// is built, and then tests one pointer per batch. While a RayRecorder::Scope is alive, every
// Intersector built in the process records into it (the mode drivers build their own, so a
// whole render, gi's photon and cache passes included, can be recorded without changing them).
//
// What is kept per traced batch: its kind, how it was traced, and the rays as Embree sees them
// (origin, direction, tnear, tfar), before tracing. Optionally the first `fullBatchesPerKind`
// batches of each kind are also kept whole (payload included, as their own type: RayBatch,
// ShadowBatch or PhotonBatch), as realistic inputs for the per-stage benchmarks.
// Recording is thread-safe (one buffer per thread); replay order is per thread, in the order
// that thread traced its batches.
#pragma once

#include "engine/ray_batch.h"

#include <cstdint>

#include <tbb/enumerable_thread_specific.h>

#include <array>
#include <atomic>
#include <cstddef>
#include <memory>
#include <vector>

namespace rayproc {

// The rays of one traced batch, SoA, exactly `count` lanes.
struct RecordedBatch {
    RayKind kind = RayKind::Camera;
    bool occlusion = false; // traced as occlusion rays (RayQuery::Occlusion)
    int count = 0;
    std::vector<float> ox, oy, oz, dx, dy, dz, tnear, tfar;
};

class RayRecorder {
public:
    explicit RayRecorder(std::size_t fullBatchesPerKind = 0) : m_fullCap(fullBatchesPerKind) {}

    // Called by the Intersector before it traces `b`; from any thread.
    void record(const WorkBatch& b, bool occlusion);

    // Every recorded batch: the first thread's in its order, then the next thread's, ...
    std::vector<RecordedBatch> batches() const;
    // The batches of `kind` kept whole (at most fullBatchesPerKind, untraced), of the type
    // Batch its route carries (RayBatch, ShadowBatch, PhotonBatch).
    template <class Batch>
    std::vector<std::shared_ptr<const Batch>> fullBatches(RayKind kind) const {
        std::vector<std::shared_ptr<const Batch>> out;
        for (const ThreadLog& log : m_logs)
            for (const auto& b : log.full[int(Batch::kType)])
                if (b->kind == kind) out.push_back(std::static_pointer_cast<const Batch>(b));
        return out;
    }
    std::size_t rayCount() const;

    // The recorder Intersectors built now attach to; null when recording is off.
    static RayRecorder* active() { return s_active.load(std::memory_order_acquire); }

    // Makes `recorder` active for the scope's lifetime (not nestable).
    class Scope {
    public:
        explicit Scope(RayRecorder& recorder);
        ~Scope();
        Scope(const Scope&) = delete;
        Scope& operator=(const Scope&) = delete;
    };

private:
    struct ThreadLog {
        std::vector<RecordedBatch> batches;
        // Batches kept whole, by type (BatchType), each owned as its own type.
        std::array<std::vector<std::shared_ptr<const WorkBatch>>, kBatchTypeCount> full;
    };
    std::size_t m_fullCap;
    std::array<std::atomic<std::size_t>, kRayKindCount> m_fullTaken{};
    tbb::enumerable_thread_specific<ThreadLog> m_logs;
    static std::atomic<RayRecorder*> s_active;
};

} // namespace rayproc
