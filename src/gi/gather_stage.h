// Gather stage: the second pass of Jensen's method at diffuse surfaces.
// Spawning side, at a diffuse hit reached from the camera through specular surfaces only:
//  - caustics: the caustic photon map's radiance estimate, added directly;
//  - indirect diffuse: Ward's irradiance cache when a usable record exists, else a final
//    gather: M x N ~ `gatherRays` cosine-weighted rays, one jittered ray per stratum
//    sin^2(theta) in [j/M, (j+1)/M), phi in [2 pi k/N, 2 pi (k+1)/N) (equal cosine-weighted
//    solid angle each; the layout Ward & Heckbert's gradients read, GatherStrata).
//  In the cache's prepass it only creates records (the gather rays then sum into them, and
//  with gradients also write their stratum's radiance and first-hit distance).
//  At a diffuse hit reached through a glossy bounce it adds the global map's estimate of all
//  reflected light (no final gather there, and no shadow rays: the map holds direct light).
// Retrace side: each gather ray's hit reads the global photon map (no second gather): the
// reflected radiance albedo/pi * E, with E the precomputed (Christensen) or full estimate.
// At a mirror or glass surface the gather ray continues specularly (one branch, chosen with
// the Fresnel probability; at most maxDepth specular bounces) until it reaches a diffuse
// surface, so light along L ... D S+ D paths is kept; emission reached that way is the caustic
// map's (L S+ D at the gather's origin) and is not added.
#pragma once

#include "engine/hit_list.h"
#include "engine/render_context.h"
#include "engine/stage.h"
#include "kernels/bsdf_params.h"

namespace rayproc {

class GatherStage : public RetraceStage {
public:
    explicit GatherStage(const RenderContext& rc) : m_rc(rc) {}
    void spawn(const RayBatch& parent, const HitList& hits, StageContext& ctx);
    void retrace(RayBatch& batch, StageContext& ctx) override;

private:
    Vec3 globalIrradiance(const Vec3& p, const Vec3& n) const;
    // The caustic map's irradiance: k-nearest, or within the pass's radius when progressive.
    Vec3 causticIrradiance(const Vec3& p, const Vec3& n) const;
    // Radiance an opaque glossy surface at h sends towards wo: the global map's estimate with
    // the BSDF (PhotonMap::radiance), n its facing shading normal.
    Vec3 glossyRadiance(const kernels::BsdfParams& bsdf, const SurfaceHit& h, const Vec3& wo,
                        const Vec3& n) const;
    const RenderContext& m_rc;
};

} // namespace rayproc
