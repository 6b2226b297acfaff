#include "accel/huge_triangles.h"

#include "kernels/ray_offset.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>

#include <tbb/parallel_for.h>

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

// A leaf as placed in the world.
struct PlacedLeaf {
    const Shape* shape;
    Affine toWorld;
};

// The triangles of `m`, placed by `w`, that are huge (ascending); none when its world bounds
// `lb` pass both tests.
template <class IsHuge>
std::vector<unsigned> hugeOf(const TriangleMesh& m, const Bounds3& lb, const Affine& w,
                             const DVec& cam, const IsHuge& isHuge) {
    DBox box;
    for (int k = 0; k < 8; ++k) {
        Vec3 corner{(k & 1) ? lb.hi.x : lb.lo.x, (k & 2) ? lb.hi.y : lb.lo.y,
                    (k & 4) ? lb.hi.z : lb.lo.z};
        box.extend(toWorld(w, corner));
    }
    // No triangle is larger, reaches farther or comes closer than the mesh's bounds.
    std::vector<unsigned> found;
    if (!isHuge(box.extent(), box.reach(cam), box.distance(cam))) return found;
    for (std::size_t t = 0; t < m.triangleCount(); ++t) {
        DVec p[3];
        DBox tb;
        for (int k = 0; k < 3; ++k) {
            p[k] = toWorld(w, m.positions[m.indices[3 * t + k]]);
            tb.extend(p[k]);
        }
        // The camera's distance to the triangle is at least its distance to the triangle's
        // bounding box and to its plane.
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
    return found;
}

} // namespace

HugeTriangles findHugeTriangles(const Scene& scene) {
    HugeTriangles huge;
    if (!scene.root) return huge;
    std::vector<PlacedLeaf> leaves;
    forEachPlacedLeaf(*scene.root, scene.root->transform,
                      [&](const Shape& s, const Affine& w) { leaves.push_back({&s, w}); });
    // Each mesh's median triangle extent and bounds once, the meshes in parallel (a mesh
    // placed many times is one task).
    std::vector<const TriangleMesh*> meshes;
    std::unordered_map<const TriangleMesh*, std::size_t> meshIndex;
    for (const PlacedLeaf& l : leaves)
        if (l.shape->type == ShapeType::Mesh && meshIndex.emplace(l.shape->mesh.get(),
                                                                  meshes.size()).second)
            meshes.push_back(l.shape->mesh.get());
    std::vector<double> median(meshes.size());
    std::vector<Bounds3> localBounds(meshes.size());
    tbb::parallel_for(std::size_t(0), meshes.size(), [&](std::size_t i) {
        median[i] = medianExtent(*meshes[i]);
        localBounds[i] = meshes[i]->bounds();
    });
    // F: the typical size of the smallest shape, in the world.
    double smallest = std::numeric_limits<double>::infinity();
    for (const PlacedLeaf& l : leaves) {
        const Shape& s = *l.shape;
        double size = s.type == ShapeType::Mesh ? median[meshIndex.at(s.mesh.get())]
                                                : 2.0 * std::abs(double(s.radius));
        size *= lengthScale(l.toWorld);
        if (size > 0 && std::isfinite(size)) smallest = std::min(smallest, size);
    }

    const DVec cam{scene.camera.position.x, scene.camera.position.y, scene.camera.position.z};
    const double lens = std::abs(double(scene.camera.apertureRadius));
    auto isHuge = [&](double extent, double reach, double distance) {
        return kFloatTestError * extent > kTolerance * smallest ||
               kFloatTestError * reach > kTolerance * std::max(0.0, distance - lens);
    };
    // Each placement's huge triangles in parallel; merged per shape in placement order.
    std::vector<std::vector<unsigned>> found(leaves.size());
    tbb::parallel_for(std::size_t(0), leaves.size(), [&](std::size_t i) {
        const Shape& s = *leaves[i].shape;
        if (s.type != ShapeType::Mesh || s.mesh->triangleCount() == 0) return;
        found[i] = hugeOf(*s.mesh, localBounds[meshIndex.at(s.mesh.get())], leaves[i].toWorld,
                          cam, isHuge);
    });
    for (std::size_t i = 0; i < leaves.size(); ++i) {
        if (found[i].empty()) continue;
        std::vector<unsigned>& list = huge[leaves[i].shape];
        std::vector<unsigned> merged;
        std::set_union(list.begin(), list.end(), found[i].begin(), found[i].end(),
                       std::back_inserter(merged));
        list = std::move(merged);
    }
    return huge;
}

} // namespace rayproc
