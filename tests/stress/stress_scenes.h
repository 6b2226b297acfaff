// Shared by the numerical-stability stress tests (tests/stress/, tag [stress]): scenes built in
// C++ in a unit frame and placed in the world by a similarity transform (scale, rotation,
// optional mirror, translation) computed in double precision and rounded once, so the same
// scene can be rendered at 1e-4 or 1e6 scale and 1e5 units from the origin; renders by every
// mode; and a double-precision ray caster of the unit frame for analytic expectations.
// docs/robustness.md lists the cases, their thresholds and the measured figures.
#pragma once

#include "engine/camera_emitter.h"
#include "test_util.h"

#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace rayproc::test::stress {

struct DVec {
    double x = 0, y = 0, z = 0;
};
inline DVec dvec(const Vec3& v) { return {v.x, v.y, v.z}; }
inline Vec3 fvec(const DVec& v) { return {float(v.x), float(v.y), float(v.z)}; }
inline DVec operator+(DVec a, DVec b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline DVec operator-(DVec a, DVec b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline DVec operator*(DVec a, double s) { return {a.x * s, a.y * s, a.z * s}; }
inline double ddot(DVec a, DVec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline DVec dnormalize(DVec a) { return a * (1.0 / std::sqrt(ddot(a, a))); }

// World = translation + scale * R * (mirrorY ? (x, -y, z) : p), evaluated in double.
struct Frame {
    double scale = 1;
    DVec translation;
    double r[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    bool mirrorY = false;

    // A fixed rotation about a skew axis, so that no face stays axis-aligned and every
    // coordinate carries rounding error.
    static Frame make(double scale, DVec translation, bool rotate, bool mirrorY = false) {
        Frame f;
        f.scale = scale;
        f.translation = translation;
        f.mirrorY = mirrorY;
        if (rotate) {
            DVec a = dnormalize({0.3, 0.8, 0.5});
            double ang = 0.7, c = std::cos(ang), s = std::sin(ang), t = 1 - c;
            double m[3][3] = {{t * a.x * a.x + c, t * a.x * a.y - s * a.z, t * a.x * a.z + s * a.y},
                              {t * a.x * a.y + s * a.z, t * a.y * a.y + c, t * a.y * a.z - s * a.x},
                              {t * a.x * a.z - s * a.y, t * a.y * a.z + s * a.x, t * a.z * a.z + c}};
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) f.r[i][j] = m[i][j];
        }
        return f;
    }
    DVec rotateVec(DVec p) const {
        if (mirrorY) p.y = -p.y;
        return {r[0][0] * p.x + r[0][1] * p.y + r[0][2] * p.z,
                r[1][0] * p.x + r[1][1] * p.y + r[1][2] * p.z,
                r[2][0] * p.x + r[2][1] * p.y + r[2][2] * p.z};
    }
    DVec unrotateVec(DVec p) const {
        DVec q{r[0][0] * p.x + r[1][0] * p.y + r[2][0] * p.z,
               r[0][1] * p.x + r[1][1] * p.y + r[2][1] * p.z,
               r[0][2] * p.x + r[1][2] * p.y + r[2][2] * p.z};
        if (mirrorY) q.y = -q.y;
        return q;
    }
    Vec3 point(const Vec3& p) const { return fvec(translation + rotateVec(dvec(p)) * scale); }
    Vec3 direction(const Vec3& v) const { return fvec(dnormalize(rotateVec(dvec(v)))); }
    DVec toUnit(DVec w) const { return unrotateVec(w - translation) * (1.0 / scale); }
    DVec directionToUnit(DVec v) const { return dnormalize(unrotateVec(v)); }
};

// Moves every shape, the camera and the lights of `scene` (built in the unit frame) by `f`.
inline void placeScene(Scene& scene, const Frame& f) {
    auto placeNode = [&](Node& n, auto& self) -> void {
        if (n.kind == Node::Kind::Group) {
            for (auto& c : n.children) self(*c, self);
            return;
        }
        if (n.kind != Node::Kind::Shape) return;
        Shape& s = n.shape;
        if (s.type == ShapeType::Mesh) {
            auto m = std::make_shared<TriangleMesh>(*s.mesh);
            for (Vec3& p : m->positions) p = f.point(p);
            for (Vec3& nn : m->normals) nn = f.direction(nn);
            // A mirror flips the winding; keep the front side where the unit scene had it.
            if (f.mirrorY)
                for (std::size_t t = 0; t + 2 < m->indices.size(); t += 3)
                    std::swap(m->indices[t + 1], m->indices[t + 2]);
            s.mesh = m;
        } else {
            s.center = f.point(s.center);
            s.radius = float(s.radius * f.scale);
            s.normal = f.direction(s.normal);
        }
    };
    placeNode(*scene.root, placeNode);
    Camera& c = scene.camera;
    Vec3 target = c.lookAt;
    c.position = f.point(c.position);
    c.lookAt = f.point(target);
    c.up = f.direction(c.up);
    if (c.focusDistance > 0) c.focusDistance = float(c.focusDistance * f.scale);
    for (Light& l : scene.lights) {
        l.position = f.point(l.position);
        l.direction = f.direction(l.direction);
        // Point and spot intensities fall off with distance squared: keep the irradiance.
        if (l.type == LightType::Point || l.type == LightType::Spot)
            l.intensity = l.intensity * float(f.scale * f.scale);
    }
    scene.computeBounds();
}

// Builds scenes in the unit frame.
struct SceneBuilder {
    std::unique_ptr<Scene> scene = std::make_unique<Scene>();
    SceneBuilder() {
        scene->root = std::make_unique<Node>();
        scene->root->kind = Node::Kind::Group;
        scene->path = "stress-scene";
    }
    int material(MaterialType type, Vec3 color, float ior = 1.5f, float roughness = 0.2f) {
        Material m;
        m.name = "m" + std::to_string(scene->materials.size());
        m.type = type;
        m.color = color;
        m.ior = ior;
        m.roughness = roughness;
        scene->materials.push_back(m);
        return int(scene->materials.size()) - 1;
    }
    Shape& addMesh(std::vector<Vec3> positions, std::vector<std::uint32_t> indices, int mat,
                   std::vector<Vec3> normals = {}) {
        auto m = std::make_shared<TriangleMesh>();
        m->positions = std::move(positions);
        m->indices = std::move(indices);
        m->normals = std::move(normals);
        auto n = std::make_unique<Node>();
        n->kind = Node::Kind::Shape;
        n->shape.type = ShapeType::Mesh;
        n->shape.mesh = m;
        n->shape.material = mat;
        n->shape.name = "shape" + std::to_string(scene->root->children.size());
        scene->root->children.push_back(std::move(n));
        return scene->root->children.back()->shape;
    }
    // An axis-aligned box with outward-facing triangles.
    Shape& addBox(Vec3 lo, Vec3 hi, int mat) {
        std::vector<Vec3> p;
        for (int i = 0; i < 8; ++i)
            p.push_back({i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
        std::vector<std::uint32_t> idx = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6,  // z-, z+
                                          0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3,  // y-, y+
                                          0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5}; // x-, x+
        return addMesh(p, idx, mat);
    }
    // The square [lo.x, hi.x] x [lo.z, hi.z] at height y, facing +y, in n x n quads.
    Shape& addFloor(float lo, float hi, float y, int n, int mat) {
        std::vector<Vec3> p;
        std::vector<std::uint32_t> idx;
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i)
                p.push_back({lo + (hi - lo) * float(i) / float(n), y, lo + (hi - lo) * float(j) / float(n)});
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                std::uint32_t a = std::uint32_t(j * (n + 1) + i), b = a + 1, c = a + std::uint32_t(n + 1), d = c + 1;
                idx.insert(idx.end(), {a, c, d, a, d, b});
            }
        return addMesh(p, idx, mat);
    }
    void directional(Vec3 towardsLight, Vec3 irradiance) {
        Light l;
        l.type = LightType::Directional;
        l.direction = -normalize(towardsLight);
        l.intensity = irradiance;
        scene->lights.push_back(l);
    }
    std::unique_ptr<Scene> take(const Frame& f) {
        scene->computeBounds();
        placeScene(*scene, f);
        return std::move(scene);
    }
};

// Renders `scene` in `mode` ("preview", "raytrace", "path", "gi") at a fixed seed, with few
// samples; gi uses few photons and gather rays so the stress suite stays fast.
inline RenderResult renderStress(const Scene& scene, const EmbreeScene& accel,
                                 const std::string& mode, int spp, std::uint64_t seed,
                                 int threads = 2, int packetWidth = 16) {
    if (mode == "gi") {
        EngineSettings engine;
        engine.threads = threads;
        engine.packetWidth = packetWidth;
        engine.seed = seed;
        engine.quiet = true;
        GiSettings s = giSettings(scene, ModeOverrides{spp, 0, 0});
        s.photons = 20000;
        s.causticPhotons = 0;
        s.caustics = false;
        s.gatherRays = 16;
        return renderGi(scene, accel, s, engine);
    }
    RenderOptions o;
    o.mode = mode;
    o.spp = spp;
    o.seed = seed;
    o.threads = threads;
    o.packetWidth = packetWidth;
    return render(scene, accel, o);
}

} // namespace rayproc::test::stress
