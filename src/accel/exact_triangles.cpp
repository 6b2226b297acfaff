#include "accel/exact_triangles.h"

#include "kernels/exact_triangle.h"

#include <algorithm>
#include <limits>

namespace rayproc {

namespace {

struct Corners {
    const Vec3 *p0, *p1, *p2;
};

Corners corners(const ExactTriangles& x, unsigned prim) {
    const TriangleMesh& m = *x.mesh;
    unsigned t = x.triangles[prim];
    return {&m.positions[m.indices[3 * t]], &m.positions[m.indices[3 * t + 1]],
            &m.positions[m.indices[3 * t + 2]]};
}

// The float vertices bound the triangle exactly: no rounding to widen for.
void exactBounds(const RTCBoundsFunctionArguments* args) {
    const auto& x = *static_cast<const ExactTriangles*>(args->geometryUserPtr);
    Corners c = corners(x, args->primID);
    Vec3 lo = vmin(*c.p0, vmin(*c.p1, *c.p2)), hi = vmax(*c.p0, vmax(*c.p1, *c.p2));
    RTCBounds* b = args->bounds_o;
    b->lower_x = lo.x;
    b->lower_y = lo.y;
    b->lower_z = lo.z;
    b->upper_x = hi.x;
    b->upper_y = hi.y;
    b->upper_z = hi.z;
}

// The hit of lane i against primitive `prim`, if it lies in (tnear, tfar] and survives the
// cut-out; Embree's triangle test accepts the same interval.
bool hitLane(const ExactTriangles& x, unsigned instId, unsigned prim, RTCRayN* ray, unsigned N,
             unsigned i, kernels::ExactTriangleHit& h) {
    Vec3 o{RTCRayN_org_x(ray, N, i), RTCRayN_org_y(ray, N, i), RTCRayN_org_z(ray, N, i)};
    Vec3 d{RTCRayN_dir_x(ray, N, i), RTCRayN_dir_y(ray, N, i), RTCRayN_dir_z(ray, N, i)};
    Corners c = corners(x, prim);
    h = kernels::intersectTriangleExact(o, d, *c.p0, *c.p1, *c.p2);
    if (!h.inside) return false;
    if (!(h.t > double(RTCRayN_tnear(ray, N, i)) && h.t <= double(RTCRayN_tfar(ray, N, i))))
        return false;
    if (x.alpha) {
        const float r[6] = {o.x, o.y, o.z, d.x, d.y, d.z};
        if (!alphaKeeps(*x.alpha, instId, x.triangles[prim], float(h.u), float(h.v), r))
            return false;
    }
    return true;
}

void exactIntersect(const RTCIntersectFunctionNArguments* args) {
    const auto& x = *static_cast<const ExactTriangles*>(args->geometryUserPtr);
    RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, args->N);
    RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, args->N);
    const unsigned N = args->N, prim = args->primID;
    const unsigned instId = args->context->instID[0];
    for (unsigned i = 0; i < N; ++i) {
        if (args->valid[i] == 0) continue;
        kernels::ExactTriangleHit h;
        if (!hitLane(x, instId, prim, ray, N, i, h)) continue;
        float t = float(h.t);
        float& tfar = RTCRayN_tfar(ray, N, i);
        // A tie (a ray along the edge two triangles share) goes to the lower triangle index
        // whichever order the traversal tests them in, where both boxes are entered (Embree's
        // box test can skip one by rounding: docs/architecture.md, the intersection handler).
        if (t > tfar) continue;
        if (t == tfar && RTCHitN_geomID(hit, N, i) == args->geomID &&
            RTCHitN_instID(hit, N, i, 0) == instId &&
            x.triangles[RTCHitN_primID(hit, N, i)] < x.triangles[prim])
            continue;
        Corners c = corners(x, prim);
        double ex = double(c.p1->x) - c.p0->x, ey = double(c.p1->y) - c.p0->y,
               ez = double(c.p1->z) - c.p0->z;
        double fx = double(c.p2->x) - c.p0->x, fy = double(c.p2->y) - c.p0->y,
               fz = double(c.p2->z) - c.p0->z;
        tfar = t;
        RTCHitN_u(hit, N, i) = float(h.u);
        RTCHitN_v(hit, N, i) = float(h.v);
        RTCHitN_Ng_x(hit, N, i) = float(ey * fz - ez * fy); // (p1 - p0) x (p2 - p0), as Embree
        RTCHitN_Ng_y(hit, N, i) = float(ez * fx - ex * fz);
        RTCHitN_Ng_z(hit, N, i) = float(ex * fy - ey * fx);
        RTCHitN_primID(hit, N, i) = prim;
        RTCHitN_geomID(hit, N, i) = args->geomID;
        RTCHitN_instID(hit, N, i, 0) = instId;
    }
}

void exactOccluded(const RTCOccludedFunctionNArguments* args) {
    const auto& x = *static_cast<const ExactTriangles*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] == 0) continue;
        kernels::ExactTriangleHit h;
        if (hitLane(x, args->context->instID[0], args->primID, args->ray, args->N, i, h))
            RTCRayN_tfar(args->ray, args->N, i) = -std::numeric_limits<float>::infinity();
    }
}

} // namespace

RTCGeometry newExactTriangleGeometry(RTCDevice device, const ExactTriangles& tris) {
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geom, unsigned(tris.triangles.size()));
    rtcSetGeometryUserData(geom, const_cast<ExactTriangles*>(&tris));
    rtcSetGeometryBoundsFunction(geom, exactBounds, nullptr);
    rtcSetGeometryIntersectFunction(geom, exactIntersect);
    rtcSetGeometryOccludedFunction(geom, exactOccluded);
    return geom;
}

} // namespace rayproc
