// Gather stage: the second pass of Jensen's method at diffuse surfaces.
// Spawning side, at a diffuse hit reached from the camera through specular surfaces only:
//  - caustics: the caustic photon map's radiance estimate, added directly;
//  - indirect diffuse: Ward's irradiance cache when a usable record exists, else a final
//    gather: `gatherRays` cosine-weighted rays, one per stratum of a jittered grid over the
//    square that maps to the hemisphere with equal cosine-weighted solid angle per cell.
//  In the cache's prepass it only creates records (the gather rays then sum into them).
//  At a diffuse hit reached through a glossy bounce it adds the global map's estimate of all
//  reflected light (no final gather there, and no shadow rays: the map holds direct light).
// Retrace side: each gather ray's hit reads the global photon map (no second gather): the
// reflected radiance albedo/pi * E, with E the precomputed (Christensen) or full estimate.
#pragma once

#include "engine/hit_list.h"
#include "engine/render_context.h"
#include "engine/stage.h"

namespace rayproc {

class GatherStage : public RetraceStage {
public:
    explicit GatherStage(const RenderContext& rc) : m_rc(rc) {}
    void spawn(const RayBatch& parent, const HitList& hits, StageContext& ctx);
    void retrace(RayBatch& batch, StageContext& ctx) override;

private:
    Vec3 globalIrradiance(const Vec3& p, const Vec3& n) const;
    const RenderContext& m_rc;
};

} // namespace rayproc
