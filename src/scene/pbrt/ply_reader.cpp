#include "scene/pbrt/ply_reader.h"

#include "core/error.h"
#include "scene/pbrt/mapped_file.h"
#include "scene/pbrt/pbrt_params.h"
#include "scene/pbrt/ply_header.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace rayproc::pbrt {

using namespace ply;

namespace {

// Where a vertex property goes: x y z nx ny nz u v, or nowhere.
enum Slot { kX, kY, kZ, kNx, kNy, kNz, kU, kV, kSlots, kSkip = -1 };

int vertexSlot(const std::string& n) {
    if (n == "x") return kX;
    if (n == "y") return kY;
    if (n == "z") return kZ;
    if (n == "nx") return kNx;
    if (n == "ny") return kNy;
    if (n == "nz") return kNz;
    if (n == "u" || n == "s" || n == "texture_u" || n == "texture_s") return kU;
    if (n == "v" || n == "t" || n == "texture_v" || n == "texture_t") return kV;
    return kSkip;
}

} // namespace

// Binary and ASCII element data, read by a cursor that converts each value to double.
class PlyCursor {
public:
    PlyCursor(std::string_view bytes, std::size_t pos, Format f, const std::string& path)
        : m_p(bytes.data() + pos), m_end(bytes.data() + bytes.size()), m_format(f), m_path(path) {}

    double read(Type t) {
        if (m_format == Format::Ascii) return readAscii();
        std::size_t n = typeSize(t);
        if (std::size_t(m_end - m_p) < n) fail(m_path, "the file ends in the middle of the data");
        unsigned char b[8];
        std::memcpy(b, m_p, n);
        m_p += n;
        if (m_format == Format::BinaryBig)
            for (std::size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
        return convert(b, t);
    }

    static double convert(const unsigned char* b, Type t) {
        switch (t) {
        case Type::Int8:
            return double(static_cast<std::int8_t>(b[0]));
        case Type::Uint8:
            return double(b[0]);
        case Type::Int16: {
            std::int16_t v;
            std::memcpy(&v, b, 2);
            return v;
        }
        case Type::Uint16: {
            std::uint16_t v;
            std::memcpy(&v, b, 2);
            return v;
        }
        case Type::Int32: {
            std::int32_t v;
            std::memcpy(&v, b, 4);
            return v;
        }
        case Type::Uint32: {
            std::uint32_t v;
            std::memcpy(&v, b, 4);
            return v;
        }
        case Type::Float32: {
            float v;
            std::memcpy(&v, b, 4);
            return v;
        }
        case Type::Float64: {
            double v;
            std::memcpy(&v, b, 8);
            return v;
        }
        }
        return 0;
    }

    // The length of a list: a count the rest of the file can hold (each value takes at least one
    // byte in binary and two, a digit and a separator, in ASCII), so that a corrupt count fails
    // here instead of allocating or looping for billions of values.
    // `element` and `row` only name the place in messages.
    std::size_t listLength(Type countType, Type valueType, const std::string& element,
                           std::size_t row) {
        double n = read(countType);
        auto where = [&] { return element + " " + std::to_string(row); };
        std::size_t minBytes = m_format == Format::Ascii ? 2 : typeSize(valueType);
        if (!(n >= 0) || n != std::floor(n))
            fail(m_path, where() + ": list length " + formatCount(n) + " is not a count");
        if (n > double(left() / minBytes) + 1)
            fail(m_path, where() + ": a list of " + formatCount(n) +
                             " values, more than the file holds");
        return std::size_t(n);
    }

    const char* raw() const { return m_p; }
    std::size_t left() const { return std::size_t(m_end - m_p); }
    void advance(std::size_t n) { m_p += n; }

private:
    static std::string formatCount(double n) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.0f", n);
        return buf;
    }

    double readAscii() {
        while (m_p < m_end && (*m_p == ' ' || *m_p == '\n' || *m_p == '\r' || *m_p == '\t')) ++m_p;
        const char* start = m_p;
        while (m_p < m_end && !(*m_p == ' ' || *m_p == '\n' || *m_p == '\r' || *m_p == '\t')) ++m_p;
        if (start == m_p) fail(m_path, "the file ends in the middle of the data");
        double v = 0;
        if (!parseNumber(std::string_view(start, std::size_t(m_p - start)), v))
            fail(m_path,
                 quote(std::string_view(start, std::size_t(m_p - start))) + " is not a number");
        return v;
    }

    const char* m_p;
    const char* m_end;
    Format m_format;
    const std::string& m_path;
};

namespace {

void readVertices(PlyCursor& cur, Element& e, Format format, PlyMesh& mesh,
                  const std::string& path) {
    bool has[kSlots] = {};
    for (Property& p : e.props) {
        p.slot = p.isList ? kSkip : vertexSlot(p.name);
        if (p.slot != kSkip) has[p.slot] = true;
    }
    if (!has[kX] || !has[kY] || !has[kZ]) fail(path, "the vertex element has no x, y and z");
    bool normals = has[kNx] && has[kNy] && has[kNz];
    bool uvs = has[kU] && has[kV];
    mesh.positions.resize(e.count);
    if (normals) mesh.normals.resize(e.count);
    if (uvs) mesh.uvs.resize(e.count);

    // Fixed-size binary rows: every value sits at a known offset.
    bool fixed = format != Format::Ascii && e.fixedSize();
    bool allFloat = true;
    const bool swap = format == Format::BinaryBig;
    std::size_t rowSize = 0;
    std::vector<const Property*> wanted;
    for (Property& p : e.props) {
        p.offset = rowSize;
        rowSize += typeSize(p.type);
        if (p.slot != kSkip) wanted.push_back(&p);
        if (p.slot != kSkip && p.type != Type::Float32) allFloat = false;
    }
    if (fixed && cur.left() / rowSize < e.count)
        fail(path, "the file ends in the middle of the vertex data");
    double v[kSlots] = {};
    for (std::size_t i = 0; i < e.count; ++i) {
        if (fixed && allFloat) { // the usual layout: floats, copied as they are
            const char* row = cur.raw();
            for (const Property* p : wanted) {
                std::uint32_t bits;
                std::memcpy(&bits, row + p->offset, 4);
                if (swap) bits = __builtin_bswap32(bits);
                float f;
                std::memcpy(&f, &bits, 4);
                v[p->slot] = f;
            }
            cur.advance(rowSize);
        } else if (fixed) {
            const auto* row = reinterpret_cast<const unsigned char*>(cur.raw());
            for (const Property* p : wanted) {
                unsigned char b[8];
                std::size_t n = typeSize(p->type);
                std::memcpy(b, row + p->offset, n);
                if (format == Format::BinaryBig)
                    for (std::size_t k = 0; k < n / 2; ++k) std::swap(b[k], b[n - 1 - k]);
                v[p->slot] = PlyCursor::convert(b, p->type);
            }
            cur.advance(rowSize);
        } else {
            for (const Property& p : e.props) {
                if (p.isList) {
                    std::size_t n = cur.listLength(p.countType, p.type, e.name, i);
                    for (std::size_t k = 0; k < n; ++k) cur.read(p.type);
                    continue;
                }
                double x = cur.read(p.type);
                if (p.slot != kSkip) v[p.slot] = x;
            }
        }
        // NaN or beyond a float's range (binary data can hold anything): broken geometry.
        for (int s = kX; s <= kZ; ++s)
            if (!std::isfinite(v[s]) || std::fabs(v[s]) > 3.4028234663852886e38)
                fail(path, "vertex " + std::to_string(i) + ": position is not a finite number");
        mesh.positions[i] = {float(v[kX]), float(v[kY]), float(v[kZ])};
        if (normals) mesh.normals[i] = {float(v[kNx]), float(v[kNy]), float(v[kNz])};
        if (uvs) mesh.uvs[i] = {float(v[kU]), float(v[kV])};
    }
}

// Collects triangles; the index array is sized up front (one triangle per face) and grows only
// for quads and larger polygons.
class TriangleSink {
public:
    TriangleSink(PlyMesh& mesh, std::size_t faces, const std::string& path)
        : m_mesh(mesh), m_count(mesh.positions.size()), m_path(path) {
        m_mesh.indices.resize(3 * faces);
    }
    ~TriangleSink() { m_mesh.indices.resize(m_used); }

    void add(const std::uint32_t* idx, std::size_t n, std::size_t face) {
        for (std::size_t k = 0; k < n; ++k) {
            if (idx[k] >= m_count)
                fail(m_path, "face " + std::to_string(face) + ": vertex index " +
                                 std::to_string(idx[k]) + " out of range (the file has " +
                                 std::to_string(m_count) + " vertices)");
        }
        if (n < 3) {
            ++m_mesh.degenerate;
            return;
        }
        if (n == 4) ++m_mesh.quads;
        if (n > 4) ++m_mesh.polygons;
        std::size_t need = m_used + 3 * (n - 2);
        if (need > m_mesh.indices.size()) m_mesh.indices.resize(std::max(need, 2 * m_used));
        std::uint32_t* out = m_mesh.indices.data() + m_used;
        for (std::size_t k = 1; k + 1 < n; ++k, out += 3) {
            out[0] = idx[0];
            out[1] = idx[k];
            out[2] = idx[k + 1];
        }
        m_used = need;
    }

private:
    PlyMesh& m_mesh;
    std::size_t m_count;
    const std::string& m_path;
    std::size_t m_used = 0;
};

void readFaces(PlyCursor& cur, const Element& e, Format format, PlyMesh& mesh,
               const std::string& path) {
    const Property* list = nullptr;
    for (const Property& p : e.props)
        if (p.isList && (p.name == "vertex_indices" || p.name == "vertex_index")) list = &p;
    if (!list) fail(path, "the face element has no vertex_indices list");
    TriangleSink sink(mesh, e.count, path);

    // The common layout, "property list uchar int vertex_indices" and nothing else, in
    // binary: read straight from the bytes.
    if (format != Format::Ascii && e.props.size() == 1 && list->countType == Type::Uint8 &&
        (list->type == Type::Int32 || list->type == Type::Uint32)) {
        bool swap = format == Format::BinaryBig;
        std::uint32_t idx[256];
        for (std::size_t f = 0; f < e.count; ++f) {
            if (cur.left() < 1) fail(path, "the file ends in the middle of the face data");
            auto n = std::size_t(static_cast<unsigned char>(*cur.raw()));
            if (cur.left() < 1 + 4 * n) fail(path, "the file ends in the middle of the face data");
            if (n == 3)
                std::memcpy(idx, cur.raw() + 1, 12); // fixed sizes copy fastest
            else if (n == 4)
                std::memcpy(idx, cur.raw() + 1, 16);
            else
                std::memcpy(idx, cur.raw() + 1, 4 * n);
            if (swap)
                for (std::size_t k = 0; k < n; ++k) idx[k] = __builtin_bswap32(idx[k]);
            cur.advance(1 + 4 * n);
            sink.add(idx, n, f);
        }
        return;
    }
    std::vector<std::uint32_t> idx;
    for (std::size_t f = 0; f < e.count; ++f) {
        for (const Property& p : e.props) {
            if (!p.isList) {
                cur.read(p.type);
                continue;
            }
            std::size_t n = cur.listLength(p.countType, p.type, e.name, f);
            if (&p != list) {
                for (std::size_t k = 0; k < n; ++k) cur.read(p.type);
                continue;
            }
            idx.resize(n);
            for (std::size_t k = 0; k < idx.size(); ++k) {
                double x = cur.read(p.type);
                if (x < 0 || x > 4294967295.0)
                    fail(path, "face " + std::to_string(f) + ": vertex index " +
                                   std::to_string(static_cast<long long>(x)) + " out of range");
                idx[k] = std::uint32_t(x);
            }
        }
        sink.add(idx.data(), idx.size(), f);
    }
}

void skipElement(PlyCursor& cur, const Element& e) {
    for (std::size_t i = 0; i < e.count; ++i) {
        for (const Property& p : e.props) {
            std::size_t n = p.isList ? cur.listLength(p.countType, p.type, e.name, i) : 1;
            for (std::size_t k = 0; k < n; ++k) cur.read(p.type);
        }
    }
}

} // namespace

// The fewest bytes a row of `e` can take: a header cannot promise more rows than the file holds
// (nor make the reader allocate for them).
void checkCount(const Element& e, Format format, std::size_t bytesLeft, const std::string& path) {
    // Rows without properties hold no data, so nothing bounds their count: refuse them rather
    // than loop over 10^18 empty rows.
    if (e.props.empty() && e.count > 0)
        fail(path, "element \"" + e.name + "\" has " + std::to_string(e.count) +
                       " rows but no properties");
    std::size_t minRow = 0;
    for (const Property& p : e.props)
        minRow += format == Format::Ascii ? 2 : typeSize(p.isList ? p.countType : p.type);
    if (minRow > 0 && e.count > bytesLeft / minRow)
        fail(path, "the header promises " + std::to_string(e.count) + " " + e.name +
                       " rows, more than the file holds");
}

PlyMesh parsePly(std::string_view bytes, const std::string& path) {
    Format format = Format::Ascii;
    std::vector<Element> elements;
    std::size_t pos = parseHeader(bytes, path, format, elements);
    for (const Element& e : elements) checkCount(e, format, bytes.size() - pos, path);
    PlyCursor cur(bytes, pos, format, path);
    PlyMesh mesh;
    bool sawVertices = false, sawFaces = false;
    for (Element& e : elements) {
        if (e.name == "vertex" && !sawVertices) {
            readVertices(cur, e, format, mesh, path);
            sawVertices = true;
        } else if (e.name == "face" && !sawFaces) {
            if (!sawVertices) fail(path, "faces come before the vertices");
            readFaces(cur, e, format, mesh, path);
            sawFaces = true;
        } else {
            skipElement(cur, e);
        }
    }
    if (mesh.positions.empty()) fail(path, "the file has no vertices");
    if (mesh.indices.empty()) fail(path, "the file has no faces");
    return mesh;
}

PlyMesh readPly(const std::string& path) {
    MappedFile file(path);
    return parsePly(file.data(), path);
}

} // namespace rayproc::pbrt
