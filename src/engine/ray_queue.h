// The central queue of the ray processor, and the pool its batches come from. Emitters and
// stages push full batches; TBB tasks pop them. Batches are recycled, never freed mid-render.
#pragma once

#include "engine/ray_batch.h"

#include <tbb/concurrent_queue.h>

#include <array>
#include <atomic>
#include <memory>
#include <mutex>
#include <vector>

namespace rayproc {

// Spent batches of each type, reused by type: one free list per BatchType.
class BatchPool {
public:
    // An empty batch of `kind`, of type Batch (RayBatch, ShadowBatch, PhotonBatch).
    template <class Batch> Batch* acquire(RayKind kind) {
        WorkBatch* b = nullptr;
        if (!m_free[int(Batch::kType)].try_pop(b)) b = own(Owned(new Batch()));
        reuse(b, kind);
        return static_cast<Batch*>(b);
    }
    void release(WorkBatch* b) { m_free[int(b->type)].push(b); }
    // An empty batch of `kind` made of a spent one.
    static void reuse(WorkBatch* b, RayKind kind);
    std::size_t allocated() const { return m_allocated.load(); }
    ~BatchPool();

private:
    // Deletes a batch as its own type: a WorkBatch has no virtual destructor.
    struct Delete {
        void operator()(WorkBatch* b) const;
    };
    using Owned = std::unique_ptr<WorkBatch, Delete>;
    WorkBatch* own(Owned made);

    std::array<tbb::concurrent_queue<WorkBatch*>, kBatchTypeCount> m_free;
    std::atomic<std::size_t> m_allocated{0};
    std::mutex m_ownedLock;
    std::vector<Owned> m_owned;
};

// Multi-producer multi-consumer queue of batches. Secondary rays (shadow, reflection,
// refraction, photon bounces, gather) are popped before fresh emitter batches (camera rays,
// emitted photons), so work in flight drains before new work starts and memory stays bounded
// by the depth of the paths, not the size of the image.
class RayQueue {
public:
    void push(WorkBatch* b);
    bool tryPop(WorkBatch*& b);
    bool empty() const { return m_size.load(std::memory_order_acquire) == 0; }
    std::size_t size() const { return m_size.load(std::memory_order_acquire); }

private:
    tbb::concurrent_queue<WorkBatch*> m_secondary;
    tbb::concurrent_queue<WorkBatch*> m_primary;
    std::atomic<std::size_t> m_size{0};
};

} // namespace rayproc
