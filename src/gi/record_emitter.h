// Record emitter: gather rays from the irradiance cache's records, for refining them during the
// render (gi/cache_refinement.h). Each record gets `rays` cosine-weighted rays over its own
// hemisphere, stratified like a final gather (kernels::cosineStratum) with fresh jitter each
// pass; each ray is a kGatherRay ray flagged kFlagGatherRecord whose pixel is the record's
// slot in the pass's IcRequests, so the gather stage adds what it finds to that slot exactly as
// in the cache's prepass. A ray's direction depends only on (seed, pass, record, ray), never on
// the thread that emits it.
// With correction rays, each record also gets that many kCorrectionRay rays (the same
// cosine strata, their own jitter) whose pixel is the record's slot: the correction stage and
// the paths it continues add what they find to that pixel of the refinement's film
// (gi/cache_refinement.h).
#pragma once

#include "core/math.h"
#include "engine/stage.h"
#include "gi/gi_pipeline.h"

#include <atomic>
#include <cstdint>
#include <vector>

namespace rayproc {

struct IrradianceRecord;
struct IcRequest;

class RecordEmitter : public Emitter {
public:
    // Records [first, last) of `records` (a distributed render's share), `rays` gather rays
    // (may be 0) and `correctionRays` correction rays each; record i's gather sums go to slot
    // i - first of `slots` (claimed by the caller in record order), its corrections to pixel
    // i - first.
    RecordEmitter(const std::vector<IrradianceRecord>& records, std::size_t first, std::size_t last,
                  int rays, int correctionRays, bool stratify, std::uint64_t key,
                  IcRequest* const* slots);
    bool emit(StageContext& ctx) override;
    // The correction rays each record gets (the count rounded to whole M x N strata), those
    // below its surface, which are not traced, included.
    int correctionRaysPerRecord() const { return m_correction.count(); }

    static constexpr std::size_t kRecordsPerUnit = 16;

private:
    const std::vector<IrradianceRecord>& m_records;
    std::size_t m_first, m_last;
    // Rays per record: M x N strata of gather rays, and of correction rays.
    struct Strata {
        int theta = 0, phi = 0;
        int count() const { return theta * phi; }
    };
    Strata m_gather, m_correction;
    bool m_stratify;
    std::uint64_t m_key;
    IcRequest* const* m_slots;
    std::atomic<std::size_t> m_next{0};
};

} // namespace rayproc
