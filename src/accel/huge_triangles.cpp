#include "accel/huge_triangles.h"

#include "kernels/ray_offset.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>

namespace rayproc {

namespace {

// The float test's error, in units of the triangle's extent or reach: gamma_(4 + 8), the
// margin the offsets take for Embree's triangle test (kernels::trianglePoint).
constexpr double kFloatTestError = kernels::errorGamma(4 + kernels::kEmbreeTestOps);
// What that error may be, relative to the smallest shape and to the camera's distance.
constexpr double kTolerance = 1e-3;

struct DVec {
    double x, y, z;
};

DVec toWorld(const Affine& a, const Vec3& p) {
    auto row = [&](int r) {
        return double(a.m[r][0]) * p.x + double(a.m[r][1]) * p.y + double(a.m[r][2]) * p.z +
               double(a.m[r][3]);
    };
    return {row(0), row(1), row(2)};
}

struct DBox {
    DVec lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
    static constexpr double kInf = std::numeric_limits<double>::infinity();
    void extend(const DVec& p) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    double extent() const { return std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}); }
    // Euclidean distance from c (0 inside).
    double distance(const DVec& c) const {
        double dx = std::max({lo.x - c.x, 0.0, c.x - hi.x});
        double dy = std::max({lo.y - c.y, 0.0, c.y - hi.y});
        double dz = std::max({lo.z - c.z, 0.0, c.z - hi.z});
        return std::sqrt(dx * dx + dy * dy + dz * dz);
    }
    // Largest coordinate of a point of the box relative to c.
    double reach(const DVec& c) const {
        return std::max({std::abs(lo.x - c.x), std::abs(hi.x - c.x), std::abs(lo.y - c.y),
                         std::abs(hi.y - c.y), std::abs(lo.z - c.z), std::abs(hi.z - c.z)});
    }
};

// The scale a placement gives lengths: the cube root of its determinant (exact for
// similarities, the geometric mean of the axis scales otherwise).
double lengthScale(const Affine& a) {
    double det = std::abs(double(a.determinant()));
    return std::cbrt(det);
}

double triangleExtent(const TriangleMesh& m, std::size_t t) {
    const Vec3 &a = m.positions[m.indices[3 * t]], &b = m.positions[m.indices[3 * t + 1]],
               &c = m.positions[m.indices[3 * t + 2]];
    Vec3 lo = vmin(a, vmin(b, c)), hi = vmax(a, vmax(b, c));
    return double(maxComponent(hi - lo));
}

// A mesh's typical size: the median of its triangles' extents (those with an extent: a
// degenerate triangle says nothing about the scene's scale).
double medianExtent(const TriangleMesh& m) {
    std::vector<double> e;
    e.reserve(m.triangleCount());
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        double x = triangleExtent(m, t);
        if (x > 0 && std::isfinite(x)) e.push_back(x);
    }
    if (e.empty()) return std::numeric_limits<double>::infinity();
    std::nth_element(e.begin(), e.begin() + e.size() / 2, e.end());
    return e[e.size() / 2];
}

// Every leaf with the transform that places it in the world, as EmbreeScene::place walks the
// tree: transformed groups and instances compose their transforms, identity groups share their
// parent's space.
void forEachPlacedLeaf(const Node& group, const Affine& toWorld,
                       const std::function<void(const Shape&, const Affine&)>& f) {
    for (const auto& c : group.children) {
        if (c->kind == Node::Kind::Shape)
            f(c->shape, toWorld);
        else if (c->kind == Node::Kind::Group)
            forEachPlacedLeaf(*c, c->transform.isIdentity() ? toWorld : toWorld * c->transform, f);
        else if (c->kind == Node::Kind::Instance)
            forEachPlacedLeaf(*c->prototype, toWorld * c->transform * c->prototype->transform, f);
    }
}

} // namespace

HugeTriangles findHugeTriangles(const Scene& scene) {
    HugeTriangles huge;
    if (!scene.root) return huge;
    const Affine& rootTransform = scene.root->transform;

    // F: the typical size of the smallest shape, in the world.
    std::unordered_map<const TriangleMesh*, double> median;
    std::unordered_map<const TriangleMesh*, Bounds3> localBounds;
    double smallest = std::numeric_limits<double>::infinity();
    forEachPlacedLeaf(*scene.root, rootTransform, [&](const Shape& s, const Affine& w) {
        double size;
        if (s.type == ShapeType::Mesh) {
            auto it = median.find(s.mesh.get());
            if (it == median.end()) it = median.emplace(s.mesh.get(), medianExtent(*s.mesh)).first;
            size = it->second;
        } else {
            size = 2.0 * std::abs(double(s.radius));
        }
        size *= lengthScale(w);
        if (size > 0 && std::isfinite(size)) smallest = std::min(smallest, size);
    });

    const DVec cam{scene.camera.position.x, scene.camera.position.y, scene.camera.position.z};
    const double lens = std::abs(double(scene.camera.apertureRadius));
    auto isHuge = [&](double extent, double reach, double distance) {
        return kFloatTestError * extent > kTolerance * smallest ||
               kFloatTestError * reach > kTolerance * std::max(0.0, distance - lens);
    };

    forEachPlacedLeaf(*scene.root, rootTransform, [&](const Shape& s, const Affine& w) {
        if (s.type != ShapeType::Mesh || s.mesh->triangleCount() == 0) return;
        const TriangleMesh& m = *s.mesh;
        auto lb = localBounds.find(&m);
        if (lb == localBounds.end()) lb = localBounds.emplace(&m, m.bounds()).first;
        DBox box;
        for (int k = 0; k < 8; ++k) {
            Vec3 corner{(k & 1) ? lb->second.hi.x : lb->second.lo.x,
                        (k & 2) ? lb->second.hi.y : lb->second.lo.y,
                        (k & 4) ? lb->second.hi.z : lb->second.lo.z};
            box.extend(toWorld(w, corner));
        }
        // No triangle is larger, reaches farther or comes closer than the mesh's bounds.
        if (!isHuge(box.extent(), box.reach(cam), box.distance(cam))) return;
        std::vector<unsigned> found;
        for (std::size_t t = 0; t < m.triangleCount(); ++t) {
            DVec p[3];
            DBox tb;
            for (int k = 0; k < 3; ++k) {
                p[k] = toWorld(w, m.positions[m.indices[3 * t + k]]);
                tb.extend(p[k]);
            }
            // The camera's distance to the triangle is at least its distance to the
            // triangle's bounding box and to its plane.
            DVec e{p[1].x - p[0].x, p[1].y - p[0].y, p[1].z - p[0].z};
            DVec f{p[2].x - p[0].x, p[2].y - p[0].y, p[2].z - p[0].z};
            DVec n{e.y * f.z - e.z * f.y, e.z * f.x - e.x * f.z, e.x * f.y - e.y * f.x};
            double nl = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
            double plane = 0;
            if (nl > 0 && std::isfinite(nl))
                plane = std::abs(n.x * (cam.x - p[0].x) + n.y * (cam.y - p[0].y) +
                                 n.z * (cam.z - p[0].z)) /
                        nl;
            double distance = std::max(tb.distance(cam), plane);
            if (isHuge(tb.extent(), tb.reach(cam), distance)) found.push_back(unsigned(t));
        }
        if (found.empty()) return;
        std::vector<unsigned>& list = huge[&s];
        std::vector<unsigned> merged;
        std::set_union(list.begin(), list.end(), found.begin(), found.end(),
                       std::back_inserter(merged));
        list = std::move(merged);
    });
    return huge;
}

} // namespace rayproc
