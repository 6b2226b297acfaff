// Triangles that Embree must not intersect in single precision (accel/huge_triangles.h picks
// them) become one Embree user geometry per mesh leaf, whose callbacks intersect in double
// precision (kernels/exact_triangle.h) and report what a triangle hit reports: t, u, v in
// Embree's convention, Ng, primID (the mesh's triangle index), geomID and instID. Single rays and
// 4/8/16-wide packets go through the same per-lane code, so every packet width finds the same
// hit on a triangle it tests (which triangles a ray tests at a tie follows the traversal order:
// docs/architecture.md, the intersection handler). Alpha cut-outs apply as for Embree's
// triangles (the same decision, alphaKeeps).
#pragma once

#include "accel/embree_scene.h"

#include <embree3/rtcore.h>

#include <vector>

namespace rayproc {

// What the callbacks read; owned by EmbreeScene, alive as long as its Embree scenes.
struct ExactTriangles {
    const TriangleMesh* mesh = nullptr;
    std::vector<unsigned> triangles;    // the mesh's triangle index of each user primitive
    const AlphaCutout* alpha = nullptr; // null: no cut-out
};

// A committed-ready user geometry over `tris` (not attached, not committed).
RTCGeometry newExactTriangleGeometry(RTCDevice device, const ExactTriangles& tris);

} // namespace rayproc
