// Benchmark fixtures: the scenes every benchmark shares, loaded and built once per process,
// and the ray sets of the intersection benchmarks, generated once per scene.
//
// Ray sets are SoA arrays of exactly kRaySetSize rays:
//  - coherent: camera rays as the CameraEmitter makes them (one 16x16 tile = one batch, rays
//    in tile order, one jittered sample per pixel) at the scene's own resolution, taken from
//    kRaySetSize / 256 tiles spread evenly over the image;
//  - incoherent: from the first hits of the scene's camera rays (every pixel's centre, cycled),
//    origins offset off the surface along the normal, directions uniform over the hemisphere
//    on the viewer's side (a direction into the surface would be no ray the engine makes).
#pragma once

#include "accel/embree_scene.h"
#include "core/math.h"
#include "engine/camera_emitter.h"
#include "engine/render_context.h"
#include "kernels/camera_rays.h"
#include "kernels/random.h"
#include "kernels/sampling.h"
#include "scene/scene_loader.h"

#include <embree3/rtcore.h>

#include <algorithm>

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace rayproc::bench {

// Rays traced per benchmark iteration: 256 batches of 256.
constexpr int kRaySetSize = 65536;

// Benchmark scenes by short name: "cornell" (scenes/cornell-box.json, 512x512) and "million"
// (scenes/million.json, ~1M triangles, 1024x768).
inline std::string scenePath(const std::string& name) {
    std::string file = name == "cornell" ? "cornell-box.json" : name + ".json";
    return std::string(RAYPROC_SOURCE_DIR) + "/scenes/" + file;
}

struct LoadedScene {
    std::unique_ptr<Scene> scene;
    std::unique_ptr<EmbreeScene> accel;
    Camera nativeCamera; // the file's camera: modes benchmarks may change scene->camera
};

// Loaded on first use and kept for the whole process. Not thread-safe: call it from the
// benchmark's setup (before any threads of a ->Threads(n) benchmark start).
inline LoadedScene& loadedScene(const std::string& name) {
    static std::map<std::string, LoadedScene> cache;
    auto it = cache.find(name);
    if (it != cache.end()) return it->second;
    LoadedScene s;
    s.scene = loadScene(scenePath(name));
    s.accel = std::make_unique<EmbreeScene>(*s.scene);
    s.nativeCamera = s.scene->camera;
    return cache.emplace(name, std::move(s)).first->second;
}

struct RaySet {
    std::vector<float> ox, oy, oz, dx, dy, dz, tnear, tfar;
    int size() const { return int(ox.size()); }
    void push(const Vec3& o, const Vec3& d) {
        ox.push_back(o.x); oy.push_back(o.y); oz.push_back(o.z);
        dx.push_back(d.x); dy.push_back(d.y); dz.push_back(d.z);
        tnear.push_back(0.0f); tfar.push_back(kInfinity);
    }
};

// Camera rays of one tile (tile order, jittered sub-pixel position), appended to `out`.
inline void appendTileRays(const kernels::CameraFrame& frame, const Camera& cam, int tileX,
                           int tileY, RaySet& out) {
    constexpr int kTile = CameraEmitter::kTile;
    alignas(64) float fx[kTile * kTile], fy[kTile * kTile], lu[kTile * kTile], lv[kTile * kTile];
    alignas(64) float ox[kTile * kTile], oy[kTile * kTile], oz[kTile * kTile];
    alignas(64) float dx[kTile * kTile], dy[kTile * kTile], dz[kTile * kTile];
    int n = 0;
    for (int y = tileY * kTile; y < std::min((tileY + 1) * kTile, cam.height); ++y) {
        for (int x = tileX * kTile; x < std::min((tileX + 1) * kTile, cam.width); ++x) {
            std::uint64_t key = kernels::pathKey(1, std::uint32_t(y * cam.width + x), 0);
            fx[n] = float(x) + kernels::uniform(key, 0);
            fy[n] = float(y) + kernels::uniform(key, 1);
            lu[n] = kernels::uniform(key, 2);
            lv[n] = kernels::uniform(key, 3);
            ++n;
        }
    }
    kernels::generateCameraRays(frame, n, fx, fy, lu, lv, ox, oy, oz, dx, dy, dz);
    for (int i = 0; i < n; ++i) out.push({ox[i], oy[i], oz[i]}, {dx[i], dy[i], dz[i]});
}

inline RaySet makeCoherentRays(const Camera& cam) {
    constexpr int kTile = CameraEmitter::kTile;
    kernels::CameraFrame frame = cameraFrame(cam);
    int tilesX = (cam.width + kTile - 1) / kTile, tilesY = (cam.height + kTile - 1) / kTile;
    int tiles = tilesX * tilesY, wanted = kRaySetSize / (kTile * kTile);
    RaySet rays;
    // Tiles i * tiles / wanted: evenly spread, each one whole (a full batch when not clipped).
    for (int i = 0; i < wanted && rays.size() < kRaySetSize; ++i) {
        int t = int((long long)i * tiles / wanted);
        appendTileRays(frame, cam, t % tilesX, t / tilesX, rays);
    }
    // Tiles clipped by the image border leave a few lanes short; top up from the first tiles.
    for (int t = 0; rays.size() < kRaySetSize; ++t) {
        RaySet extra;
        appendTileRays(frame, cam, t % tilesX, t / tilesX, extra);
        for (int i = 0; i < extra.size() && rays.size() < kRaySetSize; ++i)
            rays.push({extra.ox[i], extra.oy[i], extra.oz[i]}, {extra.dx[i], extra.dy[i], extra.dz[i]});
    }
    return rays;
}

inline RaySet makeIncoherentRays(const EmbreeScene& accel, const Camera& cam) {
    kernels::CameraFrame frame = cameraFrame(cam);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RaySet rays;
    int pixels = cam.width * cam.height;
    // Walk the pixels with a stride coprime to their count, so that a partial walk is spread
    // over the whole image; misses (sky) are skipped.
    int stride = 7919;
    while (pixels % stride == 0) stride += 2;
    for (long long k = 0; rays.size() < kRaySetSize && k < 64LL * pixels; ++k) {
        int p = int((k * stride) % pixels);
        float fx = float(p % cam.width) + 0.5f, fy = float(p / cam.width) + 0.5f, l = 0.5f;
        float o[3], d[3];
        kernels::generateCameraRays(frame, 1, &fx, &fy, &l, &l, &o[0], &o[1], &o[2], &d[0],
                                    &d[1], &d[2]);
        RTCRayHit rh{};
        rh.ray.org_x = o[0]; rh.ray.org_y = o[1]; rh.ray.org_z = o[2];
        rh.ray.dir_x = d[0]; rh.ray.dir_y = d[1]; rh.ray.dir_z = d[2];
        rh.ray.tnear = 0; rh.ray.tfar = kInfinity; rh.ray.mask = 0xffffffffu;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(accel.root(), &ctx, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
        Vec3 org(o[0], o[1], o[2]), dir(d[0], d[1], d[2]);
        SurfaceHit h = accel.surface(rh.hit.instID[0], rh.hit.geomID, rh.hit.primID, rh.hit.u,
                                     rh.hit.v, org, dir, rh.ray.tfar);
        Vec3 n = dot(h.ng, dir) < 0 ? h.ng : -h.ng; // the viewer's side
        std::uint64_t key = kernels::pathKey(2, std::uint32_t(p), std::uint32_t(k / pixels));
        Vec3 wi = kernels::toWorld(kernels::uniformCone({kernels::uniform(key, 0),
                                                         kernels::uniform(key, 1)}, 0.0f), n);
        rays.push(offsetRayOrigin(h, n, wi), wi);
    }
    return rays;
}

// The ray sets of a scene, generated on first use. Same threading rule as loadedScene().
inline const RaySet& raySet(const std::string& sceneName, bool coherent) {
    static std::map<std::pair<std::string, bool>, RaySet> cache;
    auto key = std::make_pair(sceneName, coherent);
    auto it = cache.find(key);
    if (it != cache.end()) return it->second;
    LoadedScene& s = loadedScene(sceneName);
    RaySet rays = coherent ? makeCoherentRays(s.nativeCamera)
                           : makeIncoherentRays(*s.accel, s.nativeCamera);
    return cache.emplace(key, std::move(rays)).first->second;
}

// Fills the ray half of a bare Embree packet of 16 from struct-of-arrays rays (fields ox, oy,
// oz, dx, dy, dz, tnear, tfar) starting at `base`; ids are the rays' indices. The raw-Embree
// baselines of the intersection and engine-efficiency benchmarks share it.
template <class Soa>
inline void loadRay16(const Soa& rays, int base, RTCRay16& ray) {
    std::copy_n(&rays.ox[base], 16, ray.org_x);
    std::copy_n(&rays.oy[base], 16, ray.org_y);
    std::copy_n(&rays.oz[base], 16, ray.org_z);
    std::copy_n(&rays.dx[base], 16, ray.dir_x);
    std::copy_n(&rays.dy[base], 16, ray.dir_y);
    std::copy_n(&rays.dz[base], 16, ray.dir_z);
    std::copy_n(&rays.tnear[base], 16, ray.tnear);
    std::copy_n(&rays.tfar[base], 16, ray.tfar);
    for (int k = 0; k < 16; ++k) {
        ray.time[k] = 0;
        ray.mask[k] = 0xffffffffu;
        ray.id[k] = unsigned(base + k);
        ray.flags[k] = 0;
    }
}

} // namespace rayproc::bench
