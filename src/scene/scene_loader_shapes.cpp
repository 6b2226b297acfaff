// Scene loading: the geometry of shape nodes. Inline meshes, OBJ files, quads and rectangles
// (two-triangle meshes flagged isQuad), exact spheres and disks, and a procedural grid that
// makes million-triangle scenes without million-triangle files.
#include "core/error.h"
#include "scene/obj_loader.h"
#include "scene/scene_loader_detail.h"

#include <nlohmann/json.hpp>

#include <cmath>

namespace rayproc::scene_json {

namespace {

constexpr long long kMaxGridSegments = 8192;
constexpr long long kMaxGridCells = 1LL << 23; // 16.7 M triangles

// Reads one vertex index and checks it against the mesh.
std::uint32_t readIndex(const JsonRef& e, std::size_t positionCount) {
    if (e.isArray()) e.fail("expected an integer (a flat index list cannot contain triangles)");
    long long i = e.integer(-(1LL << 53), 1LL << 53);
    if (i < 0 || i >= static_cast<long long>(positionCount)) {
        e.fail("index " + std::to_string(i) + " out of range: the mesh has " +
               std::to_string(positionCount) + " positions (valid indices 0 to " +
               std::to_string(positionCount - 1) + ")");
    }
    return std::uint32_t(i);
}

// "indices": either [[a,b,c], ...] or a flat [a,b,c, a,b,c, ...].
void readIndices(const JsonRef& idx, TriangleMesh& mesh) {
    std::size_t n = idx.arraySize();
    if (n == 0) idx.fail("mesh has no triangles (empty index list)");
    if (idx[std::size_t(0)].isArray()) {
        for (std::size_t t = 0; t < n; ++t) {
            JsonRef tri = idx[t];
            if (!tri.isArray() || tri.arraySize() != 3)
                tri.fail("expected an array of 3 integers (one triangle)");
            for (std::size_t k = 0; k < 3; ++k)
                mesh.indices.push_back(readIndex(tri[k], mesh.positions.size()));
        }
    } else {
        if (n % 3 != 0) {
            idx.fail("triangle index count " + std::to_string(n) + " is not a multiple of 3");
        }
        for (std::size_t k = 0; k < n; ++k)
            mesh.indices.push_back(readIndex(idx[k], mesh.positions.size()));
    }
}

std::shared_ptr<TriangleMesh> parseMesh(const JsonRef& v) {
    auto mesh = std::make_shared<TriangleMesh>();
    JsonRef pos = v["positions"];
    std::size_t n = pos.arraySize();
    if (n == 0) pos.fail("mesh has no positions");
    if (n > 0xffffffffull) pos.fail("too many positions for 32-bit indices");
    for (std::size_t i = 0; i < n; ++i) mesh->positions.push_back(pos[i].vec3());
    readIndices(v["indices"], *mesh);
    if (v.has("normals")) {
        JsonRef nrm = v["normals"];
        if (nrm.arraySize() != n) {
            nrm.fail("expected " + std::to_string(n) + " normals (one per position), got " +
                     std::to_string(nrm.arraySize()));
        }
        for (std::size_t i = 0; i < n; ++i) mesh->normals.push_back(nrm[i].direction());
    }
    if (v.has("uvs")) {
        JsonRef uv = v["uvs"];
        if (uv.arraySize() != n) {
            uv.fail("expected " + std::to_string(n) + " uvs (one per position), got " +
                    std::to_string(uv.arraySize()));
        }
        for (std::size_t i = 0; i < n; ++i) mesh->uvs.push_back(uv[i].vec2());
    }
    return mesh;
}

// A planar quad c0 c1 c2 c3 as triangles (0,1,2), (0,2,3); its front is the side of
// cross(c1 - c0, c2 - c0).
std::shared_ptr<TriangleMesh> quadMesh(const Vec3 c[4], const JsonRef& where) {
    auto area = [](Vec3 a, Vec3 b, Vec3 d) {
        Vec3 e1 = b - a, e2 = d - a;
        float scale = length(e1) * length(e2);
        return scale > 0 && length(cross(e1, e2)) > 1e-7f * scale;
    };
    if (!area(c[0], c[1], c[2]) || !area(c[0], c[2], c[3]))
        where.fail("quad has zero area (coincident or collinear corners)");
    auto mesh = std::make_shared<TriangleMesh>();
    mesh->positions.assign(c, c + 4);
    mesh->indices = {0, 1, 2, 0, 2, 3};
    return mesh;
}

std::shared_ptr<TriangleMesh> parseQuad(const JsonRef& v) {
    JsonRef cs = v["corners"];
    if (!cs.isArray() || cs.arraySize() != 4)
        cs.fail("expected an array of 4 corners, each an array of 3 numbers");
    Vec3 c[4];
    for (std::size_t i = 0; i < 4; ++i) c[i] = cs[i].vec3();
    return quadMesh(c, cs);
}

// A w x h rectangle around `center` facing `normal`. The height runs along `up` (projected
// into the plane); by default up is world +y, or -z for a rectangle facing up or down, so a
// floor's width runs along +x.
std::shared_ptr<TriangleMesh> parseRectangle(const JsonRef& v) {
    Vec3 center = v.has("center") ? v["center"].vec3() : Vec3(0.0f);
    JsonRef sz = v["size"];
    Vec2 size = sz.vec2();
    if (size.x <= 0) sz[std::size_t(0)].fail("width must be positive");
    if (size.y <= 0) sz[1].fail("height must be positive");
    Vec3 n = v.has("normal") ? v["normal"].direction() : Vec3(0, 1, 0);
    Vec3 up = std::fabs(n.y) > 0.999f ? Vec3(0, 0, -1) : Vec3(0, 1, 0);
    if (v.has("up")) up = v["up"].direction();
    Vec3 along = up - n * dot(up, n);
    if (length(along) < 1e-6f) v["up"].fail("up is parallel to the normal");
    Vec3 vAxis = normalize(along) * (0.5f * size.y);
    Vec3 uAxis = normalize(cross(along, n)) * (0.5f * size.x);
    Vec3 c[4] = {center - uAxis - vAxis, center + uAxis - vAxis, center + uAxis + vAxis,
                 center - uAxis + vAxis};
    return quadMesh(c, v);
}

// A grid of nx x ny cells in the xz-plane, centred on the origin, facing +y. "waves" displaces
// it to y = a sin(2 pi f x) sin(2 pi f z) with analytic normals.
std::shared_ptr<TriangleMesh> parseGrid(const JsonRef& v) {
    JsonRef sz = v["size"];
    Vec2 size = sz.vec2();
    if (size.x <= 0) sz[std::size_t(0)].fail("width must be positive");
    if (size.y <= 0) sz[1].fail("depth must be positive");
    JsonRef seg = v["segments"];
    if (!seg.isArray() || seg.arraySize() != 2) seg.fail("expected an array of 2 integers");
    long long nx = seg[std::size_t(0)].integer(1, kMaxGridSegments);
    long long ny = seg[1].integer(1, kMaxGridSegments);
    if (nx * ny > kMaxGridCells) {
        seg.fail("too many cells: " + std::to_string(nx * ny) + " exceeds the limit of " +
                 std::to_string(kMaxGridCells));
    }
    std::string displace = v.has("displace") ? v["displace"].string() : "none";
    if (displace != "none" && displace != "waves")
        v["displace"].fail("unknown displacement \"" + displace + "\"; known: none, waves");
    bool waves = displace == "waves";
    for (const char* key : {"amplitude", "frequency"}) {
        if (!waves && v.has(key))
            v.child(key).fail(std::string(key) + " applies only with \"displace\": \"waves\"");
    }
    float amplitude = v.has("amplitude") ? v["amplitude"].number() : 0.1f;
    float frequency = v.has("frequency") ? v["frequency"].positive() : 1.0f;

    auto mesh = std::make_shared<TriangleMesh>();
    std::size_t cols = std::size_t(nx) + 1, rows = std::size_t(ny) + 1;
    mesh->positions.reserve(cols * rows);
    mesh->uvs.reserve(cols * rows);
    if (waves) mesh->normals.reserve(cols * rows);
    const double k = 2.0 * 3.14159265358979323846 * frequency;
    for (std::size_t j = 0; j < rows; ++j) {
        double z = (double(j) / double(ny) - 0.5) * size.y;
        for (std::size_t i = 0; i < cols; ++i) {
            double x = (double(i) / double(nx) - 0.5) * size.x;
            double y = 0;
            if (waves) {
                double sx = std::sin(k * x), cx = std::cos(k * x);
                double sz2 = std::sin(k * z), cz = std::cos(k * z);
                y = amplitude * sx * sz2;
                double dydx = amplitude * k * cx * sz2, dydz = amplitude * k * sx * cz;
                mesh->normals.push_back(normalize(Vec3(float(-dydx), 1.0f, float(-dydz))));
            }
            mesh->positions.push_back({float(x), float(y), float(z)});
            mesh->uvs.push_back({float(i) / float(nx), float(j) / float(ny)});
        }
    }
    // Cell (i, j) with corners a = (i, j), b = (i+1, j), c = (i, j+1), d = (i+1, j+1): the
    // triangles (a, c, d) and (a, d, b) face +y.
    mesh->indices.reserve(std::size_t(nx * ny) * 6);
    for (std::size_t j = 0; j < std::size_t(ny); ++j) {
        for (std::size_t i = 0; i < std::size_t(nx); ++i) {
            auto a = std::uint32_t(j * cols + i), b = a + 1;
            auto c = std::uint32_t(a + cols), d = c + 1;
            mesh->indices.insert(mesh->indices.end(), {a, c, d, a, d, b});
        }
    }
    return mesh;
}

std::shared_ptr<const TriangleMesh>
parseObj(const JsonRef& v, const std::filesystem::path& sceneDir,
         std::map<std::string, std::shared_ptr<const TriangleMesh>>& cache) {
    JsonRef file = v["file"];
    std::filesystem::path p(file.nonEmptyString());
    if (p.is_relative()) p = sceneDir / p;
    std::error_code ec;
    std::filesystem::path absolute = std::filesystem::absolute(p, ec);
    std::string resolved = (ec ? p : absolute).lexically_normal().string();
    if (auto it = cache.find(resolved); it != cache.end()) return it->second;

    if (!std::filesystem::is_regular_file(resolved, ec))
        file.fail("OBJ file not found: " + resolved);
    try {
        auto mesh = std::make_shared<const TriangleMesh>(loadObjMesh(resolved));
        cache[resolved] = mesh;
        return mesh;
    } catch (const InputError& e) {
        file.fail(std::string("cannot load the OBJ file: ") + e.what());
    }
}

} // namespace

std::vector<std::string> shapeTypeNames() {
    return {"mesh", "obj", "quad", "rectangle", "sphere", "disk", "grid"};
}

std::vector<std::string_view> shapeKeys(std::string_view type) {
    if (type == "mesh") return {"positions", "indices", "normals", "uvs"};
    if (type == "obj") return {"file"};
    if (type == "quad") return {"corners"};
    if (type == "rectangle") return {"center", "size", "normal", "up"};
    if (type == "sphere") return {"center", "radius"};
    if (type == "disk") return {"center", "normal", "radius"};
    if (type == "grid") return {"size", "segments", "displace", "amplitude", "frequency"};
    return {};
}

void parseShapeGeometry(const JsonRef& v, std::string_view type, Shape& shape,
                        const std::filesystem::path& sceneDir,
                        std::map<std::string, std::shared_ptr<const TriangleMesh>>& objCache) {
    shape.type = ShapeType::Mesh;
    if (type == "mesh") {
        shape.mesh = parseMesh(v);
    } else if (type == "obj") {
        shape.mesh = parseObj(v, sceneDir, objCache);
    } else if (type == "quad") {
        shape.mesh = parseQuad(v);
        shape.isQuad = true;
    } else if (type == "rectangle") {
        shape.mesh = parseRectangle(v);
        shape.isQuad = true;
    } else if (type == "grid") {
        shape.mesh = parseGrid(v);
    } else if (type == "sphere") {
        shape.type = ShapeType::Sphere;
        if (v.has("center")) shape.center = v["center"].vec3();
        shape.radius = v["radius"].positive();
    } else if (type == "disk") {
        shape.type = ShapeType::Disk;
        if (v.has("center")) shape.center = v["center"].vec3();
        if (v.has("normal")) shape.normal = v["normal"].direction();
        shape.radius = v["radius"].positive();
        // (u, v) about the normal (Shape::frameZ), phi from an axis orthonormalBasis picks.
        shape.frameZ = normalize(shape.normal);
        orthonormalBasis(shape.frameZ, shape.frameX, shape.frameY);
    } else {
        v.fail("not a shape type: \"" + std::string(type) + "\"");
    }
}

} // namespace rayproc::scene_json
