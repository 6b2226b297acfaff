// Path stage: the retrace stage of path mode, an unbiased path tracer on the same queue and
// intersection handler as the other modes. At each hit of a camera or bounce ray it
//  - adds the emission it lands on (or the sky it escapes to), weighted by multiple importance
//    sampling against light sampling (Veach's power heuristic) unless the ray came off a
//    delta lobe or the camera;
//  - at non-delta surfaces samples one light (uniform choice among the lights and the sky)
//    and emits a shadow ray carrying the MIS-weighted contribution (next-event estimation);
//  - samples the BSDF for the next ray, with Russian roulette after `rrStartDepth` bounces;
//    past the last vertex (depth == maxDepth) only a non-delta sample goes on, flagged
//    kFlagEmissionOnly: it adds its MIS share of the emission or sky it finds, nothing else.
// The shadow stage's retrace adds unoccluded contributions to the film.
#pragma once

#include "engine/render_context.h"
#include "engine/stage.h"

namespace rayproc {

class PathStage : public RetraceStage {
public:
    explicit PathStage(const RenderContext& rc) : m_rc(rc) {}
    void retrace(RayBatch& batch, StageContext& ctx) override;

private:
    const RenderContext& m_rc;
};

} // namespace rayproc
