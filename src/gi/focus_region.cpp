#include "gi/focus_region.h"

#include "accel/embree_scene.h"
#include "engine/camera_emitter.h"
#include "engine/intersect.h"
#include "engine/material_bsdf.h"
#include "engine/path_state.h"
#include "kernels/bsdf.h"
#include "engine/ray_batch.h"
#include "engine/stats.h"
#include "kernels/camera_rays.h"
#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace rayproc {

namespace {

Bounds3 grown(const Bounds3& bounds) {
    if (bounds.empty()) return bounds;
    float m = kFocusMargin * length(bounds.diagonal());
    Bounds3 b = bounds;
    b.lo = b.lo - Vec3(m, m, m);
    b.hi = b.hi + Vec3(m, m, m);
    return b;
}

// Per axis, the central (1 - 2 kFocusTrim) of the points: a few far points seen through a
// window or past an edge do not set the region's size.
Bounds3 trimmedBounds(const std::vector<Vec3>& points) {
    Bounds3 b;
    if (points.empty()) return b;
    std::vector<float> axis(points.size());
    std::size_t lo = std::size_t(kFocusTrim * double(points.size()));
    std::size_t hi = points.size() - 1 - lo;
    for (int a = 0; a < 3; ++a) {
        for (std::size_t k = 0; k < points.size(); ++k) axis[k] = points[k][a];
        std::nth_element(axis.begin(), axis.begin() + std::ptrdiff_t(lo), axis.end());
        b.lo[a] = axis[lo];
        std::nth_element(axis.begin(), axis.begin() + std::ptrdiff_t(hi), axis.end());
        b.hi[a] = axis[hi];
    }
    return b;
}

// The direction a camera probe continues in past a mirror or glass hit (refracted if it can be,
// reflected otherwise; straight on through thin glass; rough glass as if smooth, the centre of
// its lobe, since caustic photons go through it too); false at other materials.
bool specularContinuation(const Scene& scene, const SurfaceHit& h, const Vec3& d, Vec3& wi, Vec3& g) {
    Vec3 wo = -d;
    int material = resolveMix(scene, h.material, h, wo);
    const Material& m = scene.materials[std::size_t(material)];
    const MaterialClass cls = materialClass(scene.materials, material);
    if (cls != MaterialClass::Specular &&
        !(cls == MaterialClass::Glossy && m.type == MaterialType::Dielectric))
        return false;
    bool front = dot(wo, h.ng) > 0;
    Vec3 n = front ? h.ns : -h.ns;
    g = front ? h.ng : -h.ng;
    wi = kernels::reflect(wo, n);
    if (m.type == MaterialType::Dielectric) {
        Vec3 wt;
        if (kernels::refract(wo, n, front ? m.ior : 1.0f / m.ior, wt)) wi = wt;
    } else if (m.type == MaterialType::ThinDielectric) {
        wi = d;
    }
    return true;
}

// Traces the camera's probe rays batch by batch, and the rays continuing past specular first
// (or later) hits level by level; collects the hit points.
class FocusProbe {
public:
    FocusProbe(const Scene& scene, const EmbreeScene& accel, int packetWidth)
        : m_scene(scene), m_accel(accel), m_intersector(accel.root(), packetWidth),
          m_batch(std::make_unique<RayBatch>()), m_next(std::make_unique<RayBatch>()) {}

    void push(const float o[3], const float d[3]) {
        int k = m_batch->push(o[0], o[1], o[2], d[0], d[1], d[2], 0.0f, kInfinity);
        m_batch->pixel[k] = 0;
        if (m_batch->full()) flush();
    }

    void flush() {
        if (m_batch->count == 0) return;
        traceLevel(*m_batch, *m_next, true);
        for (int bounce = 0; bounce < kFocusSpecularBounces && m_next->count > 0; ++bounce) {
            std::swap(m_batch, m_next);
            traceLevel(*m_batch, *m_next, false);
        }
        m_next->count = 0;
        m_batch->count = 0;
    }

    std::vector<Vec3> points;      // first hits
    std::vector<Vec3> chainPoints; // hits past a mirror or smooth glass

private:
    void traceLevel(RayBatch& in, RayBatch& out, bool first) {
        m_intersector.trace(in, m_stats);
        for (int i = 0; i < in.count; ++i) {
            if (!in.hit(i)) continue;
            Vec3 o{in.ox[i], in.oy[i], in.oz[i]}, d{in.dx[i], in.dy[i], in.dz[i]};
            Vec3 p = o + d * in.t[i];
            if (!isFinite(p)) continue;
            (first ? points : chainPoints).push_back(p);
            if (out.full()) continue;
            SurfaceHit h = m_accel.surface(in.instId[i], in.geomId[i], in.primId[i], in.u[i],
                                           in.v[i], o, d, in.t[i]);
            Vec3 wi, g;
            if (!specularContinuation(m_scene, h, d, wi, g)) continue;
            Vec3 no = offsetRayOrigin(h, g, wi);
            int k = out.push(no.x, no.y, no.z, wi.x, wi.y, wi.z, 0.0f, kInfinity);
            out.pixel[k] = 0;
        }
        in.count = 0;
    }

    const Scene& m_scene;
    const EmbreeScene& m_accel;
    Intersector m_intersector;
    ThreadStats m_stats;
    std::unique_ptr<RayBatch> m_batch, m_next;
};

} // namespace

Bounds3 FocusRegion::emissionBounds() const { return grown(bounds); }

Bounds3 FocusRegion::causticEmissionBounds() const { return grown(specularBounds); }

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

    FocusProbe probe(scene, accel, packetWidth);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            float fx = (float(i) + 0.5f) * float(cam.width) / float(nx);
            float fy = (float(j) + 0.5f) * float(cam.height) / float(ny);
            float zero = 0, o[3], d[3];
            kernels::generateCameraRays(frame, 1, &fx, &fy, &zero, &zero, &o[0], &o[1], &o[2],
                                        &d[0], &d[1], &d[2]);
            ++region.rays;
            probe.push(o, d);
        }
    probe.flush();

    region.hits = probe.points.size();
    region.bounds = trimmedBounds(probe.points);
    region.specularBounds = region.bounds;
    if (!probe.chainPoints.empty()) {
        probe.chainPoints.insert(probe.chainPoints.end(), probe.points.begin(),
                                 probe.points.end());
        region.specularBounds = trimmedBounds(probe.chainPoints);
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
