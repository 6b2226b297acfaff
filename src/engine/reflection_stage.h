// Reflection stage: continues paths off mirrors (perfect specular, weight = reflectance) and
// glossy surfaces (one GGX-importance-sampled ray: emitters there are sampled by the shadow
// stage, so the ray does not count the emitters it hits, but it is what sees the sky).
#pragma once

#include "engine/hit_list.h"
#include "engine/render_context.h"
#include "engine/stage.h"

namespace rayproc {

class ReflectionStage {
public:
    explicit ReflectionStage(const RenderContext& rc) : m_rc(rc) {}
    void spawn(const RayBatch& parent, const HitList& hits, StageContext& ctx);

private:
    const RenderContext& m_rc;
};

} // namespace rayproc
