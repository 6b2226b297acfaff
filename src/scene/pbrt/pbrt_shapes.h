// pbrt shapes as rayproc shape leaves. Triangle meshes (trianglemesh, plymesh, bilinearmesh as
// two triangles per patch, loopsubdiv as its control mesh) are baked into the space they are
// placed in, as pbrt does, so a scene of many transformed meshes does not become many Embree
// instances. Spheres and disks stay exact: under a similarity transform they are baked too
// (centre, radius, normal); under any other transform they keep it in a group.
//
// Front sides follow pbrt: a triangle (a, b, c) faces cross(b - a, c - a), flipped by
// ReverseOrientation and by transforms that swap handedness; with per-vertex normals the front
// is the side the normals point to.
#pragma once

#include "scene/pbrt/deferred_loads.h"
#include "scene/pbrt/pbrt_params.h"
#include "scene/pbrt/pbrt_transform.h"
#include "scene/pbrt/pbrt_warnings.h"
#include "scene/scene.h"

#include <filesystem>
#include <string>
#include <vector>

namespace rayproc::pbrt {

struct ShapeContext {
    Mat4 toWorld; // the shape's CTM, in the space of the node that will hold it
    bool reverseOrientation = false;
    bool emissive = false;         // an area light is active
    std::filesystem::path dir;     // of the file that names the shape
    std::filesystem::path mainDir; // of the scene file (pbrt resolves paths from there)
    SourceLoc loc;
    // Where a PLY file may be read in the background; null: read here and now.
    DeferredLoads* loads = nullptr;
};

struct ShapeResult {
    std::vector<Shape> shapes; // geometry only: material and emission are the caller's
    bool grouped = false;      // true: the shapes need a group with `groupTransform`
    Affine groupTransform;
    // true: the meshes are being read (ShapeContext::loads); they are empty until the loads
    // are joined, after which `isQuadMesh` gives each shape's isQuad.
    bool deferred = false;
};

// Whether a mesh is one quad: four corners as triangles (0, 1, 2), (0, 2, 3), as a JSON
// "quad" node is (preview mode puts a point light at each corner of a quad light).
bool isQuadMesh(const TriangleMesh& mesh);

// Converts one Shape directive; an unsupported type warns and returns no shapes. Malformed
// geometry (indices out of range, counts that disagree, missing PLY files) is an InputError.
ShapeResult convertShape(const std::string& type, const ParamList& params, const ShapeContext& ctx,
                         Warnings& warnings);

// The file a relative path names: next to the naming file, else next to the scene file.
std::filesystem::path resolvePath(const std::string& name, const std::filesystem::path& dir,
                                  const std::filesystem::path& mainDir);

} // namespace rayproc::pbrt
