// The offset itself, against Embree: random triangles, spheres and disks at every scale, near
// and far from the origin, in instances and not; rays leave random hit points in random
// directions (down to grazing, on both sides) from the offset origin and must never hit the
// surface they left. The same rays from the un-offset hit point do, which shows the test can fail.
#include "stress/stress_scenes.h"

#include <random>

namespace rayproc::test::stress {

namespace {

struct SelfHits {
    int tried = 0, offsetHits = 0, rawHits = 0;
};

Vec3 randomUnit(std::mt19937_64& rng) {
    std::normal_distribution<float> n;
    for (;;) {
        Vec3 v{n(rng), n(rng), n(rng)};
        if (lengthSquared(v) > 1e-6f) return normalize(v);
    }
}

// Traces one ray from o along d (unbounded) through bare rtcIntersect1.
RTCRayHit traceOne(const EmbreeScene& accel, const Vec3& o, const Vec3& d) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh{};
    rh.ray.org_x = o.x; rh.ray.org_y = o.y; rh.ray.org_z = o.z;
    rh.ray.dir_x = d.x; rh.ray.dir_y = d.y; rh.ray.dir_z = d.z;
    rh.ray.tnear = 0;
    rh.ray.tfar = kInfinity;
    rh.ray.mask = 0xffffffffu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(accel.root(), &ctx, &rh);
    return rh;
}

// Traces one ray; true when it hits primitive (geom, prim) of instance inst.
bool hitsSame(const EmbreeScene& accel, const Vec3& o, const Vec3& d, unsigned inst, unsigned geom,
              unsigned prim) {
    RTCRayHit rh = traceOne(accel, o, d);
    return rh.hit.geomID == geom && rh.hit.primID == prim && rh.hit.instID[0] == inst;
}

SelfHits probe(double scale, double translation, bool instanced, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> uni(0.0f, 1.0f);
    SceneBuilder b;
    int m = b.material(MaterialType::Diffuse, Vec3(0.5f));
    // Triangles of sizes from 1e-3 to 1 and needles, spheres, disks, in the unit cube.
    for (int t = 0; t < 60; ++t) {
        Vec3 c{uni(rng) * 2 - 1, uni(rng) * 2 - 1, uni(rng) * 2 - 1};
        float size = std::pow(10.0f, -3.0f * uni(rng));
        Vec3 a = c + randomUnit(rng) * size, bb = c + randomUnit(rng) * size;
        Vec3 cc = t % 10 == 0 ? a + (bb - a) * 0.5f + randomUnit(rng) * (size * 1e-3f)
                              : c + randomUnit(rng) * size;
        b.addMesh({a, bb, cc}, {0, 1, 2}, m);
    }
    for (int s = 0; s < 10; ++s) {
        auto n = std::make_unique<Node>();
        n->kind = Node::Kind::Shape;
        n->shape.type = s % 2 ? ShapeType::Sphere : ShapeType::Disk;
        n->shape.center = {uni(rng) * 2 - 1, uni(rng) * 2 - 1, uni(rng) * 2 - 1};
        n->shape.radius = std::pow(10.0f, -2.0f * uni(rng));
        n->shape.normal = randomUnit(rng);
        n->shape.material = m;
        b.scene->root->children.push_back(std::move(n));
    }
    b.scene->computeBounds();
    Frame f = Frame::make(scale, {translation, -translation, translation}, true);
    std::unique_ptr<Scene> scene;
    if (instanced) {
        // The same geometry in unit space, placed by an instance transform (float).
        auto group = std::make_unique<Node>();
        group->kind = Node::Kind::Group;
        group->children = std::move(b.scene->root->children);
        Affine a;
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) a.m[r][c] = float(f.r[r][c] * f.scale);
        }
        a.m[0][3] = float(f.translation.x);
        a.m[1][3] = float(f.translation.y);
        a.m[2][3] = float(f.translation.z);
        group->transform = a;
        b.scene->root->children.clear();
        b.scene->root->children.push_back(std::move(group));
        b.scene->computeBounds();
        scene = std::move(b.scene);
    } else {
        scene = b.take(f);
    }
    EmbreeScene accel(*scene);
    Bounds3 wb = scene->worldBounds();
    Vec3 centre = wb.center();
    float radius = 0.5f * length(wb.diagonal());

    SelfHits out;
    for (int i = 0; i < 6000; ++i) {
        // A ray from outside the scene through it.
        Vec3 dir = randomUnit(rng);
        Vec3 target = centre + Vec3(uni(rng) * 2 - 1, uni(rng) * 2 - 1, uni(rng) * 2 - 1) * (0.5f * radius);
        Vec3 o = target - dir * (2 * radius);
        RTCRayHit rh = traceOne(accel, o, dir);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
        SurfaceHit h = accel.surface(rh.hit.instID[0], rh.hit.geomID, rh.hit.primID, rh.hit.u,
                                     rh.hit.v, o, dir, rh.ray.tfar);
        // Spheres are closed: a ray leaving inwards meets the far side legitimately. Only rays
        // leaving outwards are checked there; flat shapes are checked on both sides.
        bool sphere = h.shape->type == ShapeType::Sphere;
        for (int k = 0; k < 4; ++k) {
            // Down to grazing: cos between 1e-4 and 1 (log-uniform), either side of the surface.
            float c = std::pow(10.0f, -4.0f * uni(rng));
            Vec3 t, bt;
            orthonormalBasis(h.ng, t, bt);
            float phi = 2 * kPi * uni(rng), s = std::sqrt(std::max(0.0f, 1 - c * c));
            float side = sphere || k % 2 == 0 ? 1.0f : -1.0f;
            Vec3 w = normalize(t * (s * std::cos(phi)) + bt * (s * std::sin(phi)) + h.ng * (c * side));
            if (dot(w, h.ng) * side <= 0) continue;
            ++out.tried;
            Vec3 start = offsetRayOrigin(h, h.ng, w);
            if (hitsSame(accel, start, w, rh.hit.instID[0], rh.hit.geomID, rh.hit.primID)) ++out.offsetHits;
            if (hitsSame(accel, h.p, w, rh.hit.instID[0], rh.hit.geomID, rh.hit.primID)) ++out.rawHits;
        }
    }
    return out;
}

} // namespace

TEST_CASE("Rays leaving an offset origin never hit the surface they left", "[stress][offset]") {
    int totalRaw = 0, totalTried = 0;
    for (double s : {1e-4, 1e-2, 1.0, 1e2, 1e4, 1e6}) {
        for (bool far : {false, true}) {
            for (bool instanced : {false, true}) {
                SelfHits r = probe(s, far ? 1e5 * s : 0.0, instanced, 17);
                INFO("scale " << s << (far ? " far" : "") << (instanced ? " instanced" : "")
                              << ": " << r.tried << " rays, " << r.offsetHits
                              << " self-hits from the offset origin, " << r.rawHits
                              << " from the hit point itself");
                CHECK(r.tried > 3000);
                CHECK(r.offsetHits == 0);
                totalRaw += r.rawHits;
                totalTried += r.tried;
            }
        }
    }
    // Without the offset the same rays do hit their own surface: the check can fail.
    INFO(totalRaw << " of " << totalTried << " rays hit their own surface without the offset");
    CHECK(totalRaw > totalTried / 100);
}

} // namespace rayproc::test::stress
