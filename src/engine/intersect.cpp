#include "engine/intersect.h"

#include "core/error.h"
#include "engine/ray_recorder.h"

#include <algorithm>

namespace rayproc {

namespace {

// One generic packet routine over the width K; the traits pick Embree's K-wide types and calls.
template <int K> struct Packet;
template <> struct Packet<4> {
    using RayHit = RTCRayHit4;
    using Ray = RTCRay4;
    static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) {
        rtcIntersect4(v, s, c, r);
    }
    static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Ray* r) {
        rtcOccluded4(v, s, c, r);
    }
};
template <> struct Packet<8> {
    using RayHit = RTCRayHit8;
    using Ray = RTCRay8;
    static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) {
        rtcIntersect8(v, s, c, r);
    }
    static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Ray* r) {
        rtcOccluded8(v, s, c, r);
    }
};
template <> struct Packet<16> {
    using RayHit = RTCRayHit16;
    using Ray = RTCRay16;
    static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) {
        rtcIntersect16(v, s, c, r);
    }
    static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Ray* r) {
        rtcOccluded16(v, s, c, r);
    }
};

template <class R>
void loadRays(R& r, const WorkBatch& b, int base, int n, int* valid, int K) {
    for (int k = 0; k < K; ++k) {
        int i = base + std::min(k, n - 1); // inactive lanes repeat a valid ray: no garbage
        valid[k] = k < n ? -1 : 0;
        r.org_x[k] = b.ox[i]; r.org_y[k] = b.oy[i]; r.org_z[k] = b.oz[i];
        r.dir_x[k] = b.dx[i]; r.dir_y[k] = b.dy[i]; r.dir_z[k] = b.dz[i];
        r.tnear[k] = b.tnear[i]; r.tfar[k] = b.tfar[i];
        r.time[k] = 0; r.mask[k] = 0xffffffffu; r.id[k] = unsigned(i); r.flags[k] = 0;
    }
}

template <int K>
void occludePackets(RTCScene scene, ShadowBatch& b, RTCIntersectContext* ctx) {
    alignas(64) int valid[K];
    for (int base = 0; base < b.count; base += K) {
        int n = std::min(K, b.count - base);
        alignas(64) typename Packet<K>::Ray r;
        loadRays(r, b, base, n, valid, K);
        Packet<K>::occluded(valid, scene, ctx, &r);
        for (int k = 0; k < n; ++k) b.tfar[base + k] = r.tfar[k];
    }
}

template <int K>
void intersectPackets(RTCScene scene, HitBatch& b, RTCIntersectContext* ctx) {
    alignas(64) int valid[K];
    for (int base = 0; base < b.count; base += K) {
        int n = std::min(K, b.count - base);
        alignas(64) typename Packet<K>::RayHit rh;
        loadRays(rh.ray, b, base, n, valid, K);
        for (int k = 0; k < K; ++k) {
            rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        }
        Packet<K>::intersect(valid, scene, ctx, &rh);
        for (int k = 0; k < n; ++k) {
            int i = base + k;
            b.t[i] = rh.ray.tfar[k];
            b.u[i] = rh.hit.u[k];
            b.v[i] = rh.hit.v[k];
            b.geomId[i] = rh.hit.geomID[k];
            b.primId[i] = rh.hit.primID[k];
            b.instId[i] = rh.hit.instID[0][k];
        }
    }
}

RTCRayHit singleRay(const WorkBatch& b, int i) {
    RTCRayHit rh;
    rh.ray.org_x = b.ox[i]; rh.ray.org_y = b.oy[i]; rh.ray.org_z = b.oz[i];
    rh.ray.dir_x = b.dx[i]; rh.ray.dir_y = b.dy[i]; rh.ray.dir_z = b.dz[i];
    rh.ray.tnear = b.tnear[i]; rh.ray.tfar = b.tfar[i];
    rh.ray.time = 0; rh.ray.mask = 0xffffffffu; rh.ray.id = unsigned(i); rh.ray.flags = 0;
    return rh;
}

void occludeSingle(RTCScene scene, ShadowBatch& b, RTCIntersectContext* ctx) {
    for (int i = 0; i < b.count; ++i) {
        RTCRayHit rh = singleRay(b, i);
        rtcOccluded1(scene, ctx, &rh.ray);
        b.tfar[i] = rh.ray.tfar;
    }
}

void intersectSingle(RTCScene scene, HitBatch& b, RTCIntersectContext* ctx) {
    for (int i = 0; i < b.count; ++i) {
        RTCRayHit rh = singleRay(b, i);
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, ctx, &rh);
        b.t[i] = rh.ray.tfar;
        b.u[i] = rh.hit.u;
        b.v[i] = rh.hit.v;
        b.geomId[i] = rh.hit.geomID;
        b.primId[i] = rh.hit.primID;
        b.instId[i] = rh.hit.instID[0];
    }
}

} // namespace

bool isValidPacketWidth(int width) {
    return width == 1 || width == 4 || width == 8 || width == 16;
}

Intersector::Intersector(RTCScene scene, int width)
    : m_scene(scene), m_width(width), m_recorder(RayRecorder::active()) {
    RAYPROC_CHECK(isValidPacketWidth(width));
}

RTCIntersectContext Intersector::begin(WorkBatch& b, ThreadStats& stats, bool occlusion) const {
    StageId id = occlusion ? StageId::Occlude : StageId::Intersect;
    if (m_recorder) m_recorder->record(b, occlusion);
    stats.stages[int(id)].raysIn += b.count;
    stats.raysTraced += b.count;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    // Primary rays of a tile are coherent; everything spawned at surfaces is not.
    ctx.flags = b.kind == RayKind::Camera ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT
                                          : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    return ctx;
}

void Intersector::trace(HitBatch& b, ThreadStats& stats) const {
    RTCIntersectContext ctx = begin(b, stats, false); // records first: untimed
    StageTimer timer(stats, StageId::Intersect);
    switch (m_width) {
    case 1: intersectSingle(m_scene, b, &ctx); break;
    case 4: intersectPackets<4>(m_scene, b, &ctx); break;
    case 8: intersectPackets<8>(m_scene, b, &ctx); break;
    default: intersectPackets<16>(m_scene, b, &ctx); break;
    }
}

void Intersector::trace(ShadowBatch& b, ThreadStats& stats) const {
    RTCIntersectContext ctx = begin(b, stats, true); // records first: untimed
    StageTimer timer(stats, StageId::Occlude);
    switch (m_width) {
    case 1: occludeSingle(m_scene, b, &ctx); break;
    case 4: occludePackets<4>(m_scene, b, &ctx); break;
    case 8: occludePackets<8>(m_scene, b, &ctx); break;
    default: occludePackets<16>(m_scene, b, &ctx); break;
    }
}

} // namespace rayproc
