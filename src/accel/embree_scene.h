// Maps the scene hierarchy onto Embree. Debian's Embree 3.13 supports one instance level
// (RTC_MAX_INSTANCE_LEVEL_COUNT = 1), so the tree is flattened into a top-level scene that holds
// the root's own leaves plus one Embree instance per placement of a prototype scene. A group
// with a non-identity transform, and every instanced group, becomes one prototype RTCScene,
// committed once however often it is placed: geometry is never duplicated per instance.
// Triangles too large for Embree's single-precision test (a 1e9 ground plane seen from near the
// origin; accel/huge_triangles.h) are intersected in double precision by a user geometry
// (accel/exact_triangles.h), beside the rest of their mesh.
#pragma once

#include "accel/huge_triangles.h"
#include "core/math.h"
#include "scene/scene.h"

#include <embree3/rtcore.h>

#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace rayproc {

struct ExactTriangles;

// One leaf as Embree sees it: the shape, in its prototype's space.
struct LeafRecord {
    const Shape* shape = nullptr;
    const Affine* localToPrototype = nullptr; // unused today: leaves live in prototype space
};

// One placement of a prototype scene in the world.
struct InstanceRecord {
    int prototype = -1;
    Affine toWorld;
    Affine toLocal;
};

// An emissive leaf placed in the world (one per placement of its prototype).
struct EmitterRecord {
    const Shape* shape = nullptr;
    Affine toWorld;
    Affine toLocal;
    int instance = -1; // the InstanceRecord it is placed by; -1 for root-level leaves
};

// What an intersection is, in world space.
struct SurfaceHit {
    Vec3 p;        // world-space hit point
    Vec3 pError;   // per-component bound on |p - true surface point| (kernels/ray_offset.h)
    Vec3 ng;       // unit geometric normal (front side by the shape's winding/outward rule)
    Vec3 ns;       // unit shading normal, on the same side as ng
    Vec2 uv;       // pbrt-v4's: a mesh's, a sphere's (phi / 2 pi, 1 - theta / pi), a disk's
    Vec3 dpdu;     // world-space dp/du (the tangent of anisotropic roughness), not normalised
    Vec3 dpdv;     // world-space dp/dv (bump mapping); a mesh without uvs: the third vertex
                   // minus the first; spheres: ns x dpdu; disks: pbrt-v4's (0 at the centre)
    // How far (u, v) move per unit of dpdu and of dpdv (bump mapping's steps): 1 where they
    // are dp/du and dp/dv (meshes); a sphere's are dp/dphi and ns x dp/dphi (sphereUv).
    Vec2 uvStep{1.0f, 1.0f};
    const Shape* shape = nullptr;
    int material = 0;
    int instance = -1; // index of the InstanceRecord, -1 for root-level leaves
};

class EmbreeScene;

// What an alpha-tested mesh's Embree filter reads (embree_scene.cpp).
struct AlphaCutout {
    const Scene* scene;
    const Shape* shape;
    const std::vector<unsigned>* triangles = nullptr; // the mesh triangle of each primID; null: the same
    const EmbreeScene* placements = nullptr;          // the instance transforms (placement)
};

// Whether a candidate hit at (u, v) of the mesh's triangle `triangle`, reached through the
// top-level instance `instId` (Embree's instID[0]; RTC_INVALID_GEOMETRY_ID at the root),
// survives the cut-out: kept where alpha is 1, dropped where it is 0, in between kept with
// probability alpha, decided by a hash of the triangle and the ray (origin, direction) so every
// packet width and thread agrees. The texture sees the hit's uv, world point and geometric
// normal, as a shading hit's (a spherical, cylindrical or planar mapping, a 3D checkerboard, a
// direction mix).
bool alphaKeeps(const AlphaCutout& cut, unsigned instId, unsigned triangle, float u, float v,
                const float ray[6]);

struct AccelStats {
    std::size_t prototypes = 0;
    std::size_t instances = 0;          // Embree instances in the top-level scene
    std::size_t uniqueTriangles = 0;    // triangles stored once
    std::size_t placedTriangles = 0;    // triangles as seen in the world, counting instances
    std::size_t spheres = 0, disks = 0; // placed
    std::size_t exactTriangles = 0;     // stored once, intersected in double (accel/huge_triangles.h)
    std::size_t leaves = 0;             // placed shape leaves
    std::size_t memoryBytes = 0;        // Embree's allocations (BVHs, buffers)
    double buildSeconds = 0;
};

class EmbreeScene {
public:
    explicit EmbreeScene(const Scene& scene);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    RTCScene root() const { return m_top; }
    RTCDevice device() const { return m_device; }
    const Scene& scene() const { return m_scene; }
    const AccelStats& stats() const { return m_stats; }
    const std::vector<EmitterRecord>& emitters() const { return m_emitters; }
    const std::vector<InstanceRecord>& instances() const { return m_instances; }

    // The world and local transforms of the top-level instance `instId` (Embree's instID[0]);
    // null at the root (RTC_INVALID_GEOMETRY_ID), where leaves are in world space.
    const InstanceRecord* placement(unsigned instId) const;
    // Resolves an Embree hit (instID[0], geomID, primID, u, v) and the ray into world space.
    SurfaceHit surface(unsigned instId, unsigned geomId, unsigned primId, float u, float v,
                       const Vec3& rayOrigin, const Vec3& rayDir, float t) const;

private:
    // One Embree geometry: a leaf, or one of the two parts of a mesh leaf with huge triangles
    // (Embree's triangles, and the rest intersected in double precision), or in the top-level
    // scene an instance.
    struct GeomEntry {
        const Shape* leaf = nullptr;
        const std::vector<unsigned>* triangles = nullptr; // mesh triangle per primID; null: primID
        bool exact = false;                               // accel/exact_triangles.h
        int instance = -1;                                // top level: the InstanceRecord
    };
    struct Prototype {
        RTCScene scene = nullptr;
        std::vector<const Shape*> leaves;
        std::vector<GeomEntry> geoms; // by geomID
    };

    void place(const Node& group, const Affine& toWorld, bool isRoot);
    int prototypeFor(const Node& group);
    void collectLeaves(const Node& group, std::vector<const Shape*>& out) const;
    // Attaches the shape's geometries to `target`, their entries to `geoms` (by geomID).
    void attachShape(RTCScene target, const Shape& shape, std::vector<GeomEntry>& geoms);
    // A mesh's Embree triangles and, for its huge triangles, the exact user geometry.
    void attachMesh(RTCScene target, const Shape& shape, std::vector<GeomEntry>& geoms);
    void attachGeometry(RTCScene target, RTCGeometry geom, const GeomEntry& entry,
                        std::vector<GeomEntry>& geoms);

    const Scene& m_scene;
    RTCDevice m_device = nullptr;
    RTCScene m_top = nullptr;
    std::vector<Prototype> m_prototypes;
    std::unordered_map<const Node*, int> m_prototypeOf;
    std::vector<InstanceRecord> m_instances;
    std::vector<GeomEntry> m_topEntries; // by geomID of the top-level scene
    std::vector<EmitterRecord> m_emitters;
    std::vector<std::unique_ptr<AlphaCutout>> m_alpha; // filter data of alpha-tested meshes
    HugeTriangles m_huge;                                // accel/huge_triangles.h
    std::vector<std::unique_ptr<ExactTriangles>> m_exact; // their user geometries' data
    std::vector<std::unique_ptr<std::vector<unsigned>>> m_embreeParts; // the rest of those meshes
    AccelStats m_stats;
};

} // namespace rayproc
