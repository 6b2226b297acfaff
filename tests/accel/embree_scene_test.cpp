// The Embree mapping against closed forms: spheres from outside and inside, disks, an
// ellipsoid (a non-uniformly scaled sphere instance), nested instances resolved to the right
// shape, material and composed transform, and the placed / unique geometry counts.
#include "engine/material_bsdf.h"
#include "pbrt/pbrt_test_util.h"
#include "test_util.h"

#include <embree3/rtcore.h>

#include <random>

using namespace rayproc;
using namespace rayproc::test;

namespace {

struct Traced {
    bool hit = false;
    RTCRayHit rh{};
    SurfaceHit s;
};

Traced traceOne(const EmbreeScene& accel, const Vec3& o, const Vec3& d) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    Traced r;
    RTCRay& ray = r.rh.ray;
    ray.org_x = o.x;
    ray.org_y = o.y;
    ray.org_z = o.z;
    ray.dir_x = d.x;
    ray.dir_y = d.y;
    ray.dir_z = d.z;
    ray.tnear = 0.0f;
    ray.tfar = kInfinity;
    ray.time = 0.0f;
    ray.mask = 0xffffffffu;
    ray.id = 0;
    ray.flags = 0;
    r.rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    r.rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(accel.root(), &ctx, &r.rh);
    r.hit = r.rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    if (r.hit) {
        r.s = accel.surface(r.rh.hit.instID[0], r.rh.hit.geomID, r.rh.hit.primID, r.rh.hit.u,
                            r.rh.hit.v, o, d, ray.tfar);
    }
    return r;
}

void checkVec(const Vec3& a, const Vec3& b, double margin) {
    CHECK(a.x == Approx(b.x).margin(margin));
    CHECK(a.y == Approx(b.y).margin(margin));
    CHECK(a.z == Approx(b.z).margin(margin));
}

Vec3 randomUnit(std::mt19937& rng) {
    std::normal_distribution<float> n;
    for (;;) {
        Vec3 v(n(rng), n(rng), n(rng));
        if (lengthSquared(v) > 1e-6f) return normalize(v);
    }
}

Vec3 randomInBall(std::mt19937& rng, float radius) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (;;) {
        Vec3 v(u(rng), u(rng), u(rng));
        if (lengthSquared(v) <= 1.0f) return v * radius;
    }
}

int materialIndex(const Scene& scene, const std::string& name) {
    int i = scene.findMaterial(name);
    REQUIRE(i >= 0);
    return i;
}

const char* kMaterials = R"("materials": {
    "red":   {"type": "diffuse", "color": [0.8, 0.1, 0.1]},
    "blue":  {"type": "diffuse", "color": [0.1, 0.1, 0.8]},
    "green": {"type": "mirror", "color": [0.1, 0.8, 0.1]}
  })";

std::string sceneWith(const std::string& rest) {
    return std::string("{") + kMaterials + ", " + rest + "}";
}

} // namespace

TEST_CASE("Sphere hits match the closed form from outside and inside", "[accel]") {
    const Vec3 c(1.0f, 2.0f, 3.0f);
    const float r = 0.5f;
    auto scene = sceneFromJson(sceneWith(
        R"("nodes": [{"type": "sphere", "material": "blue", "center": [1, 2, 3],
                      "radius": 0.5}])"));
    EmbreeScene accel(*scene);
    const int blue = materialIndex(*scene, "blue");
    std::mt19937 rng(7);

    SECTION("from outside, aimed at the centre: t = |c - o| - r, outward normal") {
        for (int k = 0; k < 200; ++k) {
            Vec3 o = c + randomUnit(rng) * (1.0f + 9.0f * float(k) / 200.0f);
            Vec3 d = normalize(c - o);
            Traced t = traceOne(accel, o, d);
            INFO("ray " << k);
            REQUIRE(t.hit);
            CHECK(t.rh.hit.instID[0] == RTC_INVALID_GEOMETRY_ID);
            CHECK(t.rh.ray.tfar == Approx(length(c - o) - r).epsilon(1e-5));
            CHECK(t.s.shape->type == ShapeType::Sphere);
            CHECK(t.s.material == blue);
            CHECK(t.s.instance == -1);
            Vec3 expectedN = normalize(o - c); // the hit faces the origin
            checkVec(t.s.ng, expectedN, 1e-4);
            checkVec(t.s.p, c + expectedN * r, 1e-5);
            CHECK(length(t.s.p - c) == Approx(r).epsilon(1e-6));
            CHECK(dot(t.s.ng, d) < 0);
        }
    }
    SECTION("from outside, off-centre: the near root of the quadratic") {
        for (int k = 0; k < 200; ++k) {
            Vec3 o = c + randomUnit(rng) * 4.0f;
            Vec3 target = c + randomInBall(rng, 0.45f);
            Vec3 d = normalize(target - o);
            double b = dot(o - c, d), cc = lengthSquared(o - c) - r * r;
            double tExpected = -b - std::sqrt(b * b - cc);
            Traced t = traceOne(accel, o, d);
            INFO("ray " << k);
            REQUIRE(t.hit);
            CHECK(t.rh.ray.tfar == Approx(tExpected).epsilon(1e-4));
            Vec3 p = o + d * float(tExpected);
            checkVec(t.s.p, p, 1e-4);
            checkVec(t.s.ng, normalize(p - c), 1e-3);
        }
    }
    SECTION("from inside: the far side, normal still outward") {
        for (int k = 0; k < 200; ++k) {
            Vec3 o = c + randomInBall(rng, 0.3f);
            Vec3 d = randomUnit(rng);
            double b = dot(o - c, d), cc = lengthSquared(o - c) - r * r;
            double tExpected = -b + std::sqrt(b * b - cc);
            Traced t = traceOne(accel, o, d);
            INFO("ray " << k);
            REQUIRE(t.hit);
            CHECK(t.rh.ray.tfar == Approx(tExpected).epsilon(1e-4));
            Vec3 p = o + d * float(tExpected);
            checkVec(t.s.p, p, 1e-4);
            checkVec(t.s.ng, normalize(p - c), 1e-3);
            CHECK(dot(t.s.ng, d) > 0);
        }
    }
    SECTION("rays passing by miss") {
        Vec3 o = c + Vec3(0.0f, 0.0f, -5.0f);
        CHECK_FALSE(traceOne(accel, o + Vec3(0.51f, 0.0f, 0.0f), Vec3(0, 0, 1)).hit);
        CHECK(traceOne(accel, o + Vec3(0.49f, 0.0f, 0.0f), Vec3(0, 0, 1)).hit);
        CHECK_FALSE(traceOne(accel, o, Vec3(0, 0, -1)).hit); // pointing away
    }
}

TEST_CASE("Disk hits: in the plane, within the radius, normal as given", "[accel]") {
    // Disk centred at (0, 1, 0), facing +z, radius 2.
    auto scene = sceneFromJson(sceneWith(R"("nodes": [{"type": "disk", "material": "red",
        "center": [0, 1, 0], "normal": [0, 0, 1], "radius": 2}])"));
    EmbreeScene accel(*scene);
    const Vec3 c(0, 1, 0), n(0, 0, 1);

    Traced front = traceOne(accel, {0.5f, 1.5f, 5.0f}, {0, 0, -1});
    REQUIRE(front.hit);
    CHECK(front.rh.ray.tfar == Approx(5.0f).epsilon(1e-6));
    CHECK(front.s.shape->type == ShapeType::Disk);
    CHECK(front.s.material == materialIndex(*scene, "red"));
    checkVec(front.s.p, {0.5f, 1.5f, 0.0f}, 1e-5);
    checkVec(front.s.ng, n, 1e-6);

    // From behind: still hit, and the normal is the disk's front side, not flipped.
    Traced back = traceOne(accel, {-0.5f, 0.5f, -3.0f}, {0, 0, 1});
    REQUIRE(back.hit);
    CHECK(back.rh.ray.tfar == Approx(3.0f).epsilon(1e-6));
    checkVec(back.s.ng, n, 1e-6);

    // The rim.
    CHECK(traceOne(accel, c + Vec3(1.95f, 0.0f, 1.0f), {0, 0, -1}).hit);
    CHECK(traceOne(accel, c + Vec3(0.0f, -1.95f, 1.0f), {0, 0, -1}).hit);
    CHECK_FALSE(traceOne(accel, c + Vec3(2.05f, 0.0f, 1.0f), {0, 0, -1}).hit);
    CHECK_FALSE(traceOne(accel, c + Vec3(1.45f, 1.45f, 1.0f), {0, 0, -1}).hit);

    // Oblique rays towards random points of the disk.
    std::mt19937 rng(3);
    for (int k = 0; k < 100; ++k) {
        Vec3 q = randomInBall(rng, 1.9f);
        q.z = 0;
        q = q + c;
        Vec3 o = q + Vec3(0.0f, 0.0f, 0.5f) + randomUnit(rng) * 0.2f + Vec3(0, 0, 2.0f);
        Vec3 d = normalize(q - o);
        Traced t = traceOne(accel, o, d);
        INFO("ray " << k);
        REQUIRE(t.hit);
        CHECK(t.rh.ray.tfar == Approx(length(q - o)).epsilon(1e-5));
        checkVec(t.s.p, q, 1e-4);
        CHECK(std::abs(t.s.p.z) < 1e-6f); // projected onto the plane
    }
}

TEST_CASE("A non-uniformly scaled sphere is an ellipsoid with the analytic normal", "[accel]") {
    // Unit sphere scaled by (a, b, c) = (2, 0.5, 1.5), moved to T.
    const double a = 2.0, b = 0.5, cz = 1.5;
    const Vec3 T(1.0f, -2.0f, 3.0f);
    auto scene = sceneFromJson(sceneWith(R"("nodes": [{"type": "sphere", "material": "green",
        "radius": 1, "transform": {"translate": [1, -2, 3], "scale": [2, 0.5, 1.5]}}])"));
    EmbreeScene accel(*scene);
    REQUIRE(accel.stats().instances == 1);
    std::mt19937 rng(11);
    for (int k = 0; k < 300; ++k) {
        Vec3 o = T + randomUnit(rng) * 6.0f;
        Vec3 inside = randomInBall(rng, 0.9f);
        Vec3 target = T + Vec3(float(a) * inside.x, float(b) * inside.y, float(cz) * inside.z);
        Vec3 d = normalize(target - o);
        // In the sphere's space the ray is o' + t d' with the same t.
        double ox = (o.x - T.x) / a, oy = (o.y - T.y) / b, oz = (o.z - T.z) / cz;
        double dx = d.x / a, dy = d.y / b, dz = d.z / cz;
        double A = dx * dx + dy * dy + dz * dz, B = 2 * (ox * dx + oy * dy + oz * dz),
               C = ox * ox + oy * oy + oz * oz - 1;
        double tExpected = (-B - std::sqrt(B * B - 4 * A * C)) / (2 * A);
        Vec3 p = o + d * float(tExpected);
        Vec3 rel = p - T;
        Vec3 nExpected = normalize(
            Vec3(float(rel.x / (a * a)), float(rel.y / (b * b)), float(rel.z / (cz * cz))));

        Traced t = traceOne(accel, o, d);
        INFO("ray " << k);
        REQUIRE(t.hit);
        CHECK(t.rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID);
        CHECK(t.rh.ray.tfar == Approx(tExpected).epsilon(1e-4));
        CHECK(t.s.shape->type == ShapeType::Sphere);
        CHECK(t.s.material == materialIndex(*scene, "green"));
        CHECK(t.s.instance == 0);
        checkVec(t.s.p, p, 2e-4);
        checkVec(t.s.ng, nExpected, 2e-3);
        CHECK(dot(t.s.ng, d) < 0);
        // The hit lies on the ellipsoid.
        double e = std::pow(t.s.p.x - T.x, 2) / (a * a) + std::pow(t.s.p.y - T.y, 2) / (b * b) +
                   std::pow(t.s.p.z - T.z, 2) / (cz * cz);
        CHECK(e == Approx(1.0).epsilon(1e-4));
    }
}

TEST_CASE("Nested instances resolve to the right shape, material and composed transform",
          "[accel]") {
    // "outer" holds a sphere of its own and an instance of "inner" (a sphere and a triangle);
    // the root places "outer" twice.
    auto scene = sceneFromJson(sceneWith(R"(
      "prototypes": {
        "inner": {"children": [
          {"type": "sphere", "material": "red", "center": [0, 0, 0], "radius": 1},
          {"type": "mesh", "material": "blue",
           "positions": [[-1, -1, -3], [1, -1, -3], [0, 1, -3]], "indices": [[0, 1, 2]]}
        ]},
        "outer": {"children": [
          {"type": "sphere", "material": "green", "center": [0, 0, 0], "radius": 0.25},
          {"type": "instance", "prototype": "inner",
           "transform": {"translate": [0, 2, 0], "scale": 0.5}}
        ]}
      },
      "nodes": [
        {"type": "instance", "prototype": "outer",
         "transform": {"translate": [5, 0, 0], "rotate": {"angle": 90, "axis": [0, 1, 0]}}},
        {"type": "instance", "prototype": "outer", "transform": {"translate": [-5, 0, 0]}},
        {"type": "sphere", "material": "blue", "center": [0, -10, 0], "radius": 1}
      ])"));
    EmbreeScene accel(*scene);
    const int red = materialIndex(*scene, "red"), blue = materialIndex(*scene, "blue"),
              green = materialIndex(*scene, "green");

    Affine t1 = Affine::translate({5, 0, 0}) * Affine::rotate(90, {0, 1, 0});
    Affine t1b = Affine::translate({-5, 0, 0});
    Affine t2 = Affine::translate({0, 2, 0}) * Affine::scale(Vec3(0.5f));
    auto checkTransform = [&](int instance, const Affine& expected) {
        REQUIRE(instance >= 0);
        REQUIRE(std::size_t(instance) < accel.instances().size());
        const Affine& got = accel.instances()[std::size_t(instance)].toWorld;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 4; ++j) CHECK(got.m[i][j] == Approx(expected.m[i][j]).margin(1e-6));
    };

    // Two prototypes (outer, inner), each committed once; four placements.
    CHECK(accel.stats().prototypes == 2);
    CHECK(accel.stats().instances == 4);

    SECTION("inner sphere through both levels") {
        // First outer: centre T1 * T2 * 0 = (5, 2, 0), radius 0.5.
        Traced a = traceOne(accel, {5, 2, 10}, {0, 0, -1});
        REQUIRE(a.hit);
        CHECK(a.rh.ray.tfar == Approx(9.5).epsilon(1e-5));
        CHECK(a.s.shape->type == ShapeType::Sphere);
        CHECK(a.s.material == red);
        checkVec(a.s.p, {5, 2, 0.5f}, 1e-4);
        checkVec(a.s.ng, {0, 0, 1}, 1e-4);
        checkTransform(a.s.instance, t1 * t2);
        // Second outer: centre (-5, 2, 0).
        Traced b = traceOne(accel, {-5, 2, 10}, {0, 0, -1});
        REQUIRE(b.hit);
        CHECK(b.rh.ray.tfar == Approx(9.5).epsilon(1e-5));
        CHECK(b.s.material == red);
        checkTransform(b.s.instance, t1b * t2);
        CHECK(a.s.instance != b.s.instance);
        CHECK(a.rh.hit.instID[0] != b.rh.hit.instID[0]);
    }
    SECTION("inner triangle through both levels") {
        // Second outer: the triangle at inner z = -3 lies at world z = -1.5.
        Traced t = traceOne(accel, {-5, 1.8f, -10}, {0, 0, 1});
        REQUIRE(t.hit);
        CHECK(t.rh.ray.tfar == Approx(8.5).epsilon(1e-5));
        CHECK(t.s.shape->type == ShapeType::Mesh);
        CHECK(t.s.material == blue);
        CHECK(t.rh.hit.primID == 0);
        checkVec(t.s.p, {-5, 1.8f, -1.5f}, 1e-4);
        checkVec(t.s.ng, {0, 0, 1}, 1e-5); // the winding's front, kept by the transform
        checkTransform(t.s.instance, t1b * t2);
        // First outer: rotated 90 degrees about y (z -> x), inner z = -3 lands at world
        // x = 5 - 1.5 and its front (+z) turns to +x; this ray sees its back.
        Traced r = traceOne(accel, {0, 1.8f, 0}, {1, 0, 0});
        REQUIRE(r.hit);
        CHECK(r.s.material == blue);
        CHECK(r.rh.ray.tfar == Approx(3.5).epsilon(1e-5));
        checkVec(r.s.p, {3.5f, 1.8f, 0}, 1e-4);
        checkVec(r.s.ng, {1, 0, 0}, 1e-5);
        checkTransform(r.s.instance, t1 * t2);
    }
    SECTION("outer's own leaf carries the outer transform only") {
        Traced t = traceOne(accel, {5, 0, 10}, {0, 0, -1});
        REQUIRE(t.hit);
        CHECK(t.rh.ray.tfar == Approx(9.75).epsilon(1e-5));
        CHECK(t.s.material == green);
        checkTransform(t.s.instance, t1);
    }
    SECTION("root leaves have no instance") {
        Traced t = traceOne(accel, {0, -5, 0}, {0, -1, 0});
        REQUIRE(t.hit);
        CHECK(t.rh.hit.instID[0] == RTC_INVALID_GEOMETRY_ID);
        CHECK(t.s.instance == -1);
        CHECK(t.s.material == blue);
        CHECK(t.rh.ray.tfar == Approx(4.0).epsilon(1e-5));
    }
}

TEST_CASE("AccelStats count placed and unique geometry of an instanced scene", "[accel]") {
    // "thing" (a quad and a sphere) placed 5 times directly and twice through "pair"; a 2x3
    // grid (12 triangles) at the root.
    auto scene = sceneFromJson(sceneWith(R"(
      "prototypes": {
        "thing": {"children": [
          {"type": "quad", "material": "red",
           "corners": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]},
          {"type": "sphere", "material": "blue", "center": [0.5, 2, 0], "radius": 0.5}
        ]},
        "pair": {"children": [
          {"type": "instance", "prototype": "thing", "transform": {"translate": [0, 0, 10]}},
          {"type": "instance", "prototype": "thing", "transform": {"translate": [0, 0, 20]}}
        ]}
      },
      "nodes": [
        {"type": "grid", "material": "green", "size": [4, 4], "segments": [2, 3]},
        {"type": "instance", "prototype": "thing", "transform": {"translate": [3, 0, 0]}},
        {"type": "instance", "prototype": "thing", "transform": {"translate": [6, 0, 0]}},
        {"type": "instance", "prototype": "thing", "transform": {"translate": [9, 0, 0]}},
        {"type": "instance", "prototype": "thing", "transform": {"translate": [12, 0, 0]}},
        {"type": "instance", "prototype": "thing",
         "transform": {"translate": [15, 0, 0], "scale": 2}},
        {"type": "instance", "prototype": "pair", "transform": {"translate": [0, 5, 0]}}
      ])"));
    EmbreeScene accel(*scene);
    const AccelStats& s = accel.stats();
    CHECK(s.prototypes == 1); // "pair" has no leaves of its own
    CHECK(s.instances == 7);
    CHECK(s.placedTriangles == 7 * 2 + 12);
    CHECK(s.uniqueTriangles == 2 + 12);
    CHECK(s.spheres == 7);
    CHECK(s.disks == 0);
    CHECK(s.leaves == 7 * 2 + 1);
    CHECK(accel.instances().size() == 7);
    CHECK(accel.emitters().empty());
}

namespace {

// Where rayproc puts pbrt-v4 world points (the importer may mirror the world for its camera):
// a marker mesh through them, loaded under the same header.
std::vector<Vec3> placedPoints(const std::vector<Vec3>& pbrtWorld) {
    std::string p;
    for (const Vec3& q : pbrtWorld)
        p += std::to_string(q.x) + " " + std::to_string(q.y) + " " + std::to_string(q.z) + " ";
    auto r = loadWorld("Shape \"trianglemesh\" \"point3 P\" [" + p + "] \"integer indices\" [" +
                       std::string(pbrtWorld.size() == 3 ? "0 1 2" : "0 1 2 0 2 3") + "]\n");
    return rootShapes(*r.scene)[0].shape->mesh->positions;
}

} // namespace

TEST_CASE("Spheres and disks have pbrt-v4's (u, v) in their own space", "[accel][pbrt]") {
    // A sphere of radius 2, translated by (1, 2, 3) and rotated 90 degrees about x: object
    // (x, y, z) is pbrt world (1 + x, 2 - z, 3 + y). u = phi / 2 pi, v = 1 - theta / pi.
    auto sphere = loadWorld("AttributeBegin\nTranslate 1 2 3\nRotate 90 1 0 0\n"
                            "Shape \"sphere\" \"float radius\" 2\nAttributeEnd\n");
    EmbreeScene accel(*sphere.scene);
    const Vec3 c = placedPoints({{1, 2, 3}, {2, 2, 3}, {1, 3, 3}})[0];
    const float r2 = std::sqrt(2.0f);
    // Object points (0, 2, 0), (-2, 0, 0), (sqrt 2, 0, -sqrt 2), (0, 2 sin 60, 2 cos 60).
    const std::vector<Vec3> at = placedPoints({{1, 2, 5}, {-1, 2, 3}, {1 + r2, 2 + r2, 3},
                                               {1, 1, 3 + 2 * std::sin(kPi / 3)}});
    const Vec2 expected[] = {{0.25f, 0.5f}, {0.5f, 0.5f}, {0.0f, 0.25f}, {0.25f, 2.0f / 3}};
    for (std::size_t k = 0; k < at.size(); ++k) {
        INFO("point " << k);
        const Vec3 o = at[k] + (at[k] - c); // outside, along the normal
        Traced t = traceOne(accel, o, normalize(c - o));
        REQUIRE(t.hit);
        // u wraps at phi = 0: 0 and 1 are the same meridian.
        CHECK(std::min(std::abs(t.s.uv.x - expected[k].x),
                       std::abs(std::abs(t.s.uv.x - expected[k].x) - 1.0f)) < 1e-4f);
        CHECK(t.s.uv.y == Approx(expected[k].y).margin(1e-4));
    }
    // A disk of radius 2 at z = 1, rotated 90 degrees about z: object (0, 1) is pbrt world
    // (-1, 0, 1): phi 90 degrees, r = 1: (0.25, 0.5).
    auto disk = loadWorld("AttributeBegin\nTranslate 0 0 1\nRotate 90 0 0 1\n"
                          "Shape \"disk\" \"float radius\" 2\nAttributeEnd\n");
    EmbreeScene diskAccel(*disk.scene);
    const std::vector<Vec3> d = placedPoints({{-1, 0, 1}, {-1, 0, 2}, {0, 0, 2}});
    Traced t = traceOne(diskAccel, d[1], normalize(d[0] - d[1]));
    REQUIRE(t.hit);
    CHECK(t.s.uv.x == Approx(0.25f).margin(1e-4));
    CHECK(t.s.uv.y == Approx(0.5f).margin(1e-4));
}

TEST_CASE("Bump mapping on a sphere steps (u, v) with its dp/du: d = a v tilts the equator's "
          "normal by atan(a / pi r)",
          "[accel][pbrt][bump]") {
    // v = 1 - theta / pi rises towards the +z pole; at the equator |dp/dv| = pi r, so the
    // displaced surface's normal leans towards -z by atan(a / (pi r)).
    const float a = 0.5f;
    auto r = loadWorld("Texture \"d\" \"float\" \"bilerp\" \"float v00\" 0 \"float v10\" 0 "
                       "\"float v01\" 0.5 \"float v11\" 0.5\n"
                       "Material \"diffuse\" \"texture displacement\" \"d\"\n"
                       "Shape \"sphere\" \"float radius\" 1\n");
    REQUIRE(r.warnings.empty());
    EmbreeScene accel(*r.scene);
    const std::vector<Vec3> p = placedPoints({{0, 0, 0}, {1, 0, 0}, {0, 0, 1}});
    const Vec3 pole = normalize(p[2] - p[0]);
    const Vec3 o = p[1] * 3.0f - p[0] * 2.0f; // two radii out from the equator point (1, 0, 0)
    Traced t = traceOne(accel, o, normalize(p[1] - o));
    REQUIRE(t.hit);
    SurfaceHit h = t.s;
    resolveShading(*r.scene, h, normalize(o - p[1]));
    CHECK(dot(h.ns, pole) == Approx(-std::sin(std::atan(a / kPi))).margin(2e-3));
}

TEST_CASE("Bump mapping on a disk steps (u, v) with pbrt-v4's dp/du and dp/dv", "[accel][pbrt][bump]") {
    // A disk of radius 2 at z = 1, rotated 90 degrees about z, hit at object (0, 1): pbrt world
    // (-1, 0, 1). There dp/dv = -(radius / r) (x, y) points inwards with length 2, and dp/du =
    // 2 pi (-y, x) has length 2 pi: d = a v leans the normal outwards by atan(a / 2), and
    // d = a u against dp/du (towards pbrt world +y) by atan(a / 2 pi).
    const float a = 0.5f;
    const std::vector<Vec3> p = placedPoints({{-1, 0, 1}, {-1, 0, 2}, {-2, 0, 1}, {-1, 1, 1}});
    const Vec3 outwards = normalize(p[2] - p[0]), along = normalize(p[3] - p[0]);
    struct Case {
        const char* corners; // bilerp's v10 and v01
        Vec3 towards;
        float tilt;
    };
    const Case cases[] = {{"\"float v10\" 0 \"float v01\" 0.5 \"float v11\" 0.5", outwards,
                           std::atan(a / 2)},
                          {"\"float v10\" 0.5 \"float v01\" 0 \"float v11\" 0.5", along,
                           std::atan(a / (2 * kPi))}};
    for (const Case& c : cases) {
        INFO(c.corners);
        std::string world = "Texture \"d\" \"float\" \"bilerp\" \"float v00\" 0 ";
        world += c.corners;
        world += "\nMaterial \"diffuse\" \"texture displacement\" \"d\"\n"
                 "AttributeBegin\nTranslate 0 0 1\nRotate 90 0 0 1\n"
                 "Shape \"disk\" \"float radius\" 2\nAttributeEnd\n";
        auto r = loadWorld(world);
        REQUIRE(r.warnings.empty());
        EmbreeScene accel(*r.scene);
        Traced t = traceOne(accel, p[1], normalize(p[0] - p[1]));
        REQUIRE(t.hit);
        SurfaceHit h = t.s;
        resolveShading(*r.scene, h, normalize(p[1] - p[0]));
        CHECK(dot(h.ns, c.towards) == Approx(std::sin(c.tilt)).margin(2e-3));
        CHECK(dot(h.ns, h.ng) == Approx(std::cos(c.tilt)).margin(2e-3));
    }
}

TEST_CASE("Bump mapping on a rotated sphere steps u about the sphere's own pole",
          "[accel][pbrt][bump]") {
    // Rotate 90 about x: object (1, 0, 0) stays at pbrt world (1, 0, 0), and dp/du there (phi
    // about the object's z) points along object +y, pbrt world +z, with length 2 pi r. So
    // d = a u leans the normal towards pbrt world -z by atan(a / 2 pi r).
    const float a = 0.5f;
    auto r = loadWorld("Texture \"d\" \"float\" \"bilerp\" \"float v00\" 0 \"float v10\" 0.5 "
                       "\"float v01\" 0 \"float v11\" 0.5\n"
                       "Material \"diffuse\" \"texture displacement\" \"d\"\n"
                       "AttributeBegin\nRotate 90 1 0 0\nShape \"sphere\" \"float radius\" 1\n"
                       "AttributeEnd\n");
    REQUIRE(r.warnings.empty());
    EmbreeScene accel(*r.scene);
    const std::vector<Vec3> p = placedPoints({{0, 0, 0}, {1, 0, 0}, {0, 0, -1}});
    const Vec3 down = normalize(p[2] - p[0]);
    const Vec3 o = p[1] * 3.0f - p[0] * 2.0f;
    Traced t = traceOne(accel, o, normalize(p[1] - o));
    REQUIRE(t.hit);
    SurfaceHit h = t.s;
    resolveShading(*r.scene, h, normalize(o - p[1]));
    CHECK(dot(h.ns, down) == Approx(std::sin(std::atan(a / (2 * kPi)))).margin(2e-3));
}
