// Wavefront OBJ files as one TriangleMesh, read with tinyobjloader (which copes with negative
// indices, n-gons and the other quirks of real-world OBJ files).
#pragma once

#include "scene/scene.h"

#include <string>

namespace rayproc {

// Loads every face of every object and group in the file into one triangle mesh; n-gons are
// triangulated. Positions are shared between faces wherever the file shares them, so indices
// stay compact. Normals and texture coordinates are kept only if every face corner has them
// (a position then splits into one vertex per distinct normal / uv combination). Materials
// (mtllib, usemtl) are ignored: the scene file assigns the material.
//
// Throws InputError "<path>: <problem>" if the file is missing, unreadable, malformed, refers
// to vertices it does not have, or has no faces; "<path>:<line>: <problem> in '<statement>'"
// for a statement that is not strictly valid (a coordinate that is not a finite float, too few
// coordinates, an index that is zero, not an integer, or beyond the int range).
TriangleMesh loadObjMesh(const std::string& path);
// The same for the file's contents; `path` only names it in errors.
TriangleMesh parseObjMesh(std::string text, const std::string& path);

} // namespace rayproc
