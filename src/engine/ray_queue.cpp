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

WorkBatch* BatchPool::own(Owned made) {
    WorkBatch* b = made.get();
    std::lock_guard<std::mutex> lock(m_ownedLock);
    m_owned.push_back(std::move(made));
    ++m_allocated;
    return b;
}

void BatchPool::Delete::operator()(WorkBatch* b) const {
    visitBatch(*b, [](auto& own) { delete &own; });
}

void BatchPool::reuse(WorkBatch* b, RayKind kind) {
    b->kind = kind;
    b->count = 0;
    b->fresh = kind == RayKind::Camera;
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
