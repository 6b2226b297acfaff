// The intersection handler at every packet width: rtcIntersect1 and 4/8/16-wide packets (with
// partially valid packets at the end of a batch) must find the same hits, at the same bits of
// t, for camera rays and for incoherent rays from anywhere in the scene, and the same
// occlusion for shadow rays with finite tfar.
#include "engine/camera_emitter.h"
#include "engine/intersect.h"
#include "kernels/camera_rays.h"
#include "test_util.h"

#include <cstring>
#include <limits>
#include <random>

using namespace rayproc;
using namespace rayproc::test;

namespace {

constexpr int kCameraRays = 2048 + 37; // 8 full batches and a partial one
constexpr int kRandomRays = 2048 + 101;

using Batches = std::vector<std::unique_ptr<RayBatch>>;
using ShadowBatches = std::vector<std::unique_ptr<ShadowBatch>>;

void append(Batches& bs, RayKind kind, const Vec3& o, const Vec3& d, float tfar) {
    if (bs.empty() || bs.back()->full() || bs.back()->kind != kind) {
        bs.push_back(std::make_unique<RayBatch>());
        bs.back()->kind = kind;
    }
    bs.back()->push(o.x, o.y, o.z, d.x, d.y, d.z, 0.0f, tfar);
}

// Half the rays from the camera through random film positions, half from random points of the
// world bounds in random directions. `shadow` gives every ray a random finite tfar (some
// infinite) and makes all batches shadow batches.
Batches makeRays(const Scene& scene, bool shadow, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    std::normal_distribution<float> gauss;
    Bounds3 bounds = scene.worldBounds();
    float diag = length(bounds.diagonal());
    auto tfarFor = [&](int i) {
        if (!shadow || i % 8 == 0) return kInfinity;
        return u01(rng) * diag;
    };

    Batches bs;
    kernels::CameraFrame frame = cameraFrame(scene.camera);
    for (int i = 0; i < kCameraRays; ++i) {
        float fx = u01(rng) * frame.width, fy = u01(rng) * frame.height, lu = 0, lv = 0;
        float ox, oy, oz, dx, dy, dz;
        kernels::generateCameraRays(frame, 1, &fx, &fy, &lu, &lv, &ox, &oy, &oz, &dx, &dy, &dz);
        append(bs, shadow ? RayKind::Shadow : RayKind::Camera, {ox, oy, oz}, {dx, dy, dz},
               tfarFor(i));
    }
    for (int i = 0; i < kRandomRays; ++i) {
        Vec3 o = bounds.lo + bounds.diagonal() * Vec3(u01(rng), u01(rng), u01(rng));
        Vec3 d;
        do d = Vec3(gauss(rng), gauss(rng), gauss(rng));
        while (lengthSquared(d) < 1e-6f);
        append(bs, shadow ? RayKind::Shadow : RayKind::Reflection, o, normalize(d), tfarFor(i));
    }
    return bs;
}

template <class B>
std::vector<std::unique_ptr<B>> copyOf(const std::vector<std::unique_ptr<B>>& bs) {
    std::vector<std::unique_ptr<B>> out;
    for (auto& b : bs) out.push_back(std::make_unique<B>(*b));
    return out;
}

// The same rays in batches of type B (occlusion rays, photons), batch for batch.
template <class B> std::vector<std::unique_ptr<B>> sameRaysAs(const Batches& bs) {
    std::vector<std::unique_ptr<B>> out;
    for (auto& b : bs) {
        out.push_back(std::make_unique<B>());
        out.back()->kind = b->kind;
        for (int i = 0; i < b->count; ++i)
            out.back()->push(b->ox[i], b->oy[i], b->oz[i], b->dx[i], b->dy[i], b->dz[i],
                             b->tnear[i], b->tfar[i]);
    }
    return out;
}
ShadowBatches shadowsOf(const Batches& bs) { return sameRaysAs<ShadowBatch>(bs); }

bool sameBits(float a, float b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

// Distance in units in the last place between two finite floats of the same sign.
std::int64_t ulpDistance(float a, float b) {
    std::int32_t ia, ib;
    std::memcpy(&ia, &a, sizeof a);
    std::memcpy(&ib, &b, sizeof b);
    if ((ia < 0) != (ib < 0)) return std::numeric_limits<std::int64_t>::max();
    return std::abs(std::int64_t(ia) - std::int64_t(ib));
}

template <class B> struct TracedOf {
    std::vector<std::unique_ptr<B>> batches;
    std::uint64_t raysTraced = 0;
};
using Traced = TracedOf<RayBatch>;

template <class B>
TracedOf<B> traceAll(const std::vector<std::unique_ptr<B>>& rays, RTCScene scene, int width) {
    TracedOf<B> t{copyOf(rays), 0};
    Intersector isect(scene, width);
    ThreadStats stats;
    for (auto& b : t.batches) isect.trace(*b, stats);
    t.raysTraced = stats.raysTraced;
    return t;
}

} // namespace

TEST_CASE("Packet and single-ray paths give the same hits on thousands of random rays over "
          "every scene",
          "[engine][intersect]") {
    const std::vector<std::string> scenes = {"cornell-box", "cornell-spheres", "instances",
                                             "materials", "million"};
    for (const std::string& name : scenes) {
        INFO("scene " << name);
        auto scene = loadScene(scenePath(name));
        EmbreeScene accel(*scene);

        // Radiance rays: hits must agree in geomID / primID / instID and bit for bit in t.
        Batches rays = makeRays(*scene, false, 1234);
        Traced single = traceAll(rays, accel.root(), 1);
        std::size_t total = 0, hits = 0;
        for (auto& b : single.batches) {
            total += std::size_t(b->count);
            for (int i = 0; i < b->count; ++i) hits += b->hit(i);
        }
        REQUIRE(total == std::size_t(kCameraRays + kRandomRays));
        CHECK(single.raysTraced == total);
        CHECK(hits > total / 10); // the comparison is not vacuous
        CHECK(hits < total + 1);

        // Packets of every width agree with each other bit for bit (one traversal template).
        // Against rtcIntersect1, Embree 3.13's sphere intersector rounds t differently in its
        // single-ray and packet kernels (1 ulp typically, |dt| < 1e-7 (t + |o|) at most), so
        // sphere hits get a tolerance of 1e-6 (t + |o|); triangles, disks and all ids must
        // match exactly.
        Traced first = traceAll(rays, accel.root(), 4);
        for (int width : {4, 8, 16}) {
            INFO("packet width " << width);
            Traced packet = width == 4 ? Traced{copyOf(first.batches), first.raysTraced}
                                       : traceAll(rays, accel.root(), width);
            CHECK(packet.raysTraced == total);
            std::size_t idMismatch = 0, tMismatch = 0, uvMismatch = 0, sphereRounding = 0,
                        packetMismatch = 0;
            std::string details;
            for (std::size_t k = 0; k < rays.size(); ++k) {
                const RayBatch &s = *single.batches[k], &p = *packet.batches[k],
                               &f = *first.batches[k];
                for (int i = 0; i < s.count; ++i) {
                    if (p.geomId[i] != f.geomId[i] ||
                        (p.hit(i) && (!sameBits(p.t[i], f.t[i]) || p.primId[i] != f.primId[i] ||
                                      p.instId[i] != f.instId[i])))
                        ++packetMismatch;
                    bool idsEqual =
                        s.geomId[i] == p.geomId[i] &&
                        (!s.hit(i) || (s.primId[i] == p.primId[i] && s.instId[i] == p.instId[i]));
                    if (!idsEqual) {
                        if (idMismatch++ < 5)
                            details += "batch " + std::to_string(k) + " lane " + std::to_string(i) +
                                       ": geom " + std::to_string(s.geomId[i]) + "/" +
                                       std::to_string(p.geomId[i]) + " prim " +
                                       std::to_string(s.primId[i]) + "/" +
                                       std::to_string(p.primId[i]) + "\n";
                        continue;
                    }
                    if (!s.hit(i)) continue;
                    if (s.u[i] != p.u[i] || s.v[i] != p.v[i]) ++uvMismatch;
                    if (sameBits(s.t[i], p.t[i])) continue;
                    const Shape* shape = accel
                                             .surface(s.instId[i], s.geomId[i], s.primId[i], s.u[i],
                                                      s.v[i], {s.ox[i], s.oy[i], s.oz[i]},
                                                      {s.dx[i], s.dy[i], s.dz[i]}, s.t[i])
                                             .shape;
                    // The rounding error of a sphere's t scales with the distances involved
                    // (|o| and t), not with t alone: the tolerance is relative to t + |o|.
                    float scale = s.t[i] + length(Vec3{s.ox[i], s.oy[i], s.oz[i]});
                    if (shape->type == ShapeType::Sphere &&
                        std::abs(double(s.t[i]) - double(p.t[i])) <= 1e-6 * scale) {
                        ++sphereRounding;
                        continue;
                    }
                    if (tMismatch++ < 5)
                        details += "batch " + std::to_string(k) + " lane " + std::to_string(i) +
                                   ": t " + std::to_string(s.t[i]) + " vs " +
                                   std::to_string(p.t[i]) + " (" +
                                   std::to_string(ulpDistance(s.t[i], p.t[i])) + " ulp)\n";
                }
            }
            INFO(details);
            INFO("sphere hits within tolerance but not bit-identical: " << sphereRounding);
            CHECK(packetMismatch == 0);
            CHECK(idMismatch == 0);
            CHECK(tMismatch == 0);
            CHECK(uvMismatch == 0);
        }

        // Shadow rays with finite tfar: the same occlusion at every width.
        ShadowBatches shadowRays = shadowsOf(makeRays(*scene, true, 4321));
        TracedOf<ShadowBatch> shadowSingle = traceAll(shadowRays, accel.root(), 1);
        std::size_t occluded = 0;
        for (auto& b : shadowSingle.batches)
            for (int i = 0; i < b->count; ++i) occluded += b->occluded(i);
        CHECK(occluded > 0);
        CHECK(occluded < total);
        for (int width : {4, 8, 16}) {
            INFO("shadow packet width " << width);
            TracedOf<ShadowBatch> packet = traceAll(shadowRays, accel.root(), width);
            std::size_t mismatch = 0;
            for (std::size_t k = 0; k < shadowRays.size(); ++k) {
                const ShadowBatch &s = *shadowSingle.batches[k], &p = *packet.batches[k];
                for (int i = 0; i < s.count; ++i) {
                    if (s.occluded(i) != p.occluded(i) || !sameBits(s.tfar[i], p.tfar[i])) {
                        if (mismatch++ < 5)
                            UNSCOPED_INFO("batch " << k << " lane " << i << ": tfar " << s.tfar[i]
                                                   << " vs " << p.tfar[i]);
                    }
                }
            }
            CHECK(mismatch == 0);
        }
    }
}

TEST_CASE("Photons get the hits rays get: a PhotonBatch is traced as a RayBatch of the same "
          "rays, at every width",
          "[engine][intersect]") {
    auto scene = loadScene(scenePath(GENERATE(std::string("cornell-box"), "instances")));
    EmbreeScene accel(*scene);
    Batches rays = makeRays(*scene, false, 99);
    auto photons = sameRaysAs<PhotonBatch>(rays);
    for (int width : {1, 4, 8, 16}) {
        INFO("width " << width);
        Traced r = traceAll(rays, accel.root(), width);
        TracedOf<PhotonBatch> p = traceAll(photons, accel.root(), width);
        CHECK(p.raysTraced == r.raysTraced);
        std::size_t mismatch = 0, hits = 0;
        for (std::size_t k = 0; k < rays.size(); ++k) {
            const RayBatch& a = *r.batches[k];
            const PhotonBatch& b = *p.batches[k];
            for (int i = 0; i < a.count; ++i) {
                hits += a.hit(i);
                // A miss leaves the rest of the hit as Embree found it: only its id counts.
                if (a.geomId[i] != b.geomId[i] ||
                    (a.hit(i) && (a.primId[i] != b.primId[i] || a.instId[i] != b.instId[i] ||
                                  !sameBits(a.t[i], b.t[i]) || !sameBits(a.u[i], b.u[i]) ||
                                  !sameBits(a.v[i], b.v[i]))))
                    ++mismatch;
            }
        }
        CHECK(hits > 0);
        CHECK(mismatch == 0);
    }
}
