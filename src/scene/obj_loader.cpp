// OBJ to TriangleMesh: tinyobjloader parses and triangulates; we validate every index, merge
// all shapes and build one compact vertex array.
#include "scene/obj_loader.h"

#include "core/error.h"

#include <tiny_obj_loader.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string_view>
#include <unordered_map>
#include <vector>

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

// tinyobjloader reads what it can and makes up the rest: "v nan" and "v abc" become 0, a
// missing coordinate 0, an index beyond the int range wraps. So every statement rayproc uses is
// checked first, strictly, with its line number: numbers parse whole and are finite, vertices
// have their coordinates, face indices are non-zero integers that name an existing element.
class StrictObjCheck {
public:
    explicit StrictObjCheck(const std::string& path) : m_path(path) {}

    void line(std::string_view text, std::size_t number) {
        m_line = number;
        m_text = text;
        std::vector<std::string_view> t = tokens(text);
        if (t.empty() || t[0][0] == '#') return;
        if (t[0] == "v") {
            // x y z, x y z w, or x y z r g b (vertex colours, which rayproc ignores).
            if (t.size() != 4 && t.size() != 5 && t.size() != 7)
                error("a vertex (v) needs 3 coordinates (or x y z w, or x y z r g b), found " +
                      std::to_string(t.size() - 1) + " values");
            numbers(t, "vertex coordinate");
            ++m_positions;
        } else if (t[0] == "vn") {
            if (t.size() != 4)
                error("a normal (vn) needs 3 components, found " + std::to_string(t.size() - 1));
            numbers(t, "normal component");
            ++m_normals;
        } else if (t[0] == "vt") {
            if (t.size() < 2 || t.size() > 4)
                error("a texture coordinate (vt) needs 1 to 3 values, found " +
                      std::to_string(t.size() - 1));
            numbers(t, "texture coordinate");
            ++m_uvs;
        } else if (t[0] == "f") {
            if (t.size() < 4)
                error("a face (f) needs at least 3 corners, found " + std::to_string(t.size() - 1));
            for (std::size_t i = 1; i < t.size(); ++i) corner(t[i]);
        }
        // Other statements (o, g, s, usemtl, mtllib, l, p, ...) do not shape the mesh.
    }

private:
    static std::vector<std::string_view> tokens(std::string_view text) {
        std::vector<std::string_view> out;
        std::size_t i = 0;
        while (i < text.size()) {
            while (i < text.size() && (text[i] == ' ' || text[i] == '\t' || text[i] == '\r')) ++i;
            std::size_t start = i;
            while (i < text.size() && text[i] != ' ' && text[i] != '\t' && text[i] != '\r') ++i;
            if (i > start) out.push_back(text.substr(start, i - start));
        }
        return out;
    }

    [[noreturn]] void error(const std::string& problem) const {
        std::string shown(m_text.substr(0, 80));
        throw InputError(m_path + ":" + std::to_string(m_line) + ": " + problem + " in '" +
                         shown + (m_text.size() > 80 ? "...'" : "'"));
    }

    void numbers(const std::vector<std::string_view>& t, const char* what) const {
        for (std::size_t i = 1; i < t.size(); ++i) {
            std::string token(t[i]);
            char* end = nullptr;
            double v = std::strtod(token.c_str(), &end);
            if (end != token.c_str() + token.size())
                error(std::string("'") + token + "' is not a number (" + what + ")");
            // Underflow to zero or a denormal is harmless; overflow is not.
            if (!std::isfinite(v) || std::abs(v) > double(std::numeric_limits<float>::max()))
                error(std::string("'") + token + "' is not a finite single-precision number (" +
                      what + ")");
        }
    }

    // One index of a corner: a non-zero integer; negative counts back from the elements so far.
    void index(std::string_view text, std::size_t count, const char* element) const {
        std::string token(text);
        char* end = nullptr;
        errno = 0;
        long long v = std::strtoll(token.c_str(), &end, 10);
        if (token.empty() || end != token.c_str() + token.size())
            error(std::string("'") + token + "' is not an integer " + element + " index");
        if (errno == ERANGE || v == 0 || v > std::numeric_limits<int>::max() ||
            v < -std::numeric_limits<int>::max())
            error(std::string(element) + " index " + token +
                  " is out of range (indices count from 1, or back from -1)");
        // A positive index may name an element defined later in the file: checked after
        // parsing, against the final count; a negative one is relative to this line.
        if (v < 0 && std::size_t(-v) > count)
            error(std::string(element) + " index " + token + " reaches before the first " +
                  element + " (" + std::to_string(count) + " so far)");
    }

    void corner(std::string_view c) {
        std::size_t a = c.find('/');
        index(c.substr(0, a), m_positions, "vertex");
        if (a == std::string_view::npos) return;
        std::size_t b = c.find('/', a + 1);
        std::string_view uv = c.substr(a + 1, b == std::string_view::npos ? std::string_view::npos : b - a - 1);
        if (!uv.empty()) index(uv, m_uvs, "texture coordinate");
        if (b == std::string_view::npos) return;
        std::string_view n = c.substr(b + 1);
        if (n.empty() || n.find('/') != std::string_view::npos)
            error("the face corner '" + std::string(c) + "' is not v, v/vt, v//vn or v/vt/vn");
        index(n, m_normals, "normal");
    }

    const std::string& m_path;
    std::size_t m_line = 0;
    std::string_view m_text;
    std::size_t m_positions = 0, m_normals = 0, m_uvs = 0;
};

} // namespace

TriangleMesh loadObjMesh(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file) fail(path, "cannot open the OBJ file (missing or unreadable)");
    std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    if (file.bad()) fail(path, "cannot read the OBJ file");
    return parseObjMesh(std::move(text), path);
}

namespace {

// What tinyobjloader read: the attributes and the shapes' faces.
struct ObjData {
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
};

ObjData readWithTinyObj(std::string text, const std::string& path) {
    std::istringstream in(std::move(text));
    ObjData obj;
    std::vector<tinyobj::material_t> materials;
    std::string warn, err;
    // No material reader: "mtllib" lines are skipped, so a missing .mtl is no concern.
    bool ok = tinyobj::LoadObj(&obj.attrib, &obj.shapes, &materials, &warn, &err, &in, nullptr,
                               /*triangulate=*/true, /*default_vcols_fallback=*/false);
    if (!ok || !err.empty()) fail(path, "malformed OBJ file: " + trimmed(err.empty() ? warn : err));
    // tinyobjloader only warns about faces that name vertices the file lacks; for a renderer
    // they are broken geometry.
    if (warn.find("out of bounds") != std::string::npos ||
        warn.find("invalid vertex index") != std::string::npos)
        fail(path, "malformed OBJ file: " + trimmed(warn));
    return obj;
}

// Which attributes the mesh keeps, and its triangle count.
struct CornerUse {
    bool keepNormals, keepUvs;
    std::size_t faceCount = 0;
};

// Every corner's vertex exists and every position is finite; normals and uvs survive only if
// every corner of every face has a valid one (and every normal can shade).
CornerUse checkCorners(const ObjData& obj, const std::string& path) {
    const tinyobj::attrib_t& attrib = obj.attrib;
    const int numPositions = int(attrib.vertices.size() / 3);
    const int numNormals = int(attrib.normals.size() / 3);
    const int numUvs = int(attrib.texcoords.size() / 2);
    CornerUse use{numNormals > 0, numUvs > 0};
    for (const tinyobj::shape_t& s : obj.shapes) {
        std::size_t offset = 0;
        for (unsigned char fv : s.mesh.num_face_vertices) {
            if (fv == 3) ++use.faceCount;
            for (std::size_t c = 0; c < fv; ++c) {
                const tinyobj::index_t& idx = s.mesh.indices[offset + c];
                if (idx.vertex_index < 0 || idx.vertex_index >= numPositions) {
                    fail(path, "a face refers to vertex " + std::to_string(idx.vertex_index + 1) +
                                   ", but the file has " + std::to_string(numPositions) +
                                   " vertices");
                }
                use.keepNormals =
                    use.keepNormals && idx.normal_index >= 0 && idx.normal_index < numNormals;
                use.keepUvs = use.keepUvs && idx.texcoord_index >= 0 && idx.texcoord_index < numUvs;
            }
            offset += fv;
        }
    }
    if (use.faceCount == 0) fail(path, "the OBJ file has no faces");
    for (float x : attrib.vertices)
        if (!std::isfinite(x)) fail(path, "a vertex position is not a finite number");
    if (use.keepNormals) {
        // A zero or non-finite normal cannot shade; fall back to the geometric normal.
        for (int i = 0; i < numNormals && use.keepNormals; ++i) {
            Vec3 n{attrib.normals[3 * i], attrib.normals[3 * i + 1], attrib.normals[3 * i + 2]};
            use.keepNormals = isFinite(n) && lengthSquared(n) > 0;
        }
    }
    return use;
}

// The triangles, with one mesh vertex per distinct (position, normal, uv) corner.
TriangleMesh weldCorners(const ObjData& obj, const CornerUse& use) {
    const tinyobj::attrib_t& attrib = obj.attrib;
    TriangleMesh mesh;
    std::unordered_map<CornerKey, std::uint32_t, CornerKeyHash> vertexOf;
    mesh.indices.reserve(use.faceCount * 3);
    for (const tinyobj::shape_t& s : obj.shapes) {
        std::size_t offset = 0;
        for (unsigned char fv : s.mesh.num_face_vertices) {
            if (fv != 3) { // tinyobjloader leaves degenerate polygons as they are
                offset += fv;
                continue;
            }
            for (std::size_t c = 0; c < 3; ++c) {
                const tinyobj::index_t& idx = s.mesh.indices[offset + c];
                CornerKey key{idx.vertex_index, use.keepNormals ? idx.normal_index : -1,
                              use.keepUvs ? idx.texcoord_index : -1};
                auto [it, added] = vertexOf.try_emplace(key, std::uint32_t(mesh.positions.size()));
                if (added) {
                    const auto* p = &attrib.vertices[3 * std::size_t(key.position)];
                    mesh.positions.push_back({p[0], p[1], p[2]});
                    if (use.keepNormals) {
                        const auto* n = &attrib.normals[3 * std::size_t(key.normal)];
                        mesh.normals.push_back(normalize(Vec3{n[0], n[1], n[2]}));
                    }
                    if (use.keepUvs) {
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

} // namespace

TriangleMesh parseObjMesh(std::string text, const std::string& path) {
    StrictObjCheck check(path);
    std::size_t lineNumber = 0;
    for (std::size_t start = 0; start < text.size();) {
        std::size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        check.line(std::string_view(text).substr(start, end - start), ++lineNumber);
        start = end + 1;
    }
    const ObjData obj = readWithTinyObj(std::move(text), path);
    return weldCorners(obj, checkCorners(obj, path));
}

} // namespace rayproc
