// gi's stages in a render pass (engine/mode_stages.h): the gather stage takes the surface
// stage's diffuse hits (caustics, the irradiance cache, final gathers) and, with
// GiSettings::mapCorrection, the correction stage takes them too and traces its paths, whose
// light samples go to the render's shadow stage.
#pragma once

#include "engine/mode_stages.h"
#include "gi/correction_stage.h"
#include "gi/gather_stage.h"

#include <memory>

namespace rayproc {

struct GiData;

class GiRenderStages : public ModeStages {
public:
    explicit GiRenderStages(const GiData& gi) : m_gi(gi) {}
    void attach(const EngineStages& engine) override;
    std::vector<StageLabel> labels() const override;

private:
    const GiData& m_gi;
    std::unique_ptr<GatherStage> m_gather;
    std::unique_ptr<CorrectionStage> m_correction;
};

} // namespace rayproc
