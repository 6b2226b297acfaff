// Refraction stage: splits each dielectric hit by the Fresnel equations into a reflected ray
// (weight F) and a refracted ray (weight (1 - F) times the tint, on entering), Whitted-style;
// total internal reflection sends everything back. In preview mode glass transmits straight
// through, with at least the policy's minimum translucency, so it never goes black.
#pragma once

#include "engine/hit_list.h"
#include "engine/render_context.h"
#include "engine/stage.h"

namespace rayproc {

class RefractionStage {
public:
    explicit RefractionStage(const RenderContext& rc) : m_rc(rc) {}
    void spawn(const RayBatch& parent, const HitList& hits, StageContext& ctx);

private:
    const RenderContext& m_rc;
};

} // namespace rayproc
