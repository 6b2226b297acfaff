#include "engine/ray_queue.h"

namespace rayproc {

const char* rayKindName(RayKind k) {
    switch (k) {
    case RayKind::Camera: return "camera";
    case RayKind::Reflection: return "reflection";
    case RayKind::Refraction: return "refraction";
    case RayKind::Shadow: return "shadow";
    }
    static const char* const modeNames[kModeRayKindCount] = {"mode-0", "mode-1", "mode-2",
                                                             "mode-3", "mode-4"};
    const int i = int(k) - kFirstModeRayKind;
    return i >= 0 && i < kModeRayKindCount ? modeNames[i] : "?";
}

template <class Batch>
Batch* BatchPool::take(tbb::concurrent_queue<Batch*>& free,
                       std::vector<std::unique_ptr<Batch>>& owned, RayKind kind) {
    Batch* b = nullptr;
    if (!free.try_pop(b)) {
        auto made = std::make_unique<Batch>();
        b = made.get();
        std::lock_guard<std::mutex> lock(m_ownedLock);
        owned.push_back(std::move(made));
        ++m_allocated;
    }
    reuse(b, kind);
    return b;
}

RayBatch* BatchPool::acquire(RayKind kind) { return take(m_free, m_owned, kind); }

ShadowBatch* BatchPool::acquireShadow(RayKind kind) {
    return take(m_freeShadow, m_ownedShadow, kind);
}

void BatchPool::reuse(WorkBatch* b, RayKind kind) {
    b->kind = kind;
    b->count = 0;
    b->fresh = kind == RayKind::Camera;
}

void BatchPool::release(WorkBatch* b) {
    if (b->type == BatchType::Shadow) m_freeShadow.push(static_cast<ShadowBatch*>(b));
    else m_free.push(static_cast<RayBatch*>(b));
}

BatchPool::~BatchPool() = default;

void RayQueue::push(WorkBatch* b) {
    // Count first: a consumer that sees the batch must also see a non-zero size.
    m_size.fetch_add(1, std::memory_order_release);
    if (b->fresh) m_primary.push(b);
    else m_secondary.push(b);
}

bool RayQueue::tryPop(WorkBatch*& b) {
    if (m_secondary.try_pop(b) || m_primary.try_pop(b)) {
        m_size.fetch_sub(1, std::memory_order_acq_rel);
        return true;
    }
    return false;
}

} // namespace rayproc
