// Reflection stage: continues paths off mirrors (perfect specular, weight = reflectance) and
// glossy surfaces (one GGX-importance-sampled ray; direct light there comes from the shadow
// stage, so these rays do not count the emitters they hit).
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
