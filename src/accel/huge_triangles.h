// Which triangles Embree's single-precision test cannot resolve well enough, so that
// EmbreeScene hands them to the double-precision user geometry (accel/exact_triangles.h).
//
// Embree's triangle test rounds (vertex - origin) and the edges to float: it can misplace the
// triangle's plane by a few ulps of max |vertex - origin|, and rayproc offsets every ray leaving
// a triangle by the bound gamma_12 (|e1| + |e2|) on that (kernels/ray_offset.h). For a ground
// plane 1e9 wide under a unit sphere that is hundreds of units: hits near the camera are lost
// (the sky shows through) and shadows are cast from far above the plane. A triangle is huge when
//   gamma_12 E > tol F            (the float error against the smallest shape), or
//   gamma_12 R > tol D            (against the camera's distance to it: camera rays),
// E the triangle's extent (largest side of its world bounding box), R its largest coordinate
// relative to the camera, D a lower bound of the camera's distance to it (to its plane and to
// its bounding box, less the lens radius), F the typical size of the smallest shape in the
// world (a sphere's or disk's diameter, a mesh's median triangle extent), tol = 1e-3: where
// Embree stays, its error, and the offset it forces, is below 0.1% of every shape and of the
// camera's distance. Both sides scale with the scene, and neither depends on where the scene
// sits: the Cornell box far from the origin keeps Embree's triangles. Measured
// (docs/robustness.md): a tilted plane under a unit sphere renders the same mean as a 1e3 one
// up to 1e5 wide with Embree's test, and differs by 0.2-0.4% at 1e6.
//
// The criterion is evaluated in world space for every placement of a leaf (a prototype's
// triangle is huge if it is huge in any placement); a mesh whose world bounds pass both tests
// is not looked at triangle by triangle.
#pragma once

#include "scene/scene.h"

#include <unordered_map>
#include <vector>

namespace rayproc {

// Per mesh leaf with huge triangles, their indices in the mesh (ascending).
using HugeTriangles = std::unordered_map<const Shape*, std::vector<unsigned>>;

HugeTriangles findHugeTriangles(const Scene& scene);

} // namespace rayproc
