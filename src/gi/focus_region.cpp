#include "gi/focus_region.h"

#include "accel/embree_scene.h"
#include "engine/camera_emitter.h"
#include "engine/intersect.h"
#include "engine/ray_batch.h"
#include "engine/stats.h"
#include "kernels/camera_rays.h"
#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace rayproc {

Bounds3 FocusRegion::emissionBounds() const {
    if (bounds.empty()) return bounds;
    float m = kFocusMargin * length(bounds.diagonal());
    Bounds3 b = bounds;
    b.lo = b.lo - Vec3(m, m, m);
    b.hi = b.hi + Vec3(m, m, m);
    return b;
}

FocusRegion cameraFocusRegion(const Scene& scene, const EmbreeScene& accel, int packetWidth,
                              int probeRays) {
    FocusRegion region;
    const Camera& cam = scene.camera;
    // A grid with the image's aspect: nx * ny ~ probeRays, at pixel-centre film positions.
    double aspect = double(cam.width) / double(std::max(1, cam.height));
    int ny = std::clamp(int(std::lround(std::sqrt(double(probeRays) / aspect))), 1, cam.height);
    int nx = std::clamp(int(std::lround(double(probeRays) / ny)), 1, cam.width);
    kernels::CameraFrame frame = cameraFrame(cam);
    frame.lensRadius = 0; // the pinhole ray through each pixel: the hits bound what is in view

    Intersector intersector(accel.root(), packetWidth);
    ThreadStats stats;
    auto batch = std::make_unique<RayBatch>();
    std::vector<Vec3> points;
    auto flush = [&] {
        if (batch->count == 0) return;
        intersector.trace(*batch, stats);
        for (int i = 0; i < batch->count; ++i) {
            if (!batch->hit(i)) continue;
            Vec3 p{batch->ox[i] + batch->t[i] * batch->dx[i],
                   batch->oy[i] + batch->t[i] * batch->dy[i],
                   batch->oz[i] + batch->t[i] * batch->dz[i]};
            if (!isFinite(p)) continue;
            points.push_back(p);
        }
        batch->count = 0;
    };
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            float fx = (float(i) + 0.5f) * float(cam.width) / float(nx);
            float fy = (float(j) + 0.5f) * float(cam.height) / float(ny);
            float zero = 0, o[3], d[3];
            kernels::generateCameraRays(frame, 1, &fx, &fy, &zero, &zero, &o[0], &o[1], &o[2],
                                        &d[0], &d[1], &d[2]);
            int k = batch->push(o[0], o[1], o[2], d[0], d[1], d[2], 0.0f, kInfinity);
            batch->pixel[k] = 0;
            ++region.rays;
            if (batch->full()) flush();
        }
    flush();

    // Per axis, the central (1 - 2 kFocusTrim) of the hits: a few far points seen through a
    // window or past an edge do not set the region's size.
    region.hits = points.size();
    if (!points.empty()) {
        std::vector<float> axis(points.size());
        std::size_t lo = std::size_t(kFocusTrim * double(points.size()));
        std::size_t hi = points.size() - 1 - lo;
        for (int a = 0; a < 3; ++a) {
            for (std::size_t k = 0; k < points.size(); ++k) axis[k] = points[k][a];
            std::nth_element(axis.begin(), axis.begin() + std::ptrdiff_t(lo), axis.end());
            float vlo = axis[lo];
            std::nth_element(axis.begin(), axis.begin() + std::ptrdiff_t(hi), axis.end());
            float vhi = axis[hi];
            region.bounds.lo[a] = vlo;
            region.bounds.hi[a] = vhi;
        }
    }
    Bounds3 world = scene.worldBounds();
    if (region.hits == 0 || world.empty()) return region;
    float regionRadius = 0.5f * length(region.bounds.diagonal());
    float worldRadius = 0.5f * length(world.diagonal());
    region.active = std::isfinite(worldRadius) && regionRadius > 0 &&
                    regionRadius <= kFocusRadiusFraction * worldRadius;
    return region;
}

} // namespace rayproc
