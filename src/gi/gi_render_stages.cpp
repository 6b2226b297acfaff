#include "gi/gi_render_stages.h"

#include "engine/pipeline.h"
#include "engine/surface_stage.h"
#include "gi/gi_context.h"
#include "gi/gi_pipeline.h"

namespace rayproc {

void GiRenderStages::attach(const EngineStages& engine) {
    m_correction.reset();
    m_gather = std::make_unique<GatherStage>(engine.rc, m_gi);
    engine.pipeline.stage("gather", {kGatherQueue, kGatherShadowQueue}, *m_gather);
    engine.surface.addDiffuseHandler(*m_gather);
    if (!m_gi.settings.mapCorrection) return;
    m_correction = std::make_unique<CorrectionStage>(engine.rc, m_gi, *m_gather);
    addCorrectionStages(engine.pipeline, *m_correction, engine.shadow);
    engine.surface.addDiffuseHandler(*m_correction);
}

std::vector<StageLabel> GiRenderStages::labels() const {
    return {{kGatherStageId, "gather"}, {kCorrectionStageId, "correction"}};
}

} // namespace rayproc
