// Scene loading, top level: read the file, parse the JSON (syntax errors by line and column,
// duplicate keys by JSON pointer), then hand each top-level section to its parser.
#include "scene/scene_loader_detail.h"

#include "core/error.h"
#include "scene/pbrt/pbrt_loader.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <functional>
#include <optional>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

namespace rayproc {

using scene_json::Json;
using scene_json::JsonRef;

namespace {

// The deepest nesting of JSON arrays and objects a scene file may have.
constexpr std::size_t kMaxJsonDepth = 1024;

// nlohmann reports the byte offset of the last character it read; scene authors want the line
// and column of that character (both 1-based, columns counted in bytes).
std::string lineColumn(const std::string& text, std::size_t byteOffset) {
    std::size_t pos = byteOffset == 0 ? 0 : std::min(byteOffset - 1, text.size());
    std::size_t line = 1, lineStart = 0;
    for (std::size_t i = 0; i < pos; ++i) {
        if (text[i] == '\n') {
            ++line;
            lineStart = i + 1;
        }
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(pos - lineStart + 1);
}

// Keeps the lexer's own words ("syntax error while parsing object - unexpected '}'; ...") but
// drops nlohmann's exception id and its own position prefix.
std::string syntaxProblem(const std::string& what) {
    std::size_t p = what.find("syntax error");
    if (p != std::string::npos) return what.substr(p);
    p = what.find("] ");
    return p == std::string::npos ? what : what.substr(p + 2);
}

// Follows the parser through the document, keeping the JSON pointer of each open object and
// array, for two reasons. Duplicate keys are legal JSON and the parser silently keeps one of
// them, but in a scene file they are a mistake (two materials of the same name, a radius given
// twice); and errors the parser raises without a position still get a JSON pointer.
class ParseTracker {
public:
    explicit ParseTracker(const std::string& file) : m_file(file) {}

    // The pointer of the value being read.
    std::string currentPointer() const { return childPointer(); }

    bool operator()(int /*depth*/, Json::parse_event_t event, Json& parsed) {
        using Event = Json::parse_event_t;
        switch (event) {
        case Event::object_start:
        case Event::array_start:
            // Each open container costs the parser and this tracker ~150 bytes for one byte
            // of input: bound the depth, far above what scenes need (nodes nest <= 256 deep).
            if (m_frames.size() >= kMaxJsonDepth) {
                throw InputError(m_file, truncatedPointer(),
                                 "nested more than " + std::to_string(kMaxJsonDepth) +
                                     " levels deep (arrays and objects)");
            }
            m_frames.push_back({event == Event::array_start, 0, {}, {}});
            break;
        case Event::key: {
            Frame& f = m_frames.back();
            f.key = parsed.get<std::string>();
            if (!f.keys.insert(f.key).second) {
                std::string section = m_frames.size() == 2 ? m_frames[0].key : "";
                std::string what = section == "materials"    ? "duplicate material name"
                                   : section == "prototypes" ? "duplicate prototype name"
                                                             : "duplicate key";
                throw InputError(m_file, childPointer(), what + " \"" + f.key + "\"");
            }
            break;
        }
        case Event::value:
            advance();
            break;
        case Event::object_end:
        case Event::array_end:
            m_frames.pop_back();
            advance();
            break;
        }
        return true;
    }

private:
    // An open object or array and where the parser is inside it. A container's own place is
    // its parent's current key or index, so the frames spell the pointer without storing it
    // (storing it per frame costs quadratic time on deeply nested input).
    struct Frame {
        bool isArray;
        std::size_t index;                    // arrays: the element being read
        std::string key;                      // objects: the member being read
        std::unordered_set<std::string> keys; // objects: the keys seen so far
    };

    // The first levels of the pointer, for messages about very deep input.
    std::string truncatedPointer() const {
        std::string p;
        for (std::size_t i = 0; i < m_frames.size() && i < 12; ++i) {
            const Frame& f = m_frames[i];
            p += "/" + (f.isArray ? std::to_string(f.index) : scene_json::pointerToken(f.key));
        }
        return m_frames.size() > 12 ? p + "/..." : p;
    }

    // The pointer of the value being read inside the innermost open container.
    std::string childPointer() const {
        std::string p;
        for (const Frame& f : m_frames)
            p += "/" + (f.isArray ? std::to_string(f.index) : scene_json::pointerToken(f.key));
        return p;
    }
    void advance() {
        if (!m_frames.empty() && m_frames.back().isArray) ++m_frames.back().index;
    }

    const std::string& m_file;
    std::vector<Frame> m_frames;
};

// nlohmann refuses literals that overflow a double (1e999) with an exception that carries the
// literal but no position; the tracker knows which value was being read.
std::string overflowProblem(const std::string& what) {
    std::size_t a = what.find('\''), b = what.rfind('\'');
    std::string literal = a != std::string::npos && b > a ? what.substr(a + 1, b - a - 1) : "";
    return "expected a finite number; " + (literal.empty() ? "a literal" : literal) +
           " overflows even a 64-bit float";
}

Json parseJson(const std::string& text, const std::string& file) {
    ParseTracker tracker(file);
    try {
        return Json::parse(text, std::ref(tracker));
    } catch (const nlohmann::json::parse_error& e) {
        throw InputError(file, lineColumn(text, e.byte), syntaxProblem(e.what()));
    } catch (const nlohmann::json::out_of_range& e) {
        std::string where = tracker.currentPointer();
        throw InputError(file, where.empty() ? "/" : where, overflowProblem(e.what()));
    } catch (const nlohmann::json::exception& e) {
        throw InputError(file, "/", e.what());
    }
}

// The scene must contain at least one shape, directly or through instances. Memoised per
// prototype so that deep instancing stays linear.
bool hasGeometry(const Node& n, std::unordered_set<const Node*>& empty) {
    switch (n.kind) {
    case Node::Kind::Shape:
        return true;
    case Node::Kind::Instance:
        if (!n.prototype || empty.count(n.prototype)) return false;
        if (hasGeometry(*n.prototype, empty)) return true;
        empty.insert(n.prototype);
        return false;
    case Node::Kind::Group:
        for (const auto& c : n.children)
            if (hasGeometry(*c, empty)) return true;
        return false;
    }
    return false;
}

// Nested instancing multiplies: 40 prototypes, each placing the next twice, describe 2^40
// placements in a few lines. The renderer flattens nesting into one level of Embree instances
// (docs/architecture.md), so every placement costs memory. Counted per prototype once
// (memoised), saturating, before anything is built.
constexpr std::uint64_t kMaxPlacements = 1ull << 22;
constexpr std::uint64_t kSaturated = 1ull << 62;

std::uint64_t saturatingAdd(std::uint64_t a, std::uint64_t b) {
    return std::min(kSaturated, a + b); // both <= 2^62: no wrap-around
}

// Placed groups and instances (an upper bound on the Embree instances) under `n`, `n` included.
std::uint64_t placements(const Node& n, std::unordered_map<const Node*, std::uint64_t>& memo) {
    switch (n.kind) {
    case Node::Kind::Shape:
        return 0;
    case Node::Kind::Instance: {
        if (!n.prototype) return 1;
        auto it = memo.find(n.prototype);
        std::uint64_t inside =
            it != memo.end() ? it->second : (memo[n.prototype] = placements(*n.prototype, memo));
        return inside; // the prototype group counts itself
    }
    case Node::Kind::Group: {
        std::uint64_t total = 1;
        for (const auto& c : n.children) total = saturatingAdd(total, placements(*c, memo));
        return total;
    }
    }
    return 0;
}

} // namespace

std::unique_ptr<Scene> loadSceneFromString(const std::string& text, const std::string& path) {
    Json doc = parseJson(text, path);
    JsonRef top(doc, path, "");
    top.expectObject({"camera", "render", "textures", "materials", "lights", "prototypes", "nodes"},
                     "the scene");

    auto scene = std::make_unique<Scene>();
    scene->path = path;
    if (top.has("camera")) scene->camera = scene_json::parseCamera(top["camera"]);
    if (top.has("render")) scene->render = scene_json::parseRenderSettings(top["render"]);
    if (top.has("textures")) scene_json::parseTextures(top["textures"], *scene);
    if (top.has("materials")) scene_json::parseMaterials(top["materials"], *scene);
    if (top.has("lights")) scene_json::parseLights(top["lights"], *scene);

    if (!top.has("nodes")) top.fail("missing required key \"nodes\": scene has no geometry");
    JsonRef nodes = top["nodes"];
    std::optional<JsonRef> prototypes;
    if (top.has("prototypes")) prototypes = top["prototypes"];
    std::filesystem::path dir = std::filesystem::path(path).parent_path();
    scene_json::parseHierarchy(prototypes ? &*prototypes : nullptr, nodes, *scene, dir);

    std::unordered_set<const Node*> empty;
    if (!hasGeometry(*scene->root, empty)) nodes.fail("scene has no geometry");
    std::unordered_map<const Node*, std::uint64_t> memo;
    std::uint64_t placed = placements(*scene->root, memo);
    if (placed > kMaxPlacements) {
        nodes.fail("the scene places " +
                   (placed >= kSaturated ? "more than 2^62" : std::to_string(placed)) +
                   " groups and instances once nested instances are expanded; the limit is " +
                   std::to_string(kMaxPlacements) + " (2^22)");
    }
    scene->computeBounds();
    return scene;
}

std::unique_ptr<Scene> loadScene(const std::string& path) {
    if (isPbrtPath(path)) return loadPbrtScene(path); // pbrt-v4 text (docs/pbrt-import.md)
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw InputError(path + ": is a directory, not a scene file");
    // A device or pipe may never end (/dev/zero, /dev/stdin): reading it would grow without
    // bound, so only regular files are scene files.
    if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
        throw InputError(path + ": not a regular file (a device, pipe or socket), not a scene file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open the scene file (missing or unreadable)");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw InputError(path + ": cannot read the scene file");
    return loadSceneFromString(text.str(), path);
}

} // namespace rayproc
