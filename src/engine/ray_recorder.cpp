#include "engine/ray_recorder.h"

#include "core/error.h"

namespace rayproc {

std::atomic<RayRecorder*> RayRecorder::s_active{nullptr};

RayRecorder::Scope::Scope(RayRecorder& recorder) {
    RayRecorder* expected = nullptr;
    RAYPROC_CHECK(s_active.compare_exchange_strong(expected, &recorder));
}

RayRecorder::Scope::~Scope() {
    s_active.store(nullptr, std::memory_order_release);
}

void RayRecorder::record(const WorkBatch& b, bool occlusion) {
    ThreadLog& log = m_logs.local();
    RecordedBatch r;
    r.kind = b.kind;
    r.occlusion = occlusion;
    r.count = b.count;
    auto copy = [&](std::vector<float>& to, const std::array<float, kBatchSize>& from) {
        to.assign(from.begin(), from.begin() + b.count);
    };
    copy(r.ox, b.ox);
    copy(r.oy, b.oy);
    copy(r.oz, b.oz);
    copy(r.dx, b.dx);
    copy(r.dy, b.dy);
    copy(r.dz, b.dz);
    copy(r.tnear, b.tnear);
    copy(r.tfar, b.tfar);
    log.batches.push_back(std::move(r));
    if (m_fullCap > 0 &&
        m_fullTaken[int(b.kind)].fetch_add(1, std::memory_order_relaxed) < m_fullCap) {
        if (b.type == BatchType::Shadow)
            log.fullShadow.push_back(
                std::make_shared<const ShadowBatch>(static_cast<const ShadowBatch&>(b)));
        else
            log.full.push_back(std::make_shared<const RayBatch>(static_cast<const RayBatch&>(b)));
    }
}

std::vector<RecordedBatch> RayRecorder::batches() const {
    std::vector<RecordedBatch> all;
    for (const ThreadLog& log : m_logs)
        all.insert(all.end(), log.batches.begin(), log.batches.end());
    return all;
}

namespace {

template <class Batch, class Logs, class Member>
std::vector<std::shared_ptr<const Batch>> ofKind(const Logs& logs, Member member, RayKind kind) {
    std::vector<std::shared_ptr<const Batch>> out;
    for (const auto& log : logs)
        for (const auto& b : log.*member)
            if (b->kind == kind) out.push_back(b);
    return out;
}

} // namespace

std::vector<std::shared_ptr<const RayBatch>> RayRecorder::fullBatches(RayKind kind) const {
    return ofKind<RayBatch>(m_logs, &ThreadLog::full, kind);
}

std::vector<std::shared_ptr<const ShadowBatch>> RayRecorder::fullShadowBatches(RayKind kind) const {
    return ofKind<ShadowBatch>(m_logs, &ThreadLog::fullShadow, kind);
}

std::size_t RayRecorder::rayCount() const {
    std::size_t n = 0;
    for (const ThreadLog& log : m_logs)
        for (const RecordedBatch& b : log.batches) n += std::size_t(b.count);
    return n;
}

} // namespace rayproc
