// Helpers of the pbrt importer tests: scene snippets written to a per-process temporary folder
// and loaded with their warnings captured, error messages of snippets that must fail, shape
// lookups, and PLY files generated in ASCII or binary of either byte order.
#pragma once

#include "core/error.h"
#include "scene/pbrt/pbrt_loader.h"

#include <catch2/catch.hpp>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace rayproc::test {

struct PbrtTestDir {
    std::filesystem::path path = std::filesystem::temp_directory_path() /
                                 ("rayproc-pbrt-tests-" + std::to_string(::getpid()));
    PbrtTestDir() { std::filesystem::create_directories(path); }
    ~PbrtTestDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
};

inline const std::filesystem::path& pbrtTestDir() {
    static PbrtTestDir dir;
    return dir.path;
}

// Writes bytes to `name` under the test folder; returns the full path.
inline std::string writePbrtFile(const std::string& name, const std::string& bytes) {
    std::filesystem::path p = pbrtTestDir() / name;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << bytes;
    return p.string();
}

// A camera and film ahead of WorldBegin, for snippets that only care about the world. The
// camera uses the exporters' "Scale -1 1 1" convention, under which the world is not mirrored
// (pbrt_camera.h), so shapes stay where the snippet puts them. Four lines: the snippet starts on
// line 5.
inline const char* kPbrtHeader = "Scale -1 1 1  LookAt 0 0 5  0 0 0  0 1 0\n"
                                 "Camera \"perspective\" \"float fov\" 40\n"
                                 "Film \"rgb\" \"integer xresolution\" 32 "
                                 "\"integer yresolution\" 32\n"
                                 "WorldBegin\n";

struct LoadedPbrt {
    std::unique_ptr<Scene> scene;
    std::vector<std::string> warnings;
    bool warned(const std::string& fragment) const {
        for (const std::string& w : warnings)
            if (w.find(fragment) != std::string::npos) return true;
        return false;
    }
};

// Loads `text` as the file `name` (warnings captured, not printed).
inline LoadedPbrt loadPbrt(const std::string& text, const std::string& name = "scene.pbrt") {
    LoadedPbrt r;
    r.scene = loadPbrtScene(writePbrtFile(name, text), &r.warnings);
    return r;
}

// A world-block snippet after kPbrtHeader.
inline LoadedPbrt loadWorld(const std::string& world, const std::string& name = "scene.pbrt") {
    return loadPbrt(std::string(kPbrtHeader) + world, name);
}

// The InputError message of a snippet that must fail to load.
inline std::string pbrtErrorOf(const std::string& text, const std::string& name = "bad.pbrt") {
    std::string path = writePbrtFile(name, text);
    std::vector<std::string> warnings;
    try {
        loadPbrtScene(path, &warnings);
    } catch (const InputError& e) {
        return e.what();
    }
    FAIL("expected an InputError from " << path);
    return {};
}

// The shape leaves of a node tree in order, with the transform of the group above each one.
struct PlacedShape {
    const Shape* shape;
    Affine transform;
};
inline void collectShapes(const Node& n, const Affine& t, std::vector<PlacedShape>& out) {
    if (n.kind == Node::Kind::Shape) out.push_back({&n.shape, t});
    for (const auto& c : n.children) collectShapes(*c, t * c->transform, out);
}
inline std::vector<PlacedShape> rootShapes(const Scene& s) {
    std::vector<PlacedShape> out;
    collectShapes(*s.root, Affine(), out);
    return out;
}

// PLY files ------------------------------------------------------------------------------------

// A mesh as PLY: float x y z (and nx ny nz, u v when given), faces as "list uchar int".
struct PlyData {
    std::vector<float> positions, normals, uvs; // 3, 3 and 2 per vertex
    std::vector<std::vector<int>> faces;
};

inline void appendBytes(std::string& out, const void* p, std::size_t n, bool bigEndian) {
    const auto* b = static_cast<const char*>(p);
    if (!bigEndian) {
        out.append(b, n);
        return;
    }
    for (std::size_t i = 0; i < n; ++i) out += b[n - 1 - i];
}

// format: "ascii", "binary_little_endian" or "binary_big_endian".
inline std::string makePly(const PlyData& d, const std::string& format) {
    std::size_t nv = d.positions.size() / 3;
    bool normals = !d.normals.empty(), uvs = !d.uvs.empty();
    std::string s = "ply\nformat " + format + " 1.0\ncomment made by the rayproc tests\n";
    s += "element vertex " + std::to_string(nv) + "\n";
    s += "property float x\nproperty float y\nproperty float z\n";
    if (normals) s += "property float nx\nproperty float ny\nproperty float nz\n";
    if (uvs) s += "property float u\nproperty float v\n";
    s += "element face " + std::to_string(d.faces.size()) + "\n";
    s += "property list uchar int vertex_indices\nend_header\n";
    bool ascii = format == "ascii", big = format == "binary_big_endian";
    auto put = [&](float v) {
        if (ascii)
            s += std::to_string(v) + " ";
        else
            appendBytes(s, &v, 4, big);
    };
    for (std::size_t i = 0; i < nv; ++i) {
        for (int k = 0; k < 3; ++k) put(d.positions[3 * i + k]);
        if (normals)
            for (int k = 0; k < 3; ++k) put(d.normals[3 * i + k]);
        if (uvs)
            for (int k = 0; k < 2; ++k) put(d.uvs[2 * i + k]);
        if (ascii) s += "\n";
    }
    for (const auto& f : d.faces) {
        if (ascii) {
            s += std::to_string(f.size());
            for (int i : f) {
                s += ' ';
                s += std::to_string(i);
            }
            s += "\n";
        } else {
            auto n = static_cast<std::uint8_t>(f.size());
            s += char(n);
            for (int i : f) {
                std::int32_t v = i;
                appendBytes(s, &v, 4, big);
            }
        }
    }
    return s;
}

} // namespace rayproc::test
