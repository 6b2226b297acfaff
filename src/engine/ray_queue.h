// The central queue of the ray processor, and the pool its batches come from. Emitters and
// stages push full batches; TBB tasks pop them. Batches are recycled, never freed mid-render.
#pragma once

#include "engine/ray_batch.h"

#include <tbb/concurrent_queue.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <vector>

namespace rayproc {

// Spent batches of each type, reused by type.
class BatchPool {
public:
    RayBatch* acquire(RayKind kind);
    ShadowBatch* acquireShadow(RayKind kind);
    void release(WorkBatch* b);
    // An empty batch of `kind` made of a spent one.
    static void reuse(WorkBatch* b, RayKind kind);
    std::size_t allocated() const { return m_allocated.load(); }
    ~BatchPool();

private:
    template <class Batch>
    Batch* take(tbb::concurrent_queue<Batch*>& free, std::vector<std::unique_ptr<Batch>>& owned,
                RayKind kind);

    tbb::concurrent_queue<RayBatch*> m_free;
    tbb::concurrent_queue<ShadowBatch*> m_freeShadow;
    std::atomic<std::size_t> m_allocated{0};
    std::mutex m_ownedLock;
    // Owned by their own type: a WorkBatch has no virtual destructor.
    std::vector<std::unique_ptr<RayBatch>> m_owned;
    std::vector<std::unique_ptr<ShadowBatch>> m_ownedShadow;
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
