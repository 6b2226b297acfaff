// Surface stage: the retrace stage of camera, reflection and refraction rays. It resolves each
// hit, adds what the ray sees directly (emitters, or the sky on a miss) and routes every hit
// by material to the stages that continue it: shadow (direct light) for diffuse and glossy,
// reflection for mirror and glossy, refraction for dielectrics, and diffuse hits also to the
// handlers a mode registers (gi: gather, for caustics and indirect light, and correction).
#pragma once

#include "engine/hit_list.h"
#include "engine/reflection_stage.h"
#include "engine/refraction_stage.h"
#include "engine/render_context.h"
#include "engine/shadow_stage.h"
#include "engine/stage.h"

#include <vector>

namespace rayproc {

// A mode's continuation of diffuse hits (gi: the gather stage's caustics and indirect light,
// the correction stage's correction of the photon map at the same hits).
class DiffuseHitHandler {
public:
    virtual ~DiffuseHitHandler() = default;
    virtual void spawn(const RayBatch& parent, const HitList& hits, StageContext& ctx) = 0;
};

class SurfaceStage : public RetraceStage {
public:
    SurfaceStage(const RenderContext& rc, ShadowStage& shadow, ReflectionStage& reflection,
                 RefractionStage& refraction)
        : m_rc(rc), m_shadow(shadow), m_reflection(reflection), m_refraction(refraction) {}
    // Diffuse hits go to `handler` too, after the shadow stage, in the order registered. With
    // any handler, the light of diffuse hits past a non-specular bounce is the handlers' (gi's
    // global map holds all the light reflected there): those hits get no light samples.
    void addDiffuseHandler(DiffuseHitHandler& handler) { m_diffuseHandlers.push_back(&handler); }
    void retrace(RayBatch& batch, StageContext& ctx) override;

private:
    void addEscaped(const RayBatch& b, int i, ThreadStats& stats) const;
    SurfaceHit resolveHit(RayBatch& b, int i, bool addDirect, ThreadStats& stats) const;
    const RenderContext& m_rc;
    ShadowStage& m_shadow;
    ReflectionStage& m_reflection;
    RefractionStage& m_refraction;
    std::vector<DiffuseHitHandler*> m_diffuseHandlers;
};

} // namespace rayproc
