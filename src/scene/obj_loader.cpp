// OBJ to TriangleMesh: tinyobjloader parses and triangulates; we validate every index, merge
// all shapes and build one compact vertex array.
#include "scene/obj_loader.h"

#include "core/error.h"

#include <tiny_obj_loader.h>

#include <cmath>
#include <fstream>
#include <unordered_map>

namespace rayproc {

namespace {

// A mesh vertex is a distinct (position, normal, uv) triple of the file's separate arrays;
// unused attributes are -1.
struct CornerKey {
    int position, normal, uv;
    bool operator==(const CornerKey& o) const {
        return position == o.position && normal == o.normal && uv == o.uv;
    }
};

struct CornerKeyHash {
    std::size_t operator()(const CornerKey& k) const {
        std::uint64_t h = std::uint32_t(k.position);
        h = h * 0x9E3779B97F4A7C15ull ^ std::uint32_t(k.normal);
        h = h * 0x9E3779B97F4A7C15ull ^ std::uint32_t(k.uv);
        return std::size_t(h ^ (h >> 29));
    }
};

std::string trimmed(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    for (char& c : s)
        if (c == '\n') c = ' ';
    return s;
}

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
    throw InputError(path + ": " + problem);
}

} // namespace

TriangleMesh loadObjMesh(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, "cannot open the OBJ file (missing or unreadable)");

    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
    std::string warn, err;
    // No material reader: "mtllib" lines are skipped, so a missing .mtl is no concern.
    bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &in, nullptr,
                               /*triangulate=*/true, /*default_vcols_fallback=*/false);
    if (!ok || !err.empty()) fail(path, "malformed OBJ file: " + trimmed(err.empty() ? warn : err));
    // tinyobjloader only warns about faces that name vertices the file lacks; for a renderer
    // they are broken geometry.
    if (warn.find("out of bounds") != std::string::npos ||
        warn.find("invalid vertex index") != std::string::npos)
        fail(path, "malformed OBJ file: " + trimmed(warn));

    const int numPositions = int(attrib.vertices.size() / 3);
    const int numNormals = int(attrib.normals.size() / 3);
    const int numUvs = int(attrib.texcoords.size() / 2);

    // Normals and uvs survive only if every corner of every face has a valid one.
    bool keepNormals = numNormals > 0, keepUvs = numUvs > 0;
    std::size_t faceCount = 0;
    for (const tinyobj::shape_t& s : shapes) {
        std::size_t offset = 0;
        for (unsigned char fv : s.mesh.num_face_vertices) {
            if (fv == 3) ++faceCount;
            for (std::size_t c = 0; c < fv; ++c) {
                const tinyobj::index_t& idx = s.mesh.indices[offset + c];
                if (idx.vertex_index < 0 || idx.vertex_index >= numPositions) {
                    fail(path, "a face refers to vertex " + std::to_string(idx.vertex_index + 1) +
                                   ", but the file has " + std::to_string(numPositions) +
                                   " vertices");
                }
                keepNormals = keepNormals && idx.normal_index >= 0 && idx.normal_index < numNormals;
                keepUvs = keepUvs && idx.texcoord_index >= 0 && idx.texcoord_index < numUvs;
            }
            offset += fv;
        }
    }
    if (faceCount == 0) fail(path, "the OBJ file has no faces");
    for (float x : attrib.vertices)
        if (!std::isfinite(x)) fail(path, "a vertex position is not a finite number");
    if (keepNormals) {
        // A zero or non-finite normal cannot shade; fall back to the geometric normal.
        for (int i = 0; i < numNormals && keepNormals; ++i) {
            Vec3 n{attrib.normals[3 * i], attrib.normals[3 * i + 1], attrib.normals[3 * i + 2]};
            keepNormals = isFinite(n) && lengthSquared(n) > 0;
        }
    }

    TriangleMesh mesh;
    std::unordered_map<CornerKey, std::uint32_t, CornerKeyHash> vertexOf;
    mesh.indices.reserve(faceCount * 3);
    for (const tinyobj::shape_t& s : shapes) {
        std::size_t offset = 0;
        for (unsigned char fv : s.mesh.num_face_vertices) {
            if (fv != 3) { // tinyobjloader leaves degenerate polygons as they are
                offset += fv;
                continue;
            }
            for (std::size_t c = 0; c < 3; ++c) {
                const tinyobj::index_t& idx = s.mesh.indices[offset + c];
                CornerKey key{idx.vertex_index, keepNormals ? idx.normal_index : -1,
                              keepUvs ? idx.texcoord_index : -1};
                auto [it, added] = vertexOf.try_emplace(key, std::uint32_t(mesh.positions.size()));
                if (added) {
                    const auto* p = &attrib.vertices[3 * std::size_t(key.position)];
                    mesh.positions.push_back({p[0], p[1], p[2]});
                    if (keepNormals) {
                        const auto* n = &attrib.normals[3 * std::size_t(key.normal)];
                        mesh.normals.push_back(normalize(Vec3{n[0], n[1], n[2]}));
                    }
                    if (keepUvs) {
                        const auto* t = &attrib.texcoords[2 * std::size_t(key.uv)];
                        mesh.uvs.push_back({t[0], t[1]});
                    }
                }
                mesh.indices.push_back(it->second);
            }
            offset += 3;
        }
    }
    return mesh;
}

} // namespace rayproc
