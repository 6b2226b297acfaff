// Huge triangles (accel/huge_triangles.h) and their double-precision user geometry
// (accel/exact_triangles.h): which triangles are chosen; hits on a tilted 1e9 plane where a
// double-precision caster puts them, the same at every packet width, for radiance and shadow
// rays, at the top level and inside an instance; a mesh split into Embree's triangles and exact
// ones keeps every triangle's identity; alpha cut-outs apply to exact triangles.
#include "engine/intersect.h"
#include "scene/pbrt/pbrt_transform.h"
#include "pbrt/pbrt_test_util.h"
#include "test_util.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

using namespace rayproc;
using namespace rayproc::test;
using rayproc::pbrt::Vec3d;

namespace {

constexpr double kPiD = 3.14159265358979323846;

// The plane's unit normal when tilted `degrees` about the x axis.
Vec3d tiltedNormal(double degrees) {
    double a = degrees * kPiD / 180;
    return {0, std::cos(a), std::sin(a)};
}

std::string num(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}

// A plane `size` wide through the origin, tilted `degrees` about the x axis, under a unit sphere
// resting on it at the origin, the camera 3 above it. Tilted either by its corners (A, B, -A, -B:
// the plane through the rounded corners contains the origin) or, `grouped`, as a flat quad in a
// rotated group (an Embree instance). `extra`: more nodes; `sky`: an environment light too.
std::unique_ptr<Scene> planeScene(double size, double degrees, bool grouped,
                                  const std::string& extra = "", bool sky = false) {
    Vec3d n = tiltedNormal(degrees);
    std::string quad;
    if (grouped) {
        std::string s = num(size), m = num(-size);
        quad =
            R"({"type": "group", "transform": {"rotate": {"angle": )" + num(degrees) +
            R"(, "axis": [1, 0, 0]}}, "children": [{"type": "quad", "material": "g", "corners": [[)" +
            m + ", 0, " + s + "], [" + s + ", 0, " + s + "], [" + s + ", 0, " + m + "], [" + m +
            ", 0, " + m + "]]}]}";
    } else {
        double y = size * std::tan(degrees * kPiD / 180);
        quad = R"({"type": "quad", "material": "g", "corners": [[)" + num(-size) + ", " + num(-y) +
               ", " + num(size) + "], [" + num(size) + ", " + num(-y) + ", " + num(size) + "], [" +
               num(size) + ", " + num(y) + ", " + num(-size) + "], [" + num(-size) + ", " + num(y) +
               ", " + num(-size) + "]]}";
    }
    return sceneFromJson(
        R"({"camera": {"position": [0, 3, 8], "look_at": [0, 0.5, 0], "resolution": [32, 24]},
            "materials": {"g": {"type": "diffuse", "color": [0.5, 0.5, 0.5]}},
            "lights": [{"type": "directional", "direction": [-0.3, -1, -0.2], "irradiance": [1, 1, 1]})" +
        std::string(sky ? R"(, {"type": "environment", "radiance": [0.2, 0.3, 0.6]})" : "") + R"(],
            "nodes": [)" +
        quad + R"(, {"type": "sphere", "material": "g", "center": [0, )" + num(n.y) + ", " +
        num(n.z) + R"(], "radius": 1})" + extra + "]}");
}

std::unique_ptr<RayBatch> batchOf(RayKind kind) {
    auto b = std::make_unique<RayBatch>();
    b->kind = kind;
    return b;
}

// The same rays as occlusion rays.
std::unique_ptr<ShadowBatch> shadowsOf(const WorkBatch& rays) {
    auto b = std::make_unique<ShadowBatch>();
    b->kind = RayKind::Shadow;
    for (int i = 0; i < rays.count; ++i)
        b->push(rays.ox[i], rays.oy[i], rays.oz[i], rays.dx[i], rays.dy[i], rays.dz[i],
                rays.tnear[i], rays.tfar[i]);
    return b;
}

bool sameBits(float a, float b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

} // namespace

TEST_CASE("Huge triangles are those whose float test errs by more than 1e-3 of the smallest "
          "shape or of the camera's distance",
          "[accel]") {
    // The 1e9 plane's two triangles, tilted or not, placed directly or by a rotated group; a
    // 1e3 plane under the same unit sphere (float error 1.4e-3 against 2e-3) keeps Embree's.
    for (double degrees : {0.0, 10.0}) {
        EmbreeScene huge(*planeScene(1e9, degrees, false));
        CHECK(huge.stats().exactTriangles == 2);
        EmbreeScene grouped(*planeScene(1e9, degrees, true));
        CHECK(grouped.stats().exactTriangles == 2);
        EmbreeScene small(*planeScene(1e3, degrees, false));
        CHECK(small.stats().exactTriangles == 0);
    }
    // Only the camera's distance: a 1e9 plane alone, 3 units below the camera.
    auto alone = sceneFromJson(R"({"camera": {"position": [0, 3, 8], "look_at": [0, 0, 0]},
        "materials": {"g": {"type": "diffuse", "color": [0.5, 0.5, 0.5]}},
        "nodes": [{"type": "quad", "material": "g", "corners": [[-1e9, 0, 1e9], [1e9, 0, 1e9], [1e9, 0, -1e9], [-1e9, 0, -1e9]]}]})");
    CHECK(EmbreeScene(*alone).stats().exactTriangles == 2);
    // The Cornell box, at every scale and far from the origin: none (tests/stress also checks).
    for (const char* name : {"cornell-box", "cornell-spheres", "instances", "materials"}) {
        INFO(name);
        auto scene = loadScene(scenePath(name));
        CHECK(EmbreeScene(*scene).stats().exactTriangles == 0);
    }
}

TEST_CASE("Rays meet a tilted 1e9 plane where a double-precision caster does, at every packet "
          "width, at the top level and instanced",
          "[accel]") {
    for (bool grouped : {false, true}) {
        for (double degrees : {-10.0, -5.0, 5.0, 10.0}) {
            INFO((grouped ? "in a rotated group" : "tilted corners")
                 << ", " << degrees << " degrees");
            auto scene = planeScene(1e9, degrees, grouped);
            EmbreeScene accel(*scene);
            REQUIRE(accel.stats().exactTriangles == 2);
            const Vec3d n = tiltedNormal(degrees), o = {0, 3, 8}, centre = n;

            // Camera rays towards a grid of points of the plane around the sphere.
            auto rays = batchOf(RayKind::Camera);
            const Vec3d u = {1, 0, 0}, w = {0, -n.z, n.y}; // in the plane
            for (int i = 0; i < 11; ++i)
                for (int j = 0; j < 9; ++j) {
                    Vec3d q = u * (-5 + i) + w * (-6 + 1.5 * j);
                    Vec3d d = q - o;
                    double l = std::sqrt(dot(d, d));
                    Vec3 df = (d * (1 / l)).toFloat();
                    rays->push(float(o.x), float(o.y), float(o.z), df.x, df.y, df.z, 0.0f,
                               kInfinity);
                }
            ThreadStats stats;
            auto first = std::make_unique<RayBatch>(*rays);
            Intersector(accel.root(), 1).trace(*first, stats);
            std::size_t planeHits = 0;
            for (int k = 0; k < first->count; ++k) {
                Vec3 of{first->ox[k], first->oy[k], first->oz[k]};
                Vec3 df{first->dx[k], first->dy[k], first->dz[k]};
                Vec3d od = Vec3d(of), dd = Vec3d(df);
                // The analytic answer: the nearer of the plane (through the origin) and the sphere.
                double tp = -dot(n, od) / dot(n, dd);
                Vec3d oc = od - centre;
                double b = dot(oc, dd), c = dot(oc, oc) - 1, disc = b * b - dot(dd, dd) * c;
                double ts = disc >= 0 ? (-b - std::sqrt(disc)) / dot(dd, dd) : kInfinity;
                REQUIRE(first->hit(k));
                SurfaceHit h = accel.surface(first->instId[k], first->geomId[k], first->primId[k],
                                             first->u[k], first->v[k], of, df, first->t[k]);
                if (ts < tp) {
                    CHECK(h.shape->type == ShapeType::Sphere);
                    continue;
                }
                ++planeHits;
                REQUIRE(h.shape->type == ShapeType::Mesh);
                Vec3d expected = od + dd * tp, p = Vec3d(h.p);
                Vec3d diff = p - expected;
                INFO("ray " << k << ": hit " << p.x << " " << p.y << " " << p.z << ", expected "
                            << expected.x << " " << expected.y << " " << expected.z);
                CHECK(std::sqrt(dot(diff, diff)) < 1e-5 * (1 + std::sqrt(dot(expected, expected))));
                CHECK(dot(Vec3d(h.ng), n) == Approx(1).margin(1e-6));
                // The offset that spawned rays take is tiny, not Embree's hundreds of units.
                CHECK(maxComponent(h.pError) < 1e-4f);
            }
            CHECK(planeHits > 60);
            for (int width : {4, 8, 16}) {
                INFO("packet width " << width);
                auto packet = std::make_unique<RayBatch>(*rays);
                Intersector(accel.root(), width).trace(*packet, stats);
                for (int k = 0; k < packet->count; ++k) {
                    CHECK(packet->geomId[k] == first->geomId[k]);
                    CHECK(packet->primId[k] == first->primId[k]);
                    CHECK(packet->instId[k] == first->instId[k]);
                    // Embree's sphere kernels round t differently per width (intersect_test.cpp);
                    // the plane's hits come from one double-precision routine.
                    const Shape* shape =
                        accel
                            .surface(first->instId[k], first->geomId[k], first->primId[k], 0, 0,
                                     {first->ox[k], first->oy[k], first->oz[k]},
                                     {first->dx[k], first->dy[k], first->dz[k]}, first->t[k])
                            .shape;
                    if (shape->type == ShapeType::Sphere) continue;
                    CHECK(sameBits(packet->t[k], first->t[k]));
                    CHECK(sameBits(packet->u[k], first->u[k]));
                    CHECK(sameBits(packet->v[k], first->v[k]));
                }
            }

            // Shadow rays straight down onto the plane from 0.5 above it, away from the sphere:
            // stopped 1e-3 short they pass, 1e-3 beyond they are blocked.
            auto shadow = std::make_unique<ShadowBatch>();
            shadow->kind = RayKind::Shadow;
            int expectBlocked = 0;
            for (int i = 0; i < 8; ++i)
                for (bool beyond : {false, true}) {
                    Vec3d q = u * (3 + i) + w * (-4 + i);
                    Vec3d from = q + n * 0.5;
                    Vec3 df = (n * -1).toFloat();
                    shadow->push(float(from.x), float(from.y), float(from.z), df.x, df.y, df.z,
                                 0.0f, beyond ? 0.501f : 0.499f);
                    expectBlocked += beyond;
                }
            for (int width : {1, 4, 8, 16}) {
                INFO("shadow rays, packet width " << width);
                auto b = std::make_unique<ShadowBatch>(*shadow);
                Intersector(accel.root(), width).trace(*b, stats);
                for (int k = 0; k < b->count; ++k) CHECK(b->occluded(k) == (k % 2 == 1));
            }
            CHECK(expectBlocked == 8);
        }
    }
}

TEST_CASE("A mesh with huge and ordinary triangles keeps each triangle's identity", "[accel]") {
    // One mesh: a 1e9 floor (triangles 0 and 1) and a unit square standing on it at z = -2
    // (triangles 2 and 3), with texture coordinates; only the floor is exact.
    auto scene = sceneFromJson(R"({"camera": {"position": [0, 3, 8], "look_at": [0, 0.5, 0]},
        "materials": {"g": {"type": "diffuse", "color": [0.5, 0.5, 0.5]}},
        "nodes": [{"type": "mesh", "material": "g",
                   "positions": [[-1e9, 0, 1e9], [1e9, 0, 1e9], [1e9, 0, -1e9], [-1e9, 0, -1e9],
                                 [-1, 0, -2], [1, 0, -2], [1, 2, -2], [-1, 2, -2]],
                   "indices": [[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]],
                   "uvs": [[0, 0], [1, 0], [1, 1], [0, 1], [0, 0], [1, 0], [1, 1], [0, 1]]},
                  {"type": "sphere", "material": "g", "center": [3, 1, 0], "radius": 1}]})");
    EmbreeScene accel(*scene);
    CHECK(accel.stats().exactTriangles == 2);
    CHECK(accel.stats().uniqueTriangles == 4);
    const Vec3 o{0, 3, 8};
    auto rays = batchOf(RayKind::Camera);
    // At the square: (x, y) = (0.5, 1.5) and (-0.5, 0.5) on it, uv = ((x + 1) / 2, y / 2).
    const Vec3 targets[] = {{0.5f, 1.5f, -2}, {-0.5f, 0.5f, -2}, {0.25f, 0, 1}, {-2, 0, 3}};
    for (const Vec3& q : targets) {
        Vec3 d = normalize(q - o);
        rays->push(o.x, o.y, o.z, d.x, d.y, d.z, 0.0f, kInfinity);
    }
    ThreadStats stats;
    for (int width : {1, 16}) {
        INFO("packet width " << width);
        auto b = std::make_unique<RayBatch>(*rays);
        Intersector(accel.root(), width).trace(*b, stats);
        for (int k = 0; k < 4; ++k) {
            INFO("target " << k);
            REQUIRE(b->hit(k));
            SurfaceHit h = accel.surface(b->instId[k], b->geomId[k], b->primId[k], b->u[k], b->v[k],
                                         o, {b->dx[k], b->dy[k], b->dz[k]}, b->t[k]);
            const Vec3& q = targets[k];
            CHECK(h.p.x == Approx(q.x).margin(1e-5));
            CHECK(h.p.y == Approx(q.y).margin(1e-5));
            CHECK(h.p.z == Approx(q.z).margin(1e-5));
            if (k < 2) {
                CHECK(h.uv.x == Approx((q.x + 1) / 2).margin(1e-5));
                CHECK(h.uv.y == Approx(q.y / 2).margin(1e-5));
                CHECK(std::abs(h.ng.z) == Approx(1));
            } else {
                // On the floor, uv = ((x + 1e9), (1e9 - z)) / 2e9, computed in double: 0.5 up to
                // the point's position over 2e9.
                CHECK(h.uv.x == Approx(0.5).margin(1e-7));
                CHECK(h.uv.y == Approx(0.5).margin(1e-7));
                CHECK(h.ng.y == Approx(1));
            }
        }
    }
}

TEST_CASE("Alpha cut-outs apply to huge triangles at every packet width", "[accel][alpha]") {
    // A 1e9 plane facing the camera (pbrt's, 5 units away at the origin), tilted 10 degrees.
    auto sceneWithAlpha = [](const std::string& alpha) {
        double s = 1e9, y = s * std::cos(10 * kPiD / 180), z = s * std::sin(10 * kPiD / 180);
        std::string p = num(-s) + " " + num(-y) + " " + num(z) + " " + num(s) + " " + num(-y) +
                        " " + num(z) + " " + num(s) + " " + num(y) + " " + num(-z) + " " + num(-s) +
                        " " + num(y) + " " + num(-z);
        return loadWorld("Shape \"trianglemesh\" \"point3 P\" [" + p +
                         "] \"integer indices\" [0 1 2 0 2 3] " + alpha + "\n");
    };
    auto opaque = sceneWithAlpha(""), hidden = sceneWithAlpha("\"float alpha\" 0"),
         half = sceneWithAlpha("\"float alpha\" 0.5");
    EmbreeScene oa(*opaque.scene), ha(*hidden.scene), hf(*half.scene);
    REQUIRE(oa.stats().exactTriangles == 2);
    REQUIRE(ha.stats().exactTriangles == 2);
    const Vec3 o = opaque.scene->camera.position;
    auto rays = batchOf(RayKind::Camera);
    for (int i = 0; i < 16; ++i)
        for (int j = 0; j < 16; ++j) {
            Vec3 d = normalize(Vec3(-0.3f + 0.04f * i, -0.3f + 0.04f * j, 0) - o);
            rays->push(o.x, o.y, o.z, d.x, d.y, d.z, 0.0f, kInfinity);
        }
    ThreadStats stats;
    for (RayKind kind : {RayKind::Camera, RayKind::Shadow}) {
        std::size_t reference = 0;
        for (int width : {1, 4, 8, 16}) {
            INFO((kind == RayKind::Shadow ? "shadow rays" : "camera rays")
                 << ", packet width " << width);
            auto count = [&](const EmbreeScene& accel) {
                std::size_t n = 0;
                if (kind == RayKind::Shadow) {
                    auto b = shadowsOf(*rays);
                    Intersector(accel.root(), width).trace(*b, stats);
                    for (int k = 0; k < b->count; ++k) n += b->occluded(k);
                } else {
                    auto b = std::make_unique<RayBatch>(*rays);
                    Intersector(accel.root(), width).trace(*b, stats);
                    for (int k = 0; k < b->count; ++k) n += b->hit(k);
                }
                return n;
            };
            CHECK(count(oa) == 256);
            CHECK(count(ha) == 0);
            std::size_t n = count(hf);
            CHECK(n > 80);
            CHECK(n < 176);
            if (width == 1) reference = n;
            CHECK(n == reference); // the same rays kept at every width
        }
    }
}

TEST_CASE("Images of a tilted 1e9 plane do not depend on the thread count or the packet width",
          "[accel][modes]") {
    auto scene = planeScene(
        1e9, 10, false,
        R"(, {"type": "sphere", "material": "g", "center": [2, 0.5, 1], "radius": 0.3})", true);
    EmbreeScene accel(*scene);
    for (const std::string mode : {"raytrace", "path"}) {
        INFO("mode " << mode);
        RenderOptions o;
        o.mode = mode;
        o.spp = 4;
        o.threads = 1;
        o.packetWidth = 16;
        Image reference = render(*scene, accel, o).image;
        CHECK(meanValue(reference) > 0.05);
        for (auto [threads, width] :
             {std::pair{2, 16}, std::pair{2, 8}, std::pair{1, 4}, std::pair{2, 1}}) {
            INFO("threads " << threads << ", packet width " << width);
            o.threads = threads;
            o.packetWidth = width;
            Image img = render(*scene, accel, o).image;
            REQUIRE(img.pixels.size() == reference.pixels.size());
            CHECK(std::memcmp(img.pixels.data(), reference.pixels.data(),
                              img.pixels.size() * sizeof(float)) == 0);
        }
    }
}
