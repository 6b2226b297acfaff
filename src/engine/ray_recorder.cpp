#include "engine/ray_recorder.h"

#include "core/error.h"

#include <type_traits>

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
        visitBatch(b, [&](const auto& whole) {
            using Batch = std::decay_t<decltype(whole)>;
            log.full[int(b.type)].push_back(std::make_shared<const Batch>(whole));
        });
    }
}

std::vector<RecordedBatch> RayRecorder::batches() const {
    std::vector<RecordedBatch> all;
    for (const ThreadLog& log : m_logs)
        all.insert(all.end(), log.batches.begin(), log.batches.end());
    return all;
}

std::size_t RayRecorder::rayCount() const {
    std::size_t n = 0;
    for (const ThreadLog& log : m_logs)
        for (const RecordedBatch& b : log.batches) n += std::size_t(b.count);
    return n;
}

} // namespace rayproc
