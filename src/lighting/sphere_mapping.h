// Parameterisations of the sphere of directions by the unit square, for environment and
// goniometric images (in the light's own space):
// - equal-area octahedral (Clarberg 2008, as pbrt-v4 defines it): the square folds onto an
//   octahedron whose faces are mapped area-preservingly onto the sphere, so every pixel of a
//   square image covers the same solid angle 4 pi / N; the centre of the square is +z, the
//   corners -z;
// - lat-long (pbrt-v3, Mitsuba): u = phi / 2 pi, v = theta / pi about +z, so a pixel covers a
//   solid angle proportional to sin theta (the Jacobian is 2 pi^2 sin theta).
#pragma once

#include "core/math.h"

namespace rayproc {

// [0,1]^2 -> unit vector, and its inverse.
Vec3 equalAreaSquareToSphere(Vec2 p);
Vec2 equalAreaSphereToSquare(const Vec3& d);

// Folds a pixel coordinate that left a square equal-area image of `res` x `res` pixels back
// onto the pixel on the other side of the edge (the octahedral wrap): crossing an edge mirrors
// the coordinate along the edge.
void wrapEqualAreaPixel(int& x, int& y, int res);

// [0,1]^2 -> unit vector (theta = pi v from +z, phi = 2 pi u from +x towards +y), its inverse,
// and sin theta at v.
Vec3 latLongToSphere(Vec2 uv);
Vec2 sphereToLatLong(const Vec3& d);

} // namespace rayproc
