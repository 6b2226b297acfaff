// Shadow stage. Spawning side: at diffuse and glossy hits, samples the lights (--light-samples
// samples of the single area light, or that many per area light that matters over several,
// each sample choosing one with the area lights' LightSampler, the choice path mode makes among
// all lights; one sample per delta light) and the environment, the numbers Sobol points over
// the pixel's samples (engine/sample_numbers.h), and emits one occlusion ray per sample
// carrying its unoccluded contribution.
// Retrace side: adds the contribution of every ray that reached its light to the film.
#pragma once

#include "engine/hit_list.h"
#include "engine/render_context.h"
#include "engine/stage.h"

namespace rayproc {

class ShadowStage : public RetraceStage {
public:
    explicit ShadowStage(const RenderContext& rc) : m_rc(rc) {}
    void spawn(const RayBatch& parent, const HitList& hits, StageContext& ctx);
    void retraceShadows(ShadowBatch& batch, StageContext& ctx) override;

private:
    const RenderContext& m_rc;
};

} // namespace rayproc
