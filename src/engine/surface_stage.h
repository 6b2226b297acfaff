// Surface stage: the retrace stage of camera, reflection and refraction rays. It resolves each
// hit, adds what the ray sees directly (emitters, or the sky on a miss) and routes every hit
// by material to the stages that continue it: shadow (direct light) for diffuse and glossy,
// reflection for mirror and glossy, refraction for dielectrics, and in gi mode gather
// (caustics and indirect light) for diffuse.
#pragma once

#include "engine/reflection_stage.h"
#include "engine/refraction_stage.h"
#include "engine/render_context.h"
#include "engine/shadow_stage.h"
#include "engine/stage.h"

namespace rayproc {

class CorrectionStage;
class GatherStage;

class SurfaceStage : public RetraceStage {
public:
    // `gather` is gi mode's indirect-diffuse stage (caustics, irradiance cache, final gather),
    // `correction` its correction of the photon map's bias at the same hits; null in the other
    // modes (and the correction in gi's cache prepass).
    SurfaceStage(const RenderContext& rc, ShadowStage& shadow, ReflectionStage& reflection,
                 RefractionStage& refraction, GatherStage* gather = nullptr,
                 const CorrectionStage* correction = nullptr)
        : m_rc(rc), m_shadow(shadow), m_reflection(reflection), m_refraction(refraction),
          m_gather(gather), m_correction(correction) {}
    void retrace(RayBatch& batch, StageContext& ctx) override;

private:
    const RenderContext& m_rc;
    ShadowStage& m_shadow;
    ReflectionStage& m_reflection;
    RefractionStage& m_refraction;
    GatherStage* m_gather;
    const CorrectionStage* m_correction;
};

} // namespace rayproc
