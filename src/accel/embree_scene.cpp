#include "accel/embree_scene.h"

#include "accel/exact_triangles.h"
#include "core/error.h"
#include "kernels/exact_triangle.h"
#include "kernels/random.h"
#include "kernels/ray_offset.h"
#include "scene/camera_check.h"
#include "texture/texture_eval.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>

namespace rayproc {

namespace {

std::atomic<long long> g_embreeBytes{0};

bool memoryMonitor(void*, ssize_t bytes, bool) {
    g_embreeBytes += bytes;
    return true;
}

void embreeError(void*, RTCError code, const char* str) {
    // Embree reports API misuse and allocation failures here; both are fatal for a render.
    throw std::runtime_error(std::string("Embree error ") + std::to_string(int(code)) + ": " +
                             (str ? str : ""));
}

// A unit vector along n that survives tiny and huge lengths (a needle triangle's cross product
// can be 1e-30, whose squared length underflows): scaled by its largest component first.
// Zero or non-finite input gives zero.
Vec3 robustNormalize(const Vec3& n) {
    if (!isFinite(n)) return Vec3(0.0f);
    float m = maxComponent(kernels::absVec(n));
    if (!(m > 0) || !std::isfinite(m)) return Vec3(0.0f);
    // Largest component +-1: the squared length is in [1, 3], normalize()'s unscaled case,
    // taken here without its range test.
    Vec3 s = n / m;
    return s / std::sqrt(dot(s, s));
}

// Embree's range (kEmbreeRayLimit, kMaxWorldCoordinate: scene/camera_check.h): in an
// instance's space a ray's components are at most |inverse transform| (max row sum) times the
// world's.

// A triangle hit whose barycentric error bound exceeds this fraction of the magnitude of the
// point and of the ray's origin is recomputed (EmbreeScene::surface). Ordinary meshes stay near
// 1e-6 of it, so their hit points, and images, do not change.
constexpr float kRefineTriangleHit = 1e-4f;

double maxAbs(const Vec3& v) {
    return std::max({std::abs(double(v.x)), std::abs(double(v.y)), std::abs(double(v.z))});
}

// Max row sum of the linear part: the factor by which the transform can grow a component.
double linearNorm(const Affine& a) {
    double n = 0;
    for (int r = 0; r < 3; ++r)
        n = std::max(n, std::abs(double(a.m[r][0])) + std::abs(double(a.m[r][1])) +
                            std::abs(double(a.m[r][2])));
    return n;
}

std::string nodeLabel(const Node& n, const std::string& path) {
    return (n.name.empty() ? std::string("node") : "node '" + n.name + "'") + " (" + path + ")";
}

// Refuses, before Embree sees it, a scene whose rays would leave Embree's range: geometry, the
// camera or a light beyond kMaxWorldCoordinate, or a placement (transformed group, instance)
// whose inverse stretches world rays beyond kEmbreeRayLimit (a scale of 1e-20 on one axis).
void checkRanges(const Scene& scene) {
    auto fail = [](const std::string& what) {
        throw InputError("the scene cannot be rendered: " + what);
    };
    auto num = rangeNumber;
    // The loaders refuse such a camera already; scenes built in code meet the same check.
    if (auto problem = cameraProblem(scene.camera)) fail(problem->message);
    Bounds3 world = scene.worldBounds();
    double reach = maxAbs(scene.camera.position) + double(scene.camera.apertureRadius);
    if (!world.empty()) {
        double extent = std::max(maxAbs(world.lo), maxAbs(world.hi));
        if (!std::isfinite(extent) || extent > kMaxWorldCoordinate)
            fail("its geometry reaches a coordinate of " + num(extent) +
                 "; rayproc handles coordinates up to " + num(kMaxWorldCoordinate) +
                 " (Embree's rays must stay within " + num(kEmbreeRayLimit) + ")");
        reach = std::max(reach, extent);
    }
    for (const Light& l : scene.lights) {
        if (l.type != LightType::Point && l.type != LightType::Spot) continue;
        double at = maxAbs(l.position);
        if (!std::isfinite(at) || at > kMaxWorldCoordinate)
            fail("light '" + l.name + "' is at a coordinate of " + num(at) +
                 "; rayproc handles coordinates up to " + num(kMaxWorldCoordinate));
    }
    // A world ray's components: origin up to `reach`, direction up to the world's span; in a
    // placement's space, origin minus its translation.
    auto check = [&](const Node& n, const Affine& placed, const std::string& path) {
        double det = double(placed.determinant());
        double stretch = linearNorm(placed.inverse());
        double translation = maxAbs(Vec3(placed.m[0][3], placed.m[1][3], placed.m[2][3]));
        double span = 2.0 * reach + translation + 1.0;
        if (!(det != 0) || !std::isfinite(det) || !std::isfinite(stretch) ||
            stretch * span > kEmbreeRayLimit / 10)
            fail(nodeLabel(n, path) + ": its transform, composed with its parents', shrinks an "
                 "axis so far (its inverse grows vectors by up to " + num(stretch) +
                 ") that rays in its space would leave Embree's range of " +
                 num(kEmbreeRayLimit) + "; scale the geometry itself, or less");
    };
    std::function<void(const Node&, const Affine&, const std::string&)> visit =
        [&](const Node& group, const Affine& toWorld, const std::string& path) {
            for (std::size_t i = 0; i < group.children.size(); ++i) {
                const Node& c = *group.children[i];
                std::string p = path + "/" + std::to_string(i);
                if (c.kind == Node::Kind::Shape) continue;
                if (c.kind == Node::Kind::Group && c.transform.isIdentity()) {
                    visit(c, toWorld, p);
                    continue;
                }
                Affine placed = c.kind == Node::Kind::Instance
                                    ? toWorld * c.transform * c.prototype->transform
                                    : toWorld * c.transform;
                check(c, placed, p);
                visit(c.kind == Node::Kind::Instance ? *c.prototype : c, placed, p);
            }
        };
    if (!scene.root) return;
    if (!scene.root->transform.isIdentity()) check(*scene.root, scene.root->transform, "root");
    visit(*scene.root, scene.root->transform, "root");
}

} // namespace

EmbreeScene::EmbreeScene(const Scene& scene) : m_scene(scene) {
    checkRanges(scene);
    auto start = std::chrono::steady_clock::now();
    long long bytesBefore = g_embreeBytes.load();
    m_device = rtcNewDevice(nullptr);
    if (!m_device) throw std::runtime_error("Embree: cannot create device");
    rtcSetDeviceErrorFunction(m_device, embreeError, nullptr);
    rtcSetDeviceMemoryMonitorFunction(m_device, memoryMonitor, nullptr);
    m_top = rtcNewScene(m_device);
    rtcSetSceneBuildQuality(m_top, RTC_BUILD_QUALITY_MEDIUM);

    RAYPROC_CHECK(scene.root && scene.root->kind == Node::Kind::Group);
    m_huge = findHugeTriangles(scene);
    place(*scene.root, scene.root->transform, true);
    for (auto& p : m_prototypes) rtcCommitScene(p.scene);
    rtcCommitScene(m_top);

    m_stats.prototypes = m_prototypes.size();
    m_stats.instances = m_instances.size();
    // Unique triangles: each mesh once, however many times it is placed.
    std::unordered_map<const TriangleMesh*, bool> seen;
    auto countMesh = [&](const Shape* s) {
        if (s && s->type == ShapeType::Mesh && !seen[s->mesh.get()]) {
            seen[s->mesh.get()] = true;
            m_stats.uniqueTriangles += s->mesh->triangleCount();
        }
    };
    for (auto& p : m_prototypes)
        for (const Shape* s : p.leaves) countMesh(s);
    for (const GeomEntry& e : m_topEntries) countMesh(e.leaf);
    m_stats.memoryBytes = std::size_t(std::max(0LL, g_embreeBytes.load() - bytesBefore));
    m_stats.buildSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

EmbreeScene::~EmbreeScene() {
    for (auto& p : m_prototypes) rtcReleaseScene(p.scene);
    if (m_top) rtcReleaseScene(m_top);
    if (m_device) rtcReleaseDevice(m_device);
}

// Leaves of a group that share its space: its own shapes and those of identity-transformed
// child groups. Transformed child groups and instances are placed separately.
void EmbreeScene::collectLeaves(const Node& group, std::vector<const Shape*>& out) const {
    for (auto& c : group.children) {
        if (c->kind == Node::Kind::Shape) out.push_back(&c->shape);
        else if (c->kind == Node::Kind::Group && c->transform.isIdentity()) collectLeaves(*c, out);
    }
}

namespace {

// Alpha cut-outs (pbrt-v4's shape "alpha"): Embree calls this for every candidate hit of a mesh
// with alpha (alphaKeeps decides).
void alphaFilter(const RTCFilterFunctionNArguments* args) {
    const auto* cut = static_cast<const AlphaCutout*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] == 0) continue;
        unsigned prim = RTCHitN_primID(args->hit, args->N, i);
        if (cut->triangles) prim = (*cut->triangles)[prim];
        float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
        const float ray[6] = {RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                              RTCRayN_org_z(args->ray, args->N, i), RTCRayN_dir_x(args->ray, args->N, i),
                              RTCRayN_dir_y(args->ray, args->N, i), RTCRayN_dir_z(args->ray, args->N, i)};
        if (!alphaKeeps(*cut, args->context->instID[0], prim, u, v, ray)) args->valid[i] = 0;
    }
}

} // namespace

bool alphaKeeps(const AlphaCutout& cut, unsigned instId, unsigned prim, float u, float v,
                const float ray[6]) {
    const TriangleMesh& m = *cut.shape->mesh;
    const std::uint32_t* corner = &m.indices[3 * std::size_t(prim)];
    const float w = 1 - u - v;
    TextureContext tc;
    tc.uv = {u, v};
    if (!m.uvs.empty()) {
        const Vec2& a = m.uvs[corner[0]];
        const Vec2& b = m.uvs[corner[1]];
        const Vec2& c = m.uvs[corner[2]];
        tc.uv = {a.x * w + b.x * u + c.x * v, a.y * w + b.y * u + c.y * v};
    }
    const Vec3& pa = m.positions[corner[0]];
    const Vec3& pb = m.positions[corner[1]];
    const Vec3& pc = m.positions[corner[2]];
    tc.p = pa * w + pb * u + pc * v;
    tc.n = cross(pb - pa, pc - pa);
    if (const InstanceRecord* inst = cut.placements ? cut.placements->placement(instId) : nullptr) {
        tc.p = inst->toWorld.point(tc.p);
        tc.n = inst->toLocal.normalByInverse(tc.n);
    }
    tc.n = normalize(tc.n);
    float alpha = evalFloat(*cut.scene, cut.shape->alpha, tc);
    if (alpha >= 1) return true;
    if (!(alpha > 0)) return false;
    std::uint64_t h = prim;
    for (int k = 0; k < 6; ++k) {
        std::uint32_t bits;
        std::memcpy(&bits, &ray[k], sizeof bits);
        h = kernels::hashCombine(h, bits);
    }
    return float(h >> 40) * 0x1p-24f < alpha;
}

void EmbreeScene::attachGeometry(RTCScene target, RTCGeometry geom, const GeomEntry& entry,
                                 std::vector<GeomEntry>& geoms) {
    rtcCommitGeometry(geom);
    unsigned id = rtcAttachGeometry(target, geom);
    rtcReleaseGeometry(geom);
    RAYPROC_CHECK(id == geoms.size());
    geoms.push_back(entry);
}

namespace {

// An Embree triangle geometry of the mesh's triangles, or of `part` of them (count of them).
// Copies (not shared buffers): Embree reads vertex buffers with 16-byte loads and needs padding
// past the last vertex that a std::vector<Vec3> does not guarantee.
RTCGeometry newTriangleGeometry(RTCDevice device, const TriangleMesh& m,
                                const std::vector<unsigned>* part, std::size_t count) {
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
        m.positions.size()));
    std::memcpy(v, m.positions.data(), m.positions.size() * sizeof(Vec3));
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), count));
    if (!part) {
        std::memcpy(idx, m.indices.data(), m.indices.size() * sizeof(unsigned));
    } else {
        for (std::size_t k = 0; k < count; ++k)
            std::memcpy(idx + 3 * k, &m.indices[3 * std::size_t((*part)[k])],
                        3 * sizeof(unsigned));
    }
    return geom;
}

// Embree's sphere or oriented disk primitive for an analytic shape.
RTCGeometry newPointGeometry(RTCDevice device, const Shape& shape) {
    const bool disk = shape.type == ShapeType::Disk;
    RTCGeometry geom = rtcNewGeometry(device, disk ? RTC_GEOMETRY_TYPE_ORIENTED_DISC_POINT
                                                   : RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
    v[0] = shape.center.x; v[1] = shape.center.y; v[2] = shape.center.z; v[3] = shape.radius;
    if (disk) {
        auto* n = static_cast<float*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_NORMAL, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 1));
        Vec3 nn = normalize(shape.normal);
        n[0] = nn.x; n[1] = nn.y; n[2] = nn.z;
    }
    return geom;
}

} // namespace

void EmbreeScene::attachShape(RTCScene target, const Shape& shape, std::vector<GeomEntry>& geoms) {
    if (shape.type == ShapeType::Mesh) {
        attachMesh(target, shape, geoms);
        return;
    }
    attachGeometry(target, newPointGeometry(m_device, shape), {&shape, nullptr, false}, geoms);
}

void EmbreeScene::attachMesh(RTCScene target, const Shape& shape, std::vector<GeomEntry>& geoms) {
    const TriangleMesh& m = *shape.mesh;
    bool alpha = shape.alpha.textured() || shape.alpha.value < 1.0f;
    // Huge triangles (accel/huge_triangles.h) are intersected in double precision by a
    // user geometry; the mesh's other triangles stay Embree's, their primIDs mapped back.
    auto hugeIt = m_huge.find(&shape);
    const std::vector<unsigned>* embreePart = nullptr;
    std::size_t embreeCount = m.triangleCount();
    if (hugeIt != m_huge.end()) {
        auto exact = std::make_unique<ExactTriangles>();
        exact->mesh = &m;
        exact->triangles = hugeIt->second;
        auto rest = std::make_unique<std::vector<unsigned>>();
        for (unsigned t = 0, k = 0; t < m.triangleCount(); ++t) {
            if (k < exact->triangles.size() && exact->triangles[k] == t) ++k;
            else rest->push_back(t);
        }
        embreeCount = rest->size();
        embreePart = rest.get();
        m_embreeParts.push_back(std::move(rest));
        if (alpha) {
            m_alpha.push_back(
                std::make_unique<AlphaCutout>(AlphaCutout{&m_scene, &shape, nullptr, this}));
            exact->alpha = m_alpha.back().get();
        }
        m_stats.exactTriangles += exact->triangles.size();
        m_exact.push_back(std::move(exact));
    }
    if (embreeCount > 0) {
        RTCGeometry geom = newTriangleGeometry(m_device, m, embreePart, embreeCount);
        if (alpha) {
            m_alpha.push_back(
                std::make_unique<AlphaCutout>(AlphaCutout{&m_scene, &shape, embreePart, this}));
            rtcSetGeometryUserData(geom, m_alpha.back().get());
            rtcSetGeometryIntersectFilterFunction(geom, alphaFilter);
            rtcSetGeometryOccludedFilterFunction(geom, alphaFilter);
        }
        attachGeometry(target, geom, {&shape, embreePart, false}, geoms);
    }
    if (hugeIt != m_huge.end()) {
        const ExactTriangles& exact = *m_exact.back();
        attachGeometry(target, newExactTriangleGeometry(m_device, exact),
                       {&shape, &exact.triangles, true}, geoms);
    }
}

int EmbreeScene::prototypeFor(const Node& group) {
    auto it = m_prototypeOf.find(&group);
    if (it != m_prototypeOf.end()) return it->second;
    Prototype p;
    p.scene = rtcNewScene(m_device);
    rtcSetSceneBuildQuality(p.scene, RTC_BUILD_QUALITY_MEDIUM);
    collectLeaves(group, p.leaves);
    for (const Shape* s : p.leaves) attachShape(p.scene, *s, p.geoms);
    int index = int(m_prototypes.size());
    m_prototypes.push_back(std::move(p));
    m_prototypeOf[&group] = index;
    return index;
}

namespace {
// Visits the children of a group that are placed on their own: transformed groups and
// instances, looking through identity groups whose leaves were merged into the parent.
template <class F>
void forEachPlacedChild(const Node& group, F&& f) {
    for (auto& c : group.children) {
        if (c->kind == Node::Kind::Instance) f(*c);
        else if (c->kind == Node::Kind::Group) {
            if (c->transform.isIdentity()) forEachPlacedChild(*c, f);
            else f(*c);
        }
    }
}
} // namespace

void EmbreeScene::place(const Node& group, const Affine& toWorld, bool isRoot) {
    std::vector<const Shape*> leaves;
    collectLeaves(group, leaves);
    auto countPlaced = [&](const Shape* s, const Affine& w, int instance) {
        ++m_stats.leaves;
        if (s->type == ShapeType::Mesh) m_stats.placedTriangles += s->mesh->triangleCount();
        if (s->type == ShapeType::Sphere) ++m_stats.spheres;
        if (s->type == ShapeType::Disk) ++m_stats.disks;
        if (s->isEmissive()) m_emitters.push_back({s, w, w.inverse(), instance});
    };
    if (!leaves.empty()) {
        if (isRoot && toWorld.isIdentity()) {
            for (const Shape* s : leaves) {
                attachShape(m_top, *s, m_topEntries);
                countPlaced(s, toWorld, -1);
            }
        } else {
            int proto = prototypeFor(group);
            RTCGeometry inst = rtcNewGeometry(m_device, RTC_GEOMETRY_TYPE_INSTANCE);
            rtcSetGeometryInstancedScene(inst, m_prototypes[proto].scene);
            float m[12];
            toWorld.toColumnMajor(m);
            rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m);
            GeomEntry entry;
            entry.instance = int(m_instances.size());
            attachGeometry(m_top, inst, entry, m_topEntries);
            m_instances.push_back({proto, toWorld, toWorld.inverse()});
            for (const Shape* s : leaves) countPlaced(s, toWorld, int(m_instances.size()) - 1);
        }
    }
    forEachPlacedChild(group, [&](const Node& child) {
        if (child.kind == Node::Kind::Instance) {
            const Node& proto = *child.prototype;
            place(proto, toWorld * child.transform * proto.transform, false);
        } else {
            place(child, toWorld * child.transform, false);
        }
    });
}

namespace {

// A hit on a huge triangle that the user geometry found in double precision
// (accel/exact_triangles.h): the same test again, in the same space (the ray mapped into the
// instance's), gives the point as o + t d rounded once, and barycentrics in double for the
// shading normal and the texture coordinates, which on a 1e9 triangle Embree's float (u, v)
// would place tens of units off. The error bound is that rounding plus what the double test of
// a ray leaving the point can miss the plane by (kernels::exactTriangleError), a few 1e-15 of
// the triangle's size, not the float test's gamma_12 (|e1| + |e2|) of hundreds of units: the
// spawned rays start next to the plane, so the contact shadows stay. False if the ray, as
// mapped here, is parallel to the plane (the caller falls back to Embree's barycentrics).
bool exactTriangleSurface(const TriangleMesh& m, unsigned i0, unsigned i1, unsigned i2,
                          const Affine* toLocal, const Vec3& rayOrigin, const Vec3& rayDir,
                          SurfaceHit& h, Vec3& pl, Vec3& errl, Vec3& ngl, Vec3& nsl, Vec3& dpdul,
                          Vec3& dpdvl) {
    const Vec3 &p0 = m.positions[i0], &p1 = m.positions[i1], &p2 = m.positions[i2];
    Vec3 ol = toLocal ? toLocal->point(rayOrigin) : rayOrigin;
    Vec3 dl = toLocal ? toLocal->vector(rayDir) : rayDir;
    kernels::ExactTriangleHit x = kernels::intersectTriangleExact(ol, dl, p0, p1, p2);
    if (!x.valid) return false;
    Vec3 p{float(ol.x + x.t * dl.x), float(ol.y + x.t * dl.y), float(ol.z + x.t * dl.z)};
    if (!isFinite(p)) return false;
    pl = p;
    errl = kernels::absVec(p) * kernels::errorGamma(1) +
           Vec3(float(kernels::exactTriangleError(p, ol, p0, p1, p2)));
    const double u = x.u, v = x.v, w = 1 - u - v;
    const double ex = double(p1.x) - p0.x, ey = double(p1.y) - p0.y, ez = double(p1.z) - p0.z;
    const double fx = double(p2.x) - p0.x, fy = double(p2.y) - p0.y, fz = double(p2.z) - p0.z;
    ngl = {float(ey * fz - ez * fy), float(ez * fx - ex * fz), float(ex * fy - ey * fx)};
    auto blend = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
        return Vec3{float(w * a.x + u * b.x + v * c.x), float(w * a.y + u * b.y + v * c.y),
                    float(w * a.z + u * b.z + v * c.z)};
    };
    nsl = m.normals.empty() ? ngl : blend(m.normals[i0], m.normals[i1], m.normals[i2]);
    dpdul = p1 - p0;
    dpdvl = p2 - p0;
    if (!m.uvs.empty()) {
        const Vec2 &a = m.uvs[i0], &b = m.uvs[i1], &c = m.uvs[i2];
        h.uv = {float(w * a.x + u * b.x + v * c.x), float(w * a.y + u * b.y + v * c.y)};
        Vec2 d02{a.x - c.x, a.y - c.y}, d12{b.x - c.x, b.y - c.y};
        float det = d02.x * d12.y - d02.y * d12.x;
        if (std::abs(det) > 1e-9f) {
            dpdul = ((p0 - p2) * d12.y - (p1 - p2) * d02.y) / det;
            dpdvl = ((p1 - p2) * d02.x - (p0 - p2) * d12.x) / det;
        }
    } else {
        h.uv = {float(u), float(v)};
    }
    return true;
}

// The far-triangle refinement: the triangle's vertices are far larger than the hit point and
// the ray's origin (a 1e9 ground plane seen from near the origin), so the barycentric sum
// cancels to errors of ~60 units along the plane. The ray meets the triangle's plane again in
// double precision instead. The error bound stays the barycentric one: it is what Embree's own
// float arithmetic on these vertices can miss the plane by, so the spawned rays' offsets still
// clear it, raised to the refined point's own error where that is larger (along an
// axis-aligned plane's normal the barycentric bound is 0: the vertices agree exactly there, the
// refined point need not). Leaves pl and errl as they are if the ray is parallel to the plane.
void refineFarTrianglePoint(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& ol,
                            const Vec3& dl, Vec3& pl, Vec3& errl) {
    double ax = p0.x, ay = p0.y, az = p0.z;
    double ex = double(p1.x) - ax, ey = double(p1.y) - ay, ez = double(p1.z) - az;
    double fx = double(p2.x) - ax, fy = double(p2.y) - ay, fz = double(p2.z) - az;
    double nx = ey * fz - ez * fy, ny = ez * fx - ex * fz, nz = ex * fy - ey * fx;
    double denom = nx * dl.x + ny * dl.y + nz * dl.z;
    if (denom == 0 || !std::isfinite(denom)) return;
    double tl = (nx * (ax - ol.x) + ny * (ay - ol.y) + nz * (az - ol.z)) / denom;
    Vec3 refined{float(ol.x + tl * dl.x), float(ol.y + tl * dl.y), float(ol.z + tl * dl.z)};
    if (!isFinite(refined)) return;
    // Its own error: the double arithmetic (a few roundings of 2^-53 relative to the origin
    // and the ray's reach), then the rounding to float.
    double reach = maxComponent(kernels::absVec(ol)) +
                   std::abs(tl) * maxComponent(kernels::absVec(dl));
    Vec3 own = kernels::absVec(refined) * 0x1p-23f + Vec3(float(reach * 0x1p-48));
    pl = refined;
    errl = vmax(errl, own);
}

// A hit's geometry in its shape's own space, before the instance's transform: references to
// the caller's variables (kept apart, not one aggregate, so that the compiler keeps them in
// registers on the hot triangle path).
struct LocalSurface {
    Vec3 &p, &err, &ng, &ns, &dpdu, &dpdv;
};

// A triangle hit from Embree's barycentrics (u, v), or from the exact double-precision test
// on a huge triangle (exactTriangleSurface).
void triangleSurface(const TriangleMesh& m, unsigned tri, bool exact, float u, float v,
                     const Affine* toLocal, const Vec3& rayOrigin, const Vec3& rayDir,
                     SurfaceHit& h, const LocalSurface& l) {
    unsigned i0 = m.indices[3 * tri], i1 = m.indices[3 * tri + 1], i2 = m.indices[3 * tri + 2];
    const Vec3 &p0 = m.positions[i0], &p1 = m.positions[i1], &p2 = m.positions[i2];
    if (exact && exactTriangleSurface(m, i0, i1, i2, toLocal, rayOrigin, rayDir, h, l.p, l.err,
                                      l.ng, l.ns, l.dpdu, l.dpdv))
        return;
    float w = 1.0f - u - v;
    // The point from barycentrics is more accurate than o + t d far from the origin, and
    // its error bound is known (kernels/ray_offset.h).
    l.p = kernels::trianglePoint(p0, p1, p2, u, v, l.err);
    Vec3 ol = toLocal ? toLocal->point(rayOrigin) : rayOrigin;
    if (maxComponent(l.err) > kRefineTriangleHit * std::max(maxComponent(kernels::absVec(l.p)),
                                                            maxComponent(kernels::absVec(ol))))
        refineFarTrianglePoint(p0, p1, p2, ol, toLocal ? toLocal->vector(rayDir) : rayDir, l.p,
                               l.err);
    l.ng = cross(p1 - p0, p2 - p0);
    l.ns = m.normals.empty() ? l.ng : m.normals[i0] * w + m.normals[i1] * u + m.normals[i2] * v;
    l.dpdu = p1 - p0; // without uvs: the first edge and the second
    l.dpdv = p2 - p0;
    if (!m.uvs.empty()) {
        h.uv = {m.uvs[i0].x * w + m.uvs[i1].x * u + m.uvs[i2].x * v,
                m.uvs[i0].y * w + m.uvs[i1].y * u + m.uvs[i2].y * v};
        // dp/du and dp/dv from the triangle's two edges and their uv differences (pbrt-v4's
        // rule).
        Vec2 d02{m.uvs[i0].x - m.uvs[i2].x, m.uvs[i0].y - m.uvs[i2].y};
        Vec2 d12{m.uvs[i1].x - m.uvs[i2].x, m.uvs[i1].y - m.uvs[i2].y};
        float det = d02.x * d12.y - d02.y * d12.x;
        if (std::abs(det) > 1e-9f) {
            l.dpdu = ((p0 - p2) * d12.y - (p1 - p2) * d02.y) / det;
            l.dpdv = ((p1 - p2) * d02.x - (p0 - p2) * d12.x) / det;
        }
    } else {
        h.uv = {u, v};
    }
}

// The direction of growing phi at the point (x, y) of the shape's frame: (-y, x) in it, of
// length r (a sphere's and a disk's dp/du, up to the disk's 2 pi).
Vec3 alongPhi(const Shape& s, float x, float y) { return s.frameY * x - s.frameX * y; }

// Embree's single-ray and packet kernels round a sphere's t differently (by an ulp or so).
// Solving the quadratic again in double precision, and taking the root Embree found, makes the
// hit point independent of the packet width and more accurate.
void sphereSurface(const Shape& s, const Affine* toLocal, const Vec3& rayOrigin,
                   const Vec3& rayDir, float t, const LocalSurface& l) {
    Vec3 ol = toLocal ? toLocal->point(rayOrigin) : rayOrigin;
    Vec3 dl = toLocal ? toLocal->vector(rayDir) : rayDir;
    double ocx = double(ol.x) - s.center.x, ocy = double(ol.y) - s.center.y,
           ocz = double(ol.z) - s.center.z;
    double a = double(dl.x) * dl.x + double(dl.y) * dl.y + double(dl.z) * dl.z;
    double bh = ocx * dl.x + ocy * dl.y + ocz * dl.z;
    double c = ocx * ocx + ocy * ocy + ocz * ocz - double(s.radius) * s.radius;
    double sq = std::sqrt(std::max(0.0, bh * bh - a * c));
    double t0 = (-bh - sq) / a, t1 = (-bh + sq) / a;
    double tl = std::abs(t0 - t) <= std::abs(t1 - t) ? t0 : t1;
    Vec3 p{float(ocx + tl * dl.x), float(ocy + tl * dl.y), float(ocz + tl * dl.z)};
    l.ng = p;
    // Re-project onto the surface: removes what error remains along the normal.
    l.p = s.center + robustNormalize(l.ng) * s.radius;
    l.err = kernels::roundSurfaceError(l.p, s.center, s.radius);
    l.ns = l.ng;
    // Along phi about the pole frameZ (sphereUv's u), |dp/dphi| = the distance from the axis.
    const Vec3 q = l.p - s.center;
    l.dpdu = alongPhi(s, dot(q, s.frameX), dot(q, s.frameY));
    l.dpdv = cross(l.ns, l.dpdu);
}

// phi / 2 pi of the point (x, y) in the shape's frame, phi in [0, 2 pi).
float azimuthU(float x, float y) {
    float phi = std::atan2(y, x);
    if (phi < 0) phi += 2 * kPi;
    return phi * 0.5f * kInvPi;
}

// pbrt-v4's (u, v) of a whole sphere's point p (in the sphere's space): u = phi / 2 pi, phi
// about frameZ from frameX towards frameY in [0, 2 pi), and v = 1 - theta / pi, theta from the
// pole frameZ. `step`: how far (u, v) move per unit of the hit's dp/du and dp/dv (sphereSurface's
// are dp/dphi and ns x dp/dphi): 1 / 2 pi and rho / (pi r), rho the distance from the axis.
Vec2 sphereUv(const Shape& s, const Vec3& p, Vec2& step) {
    const Vec3 q = p - s.center;
    const float x = dot(q, s.frameX), y = dot(q, s.frameY), z = dot(q, s.frameZ);
    const float theta = std::acos(std::clamp(z / s.radius, -1.0f, 1.0f));
    const float rho = std::sqrt(x * x + y * y);
    step = {0.5f * kInvPi, rho * kInvPi / s.radius};
    return {azimuthU(x, y), 1.0f - theta * kInvPi};
}

// pbrt-v4's (u, v) of a whole disk's point: u = phi / 2 pi as a sphere's, v = 1 - r / radius.
Vec2 diskUv(const Shape& s, const Vec3& p) {
    const Vec3 q = p - s.center;
    const float x = dot(q, s.frameX), y = dot(q, s.frameY);
    return {azimuthU(x, y), 1.0f - std::sqrt(x * x + y * y) / s.radius};
}

// A disk's point projected onto its plane, with pbrt-v4's dp/du = 2 pi (-y, x) and dp/dv =
// -(radius / r) (x, y) in the disk's frame (diskUv's u and v). At the centre, where neither is
// defined, both are zero and shading takes a frame about the normal.
void diskSurface(const Shape& s, const Affine* toLocal, const Vec3& rayOrigin,
                 const Vec3& rayDir, float t, const LocalSurface& l) {
    Vec3 pw = rayOrigin + rayDir * t;
    Vec3 p = toLocal ? toLocal->point(pw) : pw;
    l.ng = s.normal;
    l.p = p - l.ng * (dot(p - s.center, l.ng) / dot(l.ng, l.ng));
    l.err = kernels::roundSurfaceError(l.p, s.center, s.radius);
    l.ns = l.ng;
    const Vec3 q = l.p - s.center;
    const float x = dot(q, s.frameX), y = dot(q, s.frameY), r = std::sqrt(x * x + y * y);
    if (!(r > 0)) return;
    l.dpdu = alongPhi(s, x, y) * (2 * kPi);
    l.dpdv = (s.frameX * x + s.frameY * y) * (-s.radius / r);
}

// Whether two vectors are the same bits (== would take -0 for 0 and never NaN for NaN).
bool sameBits(const Vec3& a, const Vec3& b) {
    static_assert(sizeof(Vec3) == 3 * sizeof(float));
    return std::memcmp(&a, &b, sizeof(Vec3)) == 0;
}

// The local geometry into world space, with normals that are never zero or NaN.
void placeSurface(const LocalSurface& l, const Affine* toWorld, const Affine* toLocal,
                  const Vec3& rayDir, SurfaceHit& h) {
    if (toWorld) {
        h.p = toWorld->point(l.p);
        h.pError = kernels::transformedPointError(*toWorld, l.p, l.err);
        h.ng = robustNormalize(toLocal->normalByInverse(l.ng));
        // A surface without its own shading normals has ns = ng: the same result, once.
        h.ns = sameBits(l.ns, l.ng) ? h.ng : robustNormalize(toLocal->normalByInverse(l.ns));
        h.dpdu = toWorld->vector(l.dpdu);
        h.dpdv = toWorld->vector(l.dpdv);
        // The inverse transpose keeps the front side the side the winding named in the
        // shape's own space, also under mirroring transforms (as pbrt's handedness flip does).
    } else {
        h.p = l.p;
        h.pError = l.err;
        h.ng = robustNormalize(l.ng);
        h.ns = sameBits(l.ns, l.ng) ? h.ng : robustNormalize(l.ns);
        h.dpdu = l.dpdu;
        h.dpdv = l.dpdv;
    }
    // Degenerate input never yields a zero or NaN normal: a triangle without area (Embree can
    // still report a hit on a needle whose cross product underflows) faces the ray, and a zero,
    // missing or non-finite shading normal falls back to the geometric one.
    if (isBlack(h.ng)) h.ng = robustNormalize(-rayDir);
    if (isBlack(h.ng)) h.ng = {0, 1, 0};
    if (isBlack(h.ns)) h.ns = h.ng;
    if (dot(h.ns, h.ng) < 0) h.ns = -h.ns;
}

} // namespace

const InstanceRecord* EmbreeScene::placement(unsigned instId) const {
    if (instId == RTC_INVALID_GEOMETRY_ID) return nullptr;
    return &m_instances[m_topEntries[instId].instance];
}

SurfaceHit EmbreeScene::surface(unsigned instId, unsigned geomId, unsigned primId, float u,
                                float v, const Vec3& rayOrigin, const Vec3& rayDir,
                                float t) const {
    SurfaceHit h;
    const Affine* toWorld = nullptr;
    const Affine* toLocal = nullptr;
    const GeomEntry* g = nullptr;
    if (instId != RTC_INVALID_GEOMETRY_ID) {
        const GeomEntry& e = m_topEntries[instId];
        const InstanceRecord& inst = m_instances[e.instance];
        g = &m_prototypes[inst.prototype].geoms[geomId];
        h.instance = e.instance;
        toWorld = &inst.toWorld;
        toLocal = &inst.toLocal;
    } else {
        g = &m_topEntries[geomId];
    }
    h.shape = g->leaf;
    const Shape& s = *h.shape;
    h.material = s.material;
    Vec3 pl, errl, ngl, nsl, dpdul, dpdvl;
    const LocalSurface l{pl, errl, ngl, nsl, dpdul, dpdvl};
    switch (s.type) {
    case ShapeType::Mesh:
        triangleSurface(*s.mesh, g->triangles ? (*g->triangles)[primId] : primId, g->exact, u, v,
                        toLocal, rayOrigin, rayDir, h, l);
        break;
    case ShapeType::Sphere:
        sphereSurface(s, toLocal, rayOrigin, rayDir, t, l);
        h.uv = sphereUv(s, pl, h.uvStep);
        break;
    case ShapeType::Disk:
        diskSurface(s, toLocal, rayOrigin, rayDir, t, l);
        h.uv = diskUv(s, pl);
        break;
    }
    placeSurface(l, toWorld, toLocal, rayDir, h);
    return h;
}

} // namespace rayproc
