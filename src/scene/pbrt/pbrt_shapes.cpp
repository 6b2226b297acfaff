#include "scene/pbrt/pbrt_shapes.h"

#include "core/error.h"
#include "scene/pbrt/ply_reader.h"

#include <algorithm>
#include <cmath>

namespace rayproc::pbrt {

namespace {

struct MeshInput {
    std::vector<Vec3> positions, normals;
    std::vector<Vec2> uvs;
    std::vector<std::uint32_t> indices;
};

std::vector<Vec3> readVec3s(const Param& p) {
    std::vector<Vec3> out(p.numbers.size() / 3);
    for (std::size_t i = 0; i < out.size(); ++i)
        out[i] = {float(p.numbers[3 * i]), float(p.numbers[3 * i + 1]),
                  float(p.numbers[3 * i + 2])};
    return out;
}

// P, N, uv and indices of trianglemesh / bilinearmesh / loopsubdiv, checked against each other.
MeshInput readMeshParams(const std::string& type, const ParamList& params, const ShapeContext& ctx,
                         std::size_t perFace) {
    MeshInput m;
    const Param* P = params.get("P", {"point3"});
    if (!P) failAt(ctx.loc, "Shape \"" + type + "\" needs \"point3 P\"");
    m.positions = readVec3s(*P);
    if (m.positions.size() > 0xffffffffull) failAt(P->loc, "too many vertices");
    std::size_t n = m.positions.size();

    const Param* idx = params.get("indices", {"integer"});
    if (idx) {
        if (idx->numbers.size() % perFace != 0)
            failAt(idx->loc, "\"indices\" of a " + type + " must come in groups of " +
                                 std::to_string(perFace) + ", got " +
                                 std::to_string(idx->numbers.size()));
        m.indices.reserve(idx->numbers.size());
        for (double v : idx->numbers) {
            if (v < 0 || v >= double(n))
                failAt(idx->loc, "index " + std::to_string(static_cast<long long>(v)) +
                                     " out of range: the mesh has " + std::to_string(n) +
                                     " vertices (\"P\")");
            m.indices.push_back(std::uint32_t(v));
        }
    } else if (n == perFace) {
        for (std::uint32_t i = 0; i < perFace; ++i) m.indices.push_back(i);
    } else {
        failAt(ctx.loc, "Shape \"" + type + "\" needs \"integer indices\"");
    }
    if (m.indices.empty()) failAt(idx ? idx->loc : ctx.loc, "the mesh has no faces");

    if (const Param* N = params.get("N", {"normal3"})) {
        if (N->size() != n)
            failAt(N->loc, "expected " + std::to_string(n) + " normals (one per vertex), got " +
                               std::to_string(N->size()));
        m.normals = readVec3s(*N);
    }
    const Param* uv = params.get("uv", {"point2", "float"});
    if (!uv) uv = params.get("st", {"point2", "float"}); // pbrt-v3
    if (uv) {
        if (uv->numbers.size() != 2 * n)
            failAt(uv->loc, "expected " + std::to_string(n) + " uvs (one per vertex), got " +
                                std::to_string(uv->numbers.size() / 2));
        m.uvs.resize(n);
        for (std::size_t i = 0; i < n; ++i)
            m.uvs[i] = {float(uv->numbers[2 * i]), float(uv->numbers[2 * i + 1])};
    }
    params.ignore({"S", "faceIndices"}); // tangents and Ptex face ids: nothing to use them for
    return m;
}

// Bakes the transform and orients the triangles as pbrt would, into `mesh`.
void finishMesh(MeshInput&& in, const ShapeContext& ctx, Warnings& warnings,
                TriangleMesh* mesh) {
    mesh->positions = std::move(in.positions);
    mesh->normals = std::move(in.normals);
    mesh->uvs = std::move(in.uvs);
    mesh->indices = std::move(in.indices);
    const Mat4& m = ctx.toWorld;
    if (!m.isIdentity()) {
        for (Vec3& p : mesh->positions) p = m.point(Vec3d(p)).toFloat();
        Mat4 inv;
        m.inverse(inv);
        for (Vec3& n : mesh->normals) // the inverse transpose keeps normals normal
            n = Vec3d(inv.m[0][0] * n.x + inv.m[1][0] * n.y + inv.m[2][0] * n.z,
                      inv.m[0][1] * n.x + inv.m[1][1] * n.y + inv.m[2][1] * n.z,
                      inv.m[0][2] * n.x + inv.m[1][2] * n.y + inv.m[2][2] * n.z)
                    .toFloat();
    }
    // Every number was finite when read, but a transform can still carry a point beyond a
    // float's range: geometry the renderer cannot place.
    for (const Vec3& p : mesh->positions)
        if (!isFinite(p))
            failAt(ctx.loc, "a mesh vertex is not finite after the transform (coordinates beyond "
                            "3.4e38)");
    for (Vec3& n : mesh->normals) {
        n = normalize(n);
        if (!isFinite(n) || lengthSquared(n) == 0) {
            warnings.add(ctx.loc, "mesh with zero-length normals: its normals are dropped");
            mesh->normals.clear();
            break;
        }
    }
    auto& idx = mesh->indices;
    const auto& P = mesh->positions;
    if (!mesh->normals.empty()) {
        // pbrt turns the geometric normal towards the shading normals.
        const auto& N = mesh->normals;
        for (std::size_t t = 0; t + 2 < idx.size(); t += 3) {
            Vec3 ng = cross(P[idx[t + 1]] - P[idx[t]], P[idx[t + 2]] - P[idx[t]]);
            if (dot(ng, N[idx[t]] + N[idx[t + 1]] + N[idx[t + 2]]) < 0)
                std::swap(idx[t + 1], idx[t + 2]);
        }
    } else if (ctx.reverseOrientation != (m.det3() < 0)) {
        for (std::size_t t = 0; t + 2 < idx.size(); t += 3) std::swap(idx[t + 1], idx[t + 2]);
    }
}

// A mesh shape; a quad is flagged (isQuadMesh).
Shape meshShape(std::shared_ptr<TriangleMesh> mesh) {
    Shape s;
    s.type = ShapeType::Mesh;
    s.isQuad = isQuadMesh(*mesh);
    s.mesh = std::move(mesh);
    return s;
}

Shape finishedMeshShape(MeshInput&& in, const ShapeContext& ctx, Warnings& warnings) {
    auto mesh = std::make_shared<TriangleMesh>();
    finishMesh(std::move(in), ctx, warnings, mesh.get());
    return meshShape(std::move(mesh));
}

// Bilinear patches (p00, p10, p01, p11) as the triangles (p00, p10, p11) and (p00, p11, p01);
// a lone patch becomes a quad whose corners run p00, p10, p11, p01.
MeshInput bilinearAsTriangles(MeshInput&& in) {
    static const std::uint32_t kCycle[4] = {0, 1, 3, 2};
    MeshInput out;
    if (in.positions.size() == 4 && in.indices.size() == 4 && in.indices[0] == 0 &&
        in.indices[1] == 1 && in.indices[2] == 2 && in.indices[3] == 3) {
        for (std::uint32_t k : kCycle) {
            out.positions.push_back(in.positions[k]);
            if (!in.normals.empty()) out.normals.push_back(in.normals[k]);
            if (!in.uvs.empty()) out.uvs.push_back(in.uvs[k]);
        }
        out.indices = {0, 1, 2, 0, 2, 3};
        return out;
    }
    out.positions = std::move(in.positions);
    out.normals = std::move(in.normals);
    out.uvs = std::move(in.uvs);
    for (std::size_t q = 0; q + 3 < in.indices.size(); q += 4) {
        const std::uint32_t* v = &in.indices[q];
        out.indices.insert(out.indices.end(), {v[0], v[1], v[3], v[0], v[3], v[2]});
    }
    return out;
}

// The linear part's uniform scale if it is a similarity (rotation, mirror, uniform scale).
bool similarityScale(const Mat4& m, double& s) {
    Vec3d c[3];
    for (int j = 0; j < 3; ++j) c[j] = {m.m[0][j], m.m[1][j], m.m[2][j]};
    double l = length(c[0]);
    const double tol = 1e-6 * l;
    if (!(l > 0) || std::fabs(length(c[1]) - l) > tol || std::fabs(length(c[2]) - l) > tol)
        return false;
    if (std::fabs(dot(c[0], c[1])) > tol * l || std::fabs(dot(c[0], c[2])) > tol * l ||
        std::fabs(dot(c[1], c[2])) > tol * l)
        return false;
    s = l;
    return true;
}

ShapeResult analytic(Shape s, const Vec3d& center, const Vec3d& normal, const ShapeContext& ctx) {
    ShapeResult r;
    double scale = 1;
    if (similarityScale(ctx.toWorld, scale)) {
        s.center = ctx.toWorld.point(center).toFloat();
        s.normal = normalize(ctx.toWorld.vector(normal)).toFloat();
        s.radius = float(s.radius * scale);
        s.frameX = normalize(ctx.toWorld.vector({1, 0, 0})).toFloat();
        s.frameY = normalize(ctx.toWorld.vector({0, 1, 0})).toFloat();
        s.frameZ = normalize(ctx.toWorld.vector({0, 0, 1})).toFloat();
    } else {
        s.center = center.toFloat();
        s.normal = normal.toFloat();
        r.grouped = true;
        r.groupTransform = ctx.toWorld.toAffine();
    }
    if (!isFinite(s.center) || !std::isfinite(s.radius))
        failAt(ctx.loc, "the shape's centre or radius is not finite after the transform");
    r.shapes.push_back(s);
    return r;
}

ShapeResult sphere(const ParamList& params, const ShapeContext& ctx, Warnings& warnings) {
    Shape s;
    s.type = ShapeType::Sphere;
    double radius = params.getFloat("radius", 1.0);
    if (!(radius > 0)) failAt(ctx.loc, "sphere radius must be positive");
    s.radius = float(radius);
    double zmin = params.getFloat("zmin", -radius), zmax = params.getFloat("zmax", radius);
    double phimax = params.getFloat("phimax", 360.0);
    if (zmin > -radius || zmax < radius || phimax < 360.0)
        warnings.add(ctx.loc, "partial spheres (zmin, zmax, phimax) are not supported; the "
                              "whole sphere is used");
    if (ctx.reverseOrientation && ctx.emissive)
        warnings.add(ctx.loc, "ReverseOrientation on an emissive sphere is not supported; it "
                              "emits outwards");
    return analytic(s, {0, 0, 0}, {0, 0, 1}, ctx);
}

ShapeResult disk(const ParamList& params, const ShapeContext& ctx, Warnings& warnings) {
    Shape s;
    s.type = ShapeType::Disk;
    double radius = params.getFloat("radius", 1.0);
    if (!(radius > 0)) failAt(ctx.loc, "disk radius must be positive");
    s.radius = float(radius);
    double height = params.getFloat("height", 0.0);
    if (params.getFloat("innerradius", 0.0) > 0)
        warnings.add(ctx.loc, "disk \"innerradius\" is not supported; the full disk is used");
    if (params.getFloat("phimax", 360.0) < 360.0)
        warnings.add(ctx.loc, "disk \"phimax\" is not supported; the full disk is used");
    // pbrt's disk faces +z in its own space.
    return analytic(s, {0, 0, height}, {0, 0, ctx.reverseOrientation ? -1.0 : 1.0}, ctx);
}

ShapeResult plyMesh(const ParamList& params, const ShapeContext& ctx, Warnings& warnings) {
    const Param* file = params.get("filename", {"string"});
    if (!file || file->strings.size() != 1)
        failAt(ctx.loc, "Shape \"plymesh\" needs \"string filename\"");
    const std::string& name = file->strings[0];
    if (name.size() > 3 && name.substr(name.size() - 3) == ".gz") {
        warnings.add(ctx.loc, "compressed PLY files (.ply.gz) are not supported; shape skipped");
        return {};
    }
    std::filesystem::path path = resolvePath(name, ctx.dir, ctx.mainDir);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        failAt(file->loc, "PLY file not found: " + path.string());
    params.ignore({"edgelength"}); // only meaningful with displacement
    auto mesh = std::make_shared<TriangleMesh>();
    auto read = [at = ctx, path = path.string(), fileLoc = file->loc,
                 target = mesh.get()](Warnings& out) {
        PlyMesh ply;
        try {
            ply = readPly(path);
        } catch (const InputError& e) {
            failAt(fileLoc, std::string("cannot read the PLY file: ") + e.what());
        }
        if (ply.polygons > 0)
            out.add(at.loc, "PLY faces of more than four vertices are split into triangle fans");
        if (ply.degenerate > 0)
            out.add(at.loc, "PLY faces of fewer than three vertices are dropped");
        MeshInput m{std::move(ply.positions), std::move(ply.normals), std::move(ply.uvs),
                    std::move(ply.indices)};
        finishMesh(std::move(m), at, out, target);
    };
    ShapeResult r;
    // An emitter's mesh is read now: "power" needs its area while the directive is read. A
    // mesh being read is empty, so not a quad until the builder joins the reads.
    r.deferred = ctx.loads && !ctx.emissive;
    if (r.deferred)
        ctx.loads->start(std::move(read));
    else
        read(warnings);
    r.shapes.push_back(meshShape(std::move(mesh)));
    return r;
}

} // namespace

std::filesystem::path resolvePath(const std::string& name, const std::filesystem::path& dir,
                                  const std::filesystem::path& mainDir) {
    std::filesystem::path p(name);
    if (p.is_absolute()) return p;
    std::error_code ec;
    std::filesystem::path near = (dir / p).lexically_normal();
    if (std::filesystem::exists(near, ec) || dir == mainDir) return near;
    std::filesystem::path fromMain = (mainDir / p).lexically_normal();
    return std::filesystem::exists(fromMain, ec) ? fromMain : near;
}

ShapeResult convertShape(const std::string& type, const ParamList& params, const ShapeContext& ctx,
                         Warnings& warnings) {
    bool known = type == "trianglemesh" || type == "plymesh" || type == "bilinearmesh" ||
                 type == "loopsubdiv" || type == "sphere" || type == "disk";
    if (!known) {
        warnings.add(ctx.loc, "Shape \"" + type + "\" is not supported; skipped");
        for (const Param& p : params.all()) p.used = true; // the shape is reported, not these
        return {};
    }
    if (ctx.toWorld.det3() == 0 || !ctx.toWorld.isAffine()) {
        warnings.add(ctx.loc, "shape under a singular or projective transform; skipped");
        for (const Param& p : params.all()) p.used = true;
        return {};
    }
    if (type == "sphere") return sphere(params, ctx, warnings);
    if (type == "disk") return disk(params, ctx, warnings);
    if (type == "plymesh") return plyMesh(params, ctx, warnings);

    MeshInput m = readMeshParams(type, params, ctx, type == "bilinearmesh" ? 4 : 3);
    if (type == "bilinearmesh") m = bilinearAsTriangles(std::move(m));
    if (type == "loopsubdiv") {
        params.ignore({"levels"});
        warnings.add(ctx.loc, "Shape \"loopsubdiv\" is rendered as its control mesh (not "
                              "subdivided)");
    }
    ShapeResult r;
    r.shapes.push_back(finishedMeshShape(std::move(m), ctx, warnings));
    return r;
}

bool isQuadMesh(const TriangleMesh& mesh) {
    static const std::uint32_t kQuad[6] = {0, 1, 2, 0, 2, 3};
    return mesh.positions.size() == 4 && mesh.indices.size() == 6 &&
           std::equal(mesh.indices.begin(), mesh.indices.end(), kQuad);
}

} // namespace rayproc::pbrt
