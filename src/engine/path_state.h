// Helpers the spawning stages share: reading a lane's ray, deciding whether a path goes on
// (maximum depth, then Russian roulette below the throughput threshold), and writing a
// successor ray with its payload.
#pragma once

#include "accel/embree_scene.h"
#include "engine/ray_batch.h"
#include "engine/render_context.h"
#include "engine/spectral_render.h"
#include "kernels/random.h"

namespace rayproc {

// Random dimensions a shading point may use, by purpose; each lane's stream is its rngKey.
enum RandomDim : std::uint32_t {
    kDimRoulette = 0,
    kDimReflect = 2,   // the reflection stage's layered BSDF's own numbers
    kDimLightBase = 16, // light samples: hashed per light, see ShadowStage
};

// The hit's normals turned to the side the ray arrived from: opaque surfaces shade both sides.
inline void facingNormals(const SurfaceHit& h, const Vec3& wo, Vec3& ng, Vec3& ns) {
    bool front = dot(wo, h.ng) >= 0;
    ng = front ? h.ng : -h.ng;
    ns = front ? h.ns : -h.ns;
}

// Lane i's (wr, wg, wb): a ray's throughput (RayBatch), an occlusion ray's unoccluded
// contribution (ShadowBatch), a photon's power (PhotonBatch).
template <class Batch> Vec3 laneThroughput(const Batch& b, int i) {
    return {b.wr[i], b.wg[i], b.wb[i]};
}

// Beer-Lambert absorption of a segment travelled inside a shape filled with an absorbing medium:
// a ray from o along d that reaches the shape's surface from its back side (d along the outward
// normal) was inside for the whole segment. With `spectral`, the absorption coefficient's
// (unbounded) spectrum at the lane's wavelengths.
inline Vec3 interiorTransmittance(const SurfaceHit& h, const Vec3& o, const Vec3& d,
                                  const SpectralRender* spectral = nullptr,
                                  const LaneSpectrum* lane = nullptr) {
    Vec3 sigma = h.shape->interiorAbsorption;
    if (isBlack(sigma) || dot(d, h.ng) <= 0) return Vec3(1.0f);
    if (spectral) sigma = spectral->unbounded(sigma, *lane);
    float t = length(h.p - o);
    return {std::exp(-sigma.x * t), std::exp(-sigma.y * t), std::exp(-sigma.z * t)};
}
inline Vec3 laneDirection(const WorkBatch& b, int i) { return {b.dx[i], b.dy[i], b.dz[i]}; }

// The paper's termination: "until the maximum ray depth is achieved or the contributed
// radiance falls below a specified threshold" — with Russian roulette below the threshold so
// that the estimate stays unbiased: survivors are reweighted by 1 / survival probability.
inline bool survivesRoulette(const ShadingPolicy& policy, std::uint64_t key, std::uint32_t branch,
                             Vec3& weight) {
    float m = maxComponent(weight);
    if (!(m > 0)) return false;
    if (policy.rouletteEnabled && m < policy.rrThreshold) {
        float q = m / policy.rrThreshold;
        if (kernels::uniform(key, kDimRoulette + branch) >= q) return false;
        weight = weight / q;
    }
    return true;
}
inline bool continuePath(const ShadingPolicy& policy, int newDepth, std::uint64_t key,
                         std::uint32_t branch, Vec3& weight) {
    return newDepth <= policy.maxDepth && survivesRoulette(policy, key, branch, weight);
}

// The random stream of a successor that a ray (or photon) of stream `parent` spawns by
// `branch`.
inline std::uint64_t successorKey(std::uint64_t parent, std::uint32_t branch) {
    return kernels::hashCombine(parent, 0x100u + branch);
}

// Writes a successor ray of `parent` lane i into `out`.
inline void spawnRay(RayBatch& out, const RayBatch& parent, int i, const Vec3& origin,
                     const Vec3& dir, const Vec3& weight, std::uint8_t depth,
                     std::uint8_t specularDepth, std::uint8_t flags, std::uint32_t branch) {
    int j = out.push(origin.x, origin.y, origin.z, dir.x, dir.y, dir.z, 0.0f, kInfinity);
    out.pixel[j] = parent.pixel[i];
    out.sample[j] = parent.sample[i];
    out.prevPdf[j] = 0.0f;
    out.prevCos[j] = 0.0f;
    out.lambdaU[j] = parent.lambdaU[i];
    out.wr[j] = weight.x; out.wg[j] = weight.y; out.wb[j] = weight.z;
    out.rngKey[j] = successorKey(parent.rngKey[i], branch);
    out.depth[j] = depth;
    out.specularDepth[j] = specularDepth;
    out.flags[j] = flags;
}

// The same with the wavelength number `lambdaU` (spectral mode: LaneShading::u(), the parent's
// or, past a dispersive interface, its hero's alone; engine/material_bsdf.h).
inline void spawnRay(RayBatch& out, const RayBatch& parent, int i, const Vec3& origin,
                     const Vec3& dir, const Vec3& weight, std::uint8_t depth,
                     std::uint8_t specularDepth, std::uint8_t flags, std::uint32_t branch,
                     float lambdaU) {
    spawnRay(out, parent, i, origin, dir, weight, depth, specularDepth, flags, branch);
    out.lambdaU[out.count - 1] = lambdaU;
}

// Writes an occlusion ray from hit h (facing geometric normal ng) carrying its unoccluded
// contribution: to the sampled point of `light` when it has one at a finite distance, stopping
// short of it by that point's error bound (kernels::shadowSegment), else along wi to infinity
// (directional lights, the sky; light = nullptr).
inline void spawnShadowRay(ShadowBatch& out, const RayBatch& parent, int i, const SurfaceHit& h,
                           const Vec3& ng, const Vec3& wi, const LightSample* light,
                           const Vec3& contribution) {
    Vec3 o, d = wi;
    float tfar = kInfinity;
    if (light && light->distance != kInfinity)
        kernels::shadowSegment(h.p, h.pError, ng, light->point, light->pointError, light->normal,
                               o, d, tfar);
    else
        o = offsetRayOrigin(h, ng, wi);
    int j = out.push(o.x, o.y, o.z, d.x, d.y, d.z, 0.0f, tfar);
    out.pixel[j] = parent.pixel[i];
    out.sample[j] = parent.sample[i];
    out.wr[j] = contribution.x; out.wg[j] = contribution.y; out.wb[j] = contribution.z;
    out.lambdaU[j] = parent.lambdaU[i];
    out.category[j] = 0;
    out.flags[j] = 0;
}
// The same with the wavelength number `lambdaU` (as spawnRay's).
inline void spawnShadowRay(ShadowBatch& out, const RayBatch& parent, int i, const SurfaceHit& h,
                           const Vec3& ng, const Vec3& wi, const LightSample* light,
                           const Vec3& contribution, float lambdaU) {
    spawnShadowRay(out, parent, i, h, ng, wi, light, contribution);
    out.lambdaU[out.count - 1] = lambdaU;
}

} // namespace rayproc
