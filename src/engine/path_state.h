// Helpers the spawning stages share: reading a lane's ray, deciding whether a path goes on
// (maximum depth, then Russian roulette below the throughput threshold), and writing a
// successor ray with its payload.
#pragma once

#include "accel/embree_scene.h"
#include "engine/ray_batch.h"
#include "engine/render_context.h"
#include "kernels/random.h"

namespace rayproc {

// Random dimensions a shading point may use, by purpose; each lane's stream is its rngKey.
enum RandomDim : std::uint32_t {
    kDimRoulette = 0,
    kDimReflect = 2,   // 2 numbers
    kDimRefract = 4,
    kDimLightBase = 16, // light samples: hashed per light, see ShadowStage
};

// The hit's normals turned to the side the ray arrived from: opaque surfaces shade both sides.
inline void facingNormals(const SurfaceHit& h, const Vec3& wo, Vec3& ng, Vec3& ns) {
    bool front = dot(wo, h.ng) >= 0;
    ng = front ? h.ng : -h.ng;
    ns = front ? h.ns : -h.ns;
}

inline Vec3 laneThroughput(const RayBatch& b, int i) { return {b.wr[i], b.wg[i], b.wb[i]}; }
inline Vec3 laneDirection(const RayBatch& b, int i) { return {b.dx[i], b.dy[i], b.dz[i]}; }

// The paper's termination: "until the maximum ray depth is achieved or the contributed
// radiance falls below a specified threshold" — with Russian roulette below the threshold so
// that the estimate stays unbiased: survivors are reweighted by 1 / survival probability.
inline bool continuePath(const ShadingPolicy& policy, int newDepth, std::uint64_t key,
                         std::uint32_t branch, Vec3& weight) {
    if (newDepth > policy.maxDepth) return false;
    float m = maxComponent(weight);
    if (!(m > 0)) return false;
    if (policy.rouletteEnabled && m < policy.rrThreshold) {
        float q = m / policy.rrThreshold;
        if (kernels::uniform(key, kDimRoulette + branch) >= q) return false;
        weight = weight / q;
    }
    return true;
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
    out.wr[j] = weight.x; out.wg[j] = weight.y; out.wb[j] = weight.z;
    out.rngKey[j] = kernels::hashCombine(parent.rngKey[i], 0x100u + branch);
    out.depth[j] = depth;
    out.specularDepth[j] = specularDepth;
    out.flags[j] = flags;
}

// Writes an occlusion ray from surface point p towards a light sample at `distance` along wi
// (infinity for directional lights and the sky), carrying its unoccluded contribution.
inline void spawnShadowRay(RayBatch& out, const RayBatch& parent, int i, const Vec3& p,
                           const Vec3& ng, const Vec3& wi, float distance, const Vec3& contribution,
                           float eps) {
    Vec3 o = offsetRayOrigin(p, ng, wi, eps);
    // Aim from the offset origin at the light point itself and stop short of it by a relative
    // margin. Keeping wi would shift the ray parallel to itself: it would meet the light's
    // plane sooner by offset * (1 - cos^2) / cos, which exceeds the margin at grazing angles,
    // and the light would occlude its own sample (surfaces parallel to a nearby light lost
    // up to a third of its direct light, and path mode all light relayed by them).
    Vec3 dir = wi;
    float tfar = kInfinity;
    if (distance != kInfinity) {
        Vec3 toLight = p + wi * distance - o;
        float len = length(toLight);
        dir = toLight / len;
        tfar = len * (1.0f - 1e-4f);
    }
    int j = out.push(o.x, o.y, o.z, dir.x, dir.y, dir.z, 0.0f, tfar);
    out.pixel[j] = parent.pixel[i];
    out.sample[j] = parent.sample[i];
    out.wr[j] = contribution.x; out.wg[j] = contribution.y; out.wb[j] = contribution.z;
    out.rngKey[j] = 0;
    out.depth[j] = parent.depth[i];
    out.specularDepth[j] = 0;
    out.flags[j] = 0;
    out.prevPdf[j] = 0;
    out.prevCos[j] = 0;
}

} // namespace rayproc
