// Record emitter: gather rays from the irradiance cache's records, for refining them during the
// render (gi/cache_refinement.h). Each record gets `rays` cosine-weighted rays over its own
// hemisphere, stratified like a final gather (kernels::cosineStratum) with fresh jitter each
// pass; each ray is a RayKind::Gather ray flagged kFlagGatherRecord whose pixel is the record's
// slot in the pass's IcRequests, so the gather stage adds what it finds to that slot exactly as
// in the cache's prepass. A ray's direction depends only on (seed, pass, record, ray), never on
// the thread that emits it.
#pragma once

#include "core/math.h"
#include "engine/stage.h"

#include <atomic>
#include <cstdint>
#include <vector>

namespace rayproc {

struct IrradianceRecord;
struct IcRequest;

class RecordEmitter : public Emitter {
public:
    // Records [first, last) of `records` (a distributed render's share), `rays` each; record i's
    // sums go to slot i - first of `slots` (claimed by the caller in record order).
    RecordEmitter(const std::vector<IrradianceRecord>& records, std::size_t first, std::size_t last,
                  int rays, bool stratify, std::uint64_t key, IcRequest* const* slots);
    bool emit(StageContext& ctx) override;

    static constexpr std::size_t kRecordsPerUnit = 16;

private:
    const std::vector<IrradianceRecord>& m_records;
    std::size_t m_first, m_last;
    int m_rays, m_thetaCount = 1, m_phiCount = 1;
    bool m_stratify;
    std::uint64_t m_key;
    IcRequest* const* m_slots;
    std::atomic<std::size_t> m_next{0};
};

} // namespace rayproc
