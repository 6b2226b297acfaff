// PLY meshes for pbrt's "plymesh" shape: ASCII, binary little-endian and binary big-endian;
// vertex positions, and normals (nx ny nz) and texture coordinates (u v, s t, texture_u
// texture_v, texture_s texture_t) when the file has them; faces as triangles, quads (split
// into two triangles along the 0-2 diagonal) and larger polygons (fanned, counted so the caller
// can warn). Other elements and properties are skipped.
//
// Binary files are parsed in place from a memory map: a million triangles take a few tens of
// milliseconds.
#pragma once

#include "core/math.h"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace rayproc::pbrt {

struct PlyMesh {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;          // empty, or one per position
    std::vector<Vec2> uvs;              // empty, or one per position
    std::vector<std::uint32_t> indices; // 3 per triangle
    std::size_t quads = 0;              // faces split into two triangles
    std::size_t polygons = 0;           // faces of more than four vertices, fanned
    std::size_t degenerate = 0;         // faces of fewer than three vertices, dropped
};

// Throws InputError "<path>: <problem>" for a missing, truncated or malformed file, an index
// out of range, or a file without vertices or faces.
PlyMesh readPly(const std::string& path);

// The same from bytes in memory; `path` only names the file in messages.
PlyMesh parsePly(std::string_view bytes, const std::string& path);

} // namespace rayproc::pbrt
