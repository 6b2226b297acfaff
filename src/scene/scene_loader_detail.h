// Building blocks shared by the scene_loader*.cpp files: checked JSON access with JSON-pointer
// error locations, transforms, and the per-section readers. Private to the loader.
#pragma once

#include "scene/scene_loader.h"

#include <nlohmann/json_fwd.hpp>

#include <filesystem>
#include <initializer_list>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace rayproc {
// ---------------------------------------------------------------------------------------------
// Building blocks shared by the scene_loader*.cpp files (and open to the tests). Not an API
// for the rest of the renderer.
namespace scene_json {

using Json = nlohmann::ordered_json; // keeps the file's order of materials and prototypes

// A JSON value together with where it sits. Every accessor checks what it reads and throws an
// InputError naming the file and the JSON pointer of the value at fault.
class JsonRef {
public:
    JsonRef(const Json& value, const std::string& file, std::string pointer);

    const Json& json() const { return *m_value; }
    const std::string& file() const { return *m_file; }
    const std::string& pointer() const { return m_pointer; }
    [[noreturn]] void fail(const std::string& problem) const;

    // Objects. expectObject checks the type and that every key is in `allowed`; `what` names
    // the object in messages ("a sphere node").
    void expectObject(std::initializer_list<std::string_view> allowed, std::string_view what) const;
    void expectObject(const std::vector<std::string_view>& allowed, std::string_view what) const;
    bool isObject() const;
    bool has(std::string_view key) const;
    JsonRef operator[](std::string_view key) const; // a missing key is an error
    JsonRef child(std::string_view key) const;      // pointer of `key`, which need not exist
    std::vector<std::string> keys() const;

    // Arrays.
    bool isArray() const;
    std::size_t arraySize() const; // expects an array
    JsonRef operator[](std::size_t index) const;

    // Scalars. Numbers must be finite as 32-bit floats; integers must be whole numbers.
    bool isNumber() const;
    bool isString() const;
    float number() const;
    float numberIn(float lo, float hi) const; // closed range
    float positive() const;                   // > 0
    long long integer(long long lo, long long hi) const;
    bool boolean() const;
    std::string string() const;
    std::string nonEmptyString() const;

    // Small vectors: "expected an array of N numbers" when the shape is wrong.
    Vec2 vec2() const;
    Vec3 vec3() const;
    Vec3 direction() const; // non-zero, returned normalised
    Vec3 color() const;     // components >= 0 (emission, intensities)
    Vec3 albedo() const;    // components in [0, 1] (reflectances)

private:
    const Json* m_value;
    const std::string* m_file;
    std::string m_pointer;
};

// A key as a JSON pointer token (RFC 6901: "~" becomes "~0", "/" becomes "~1").
std::string pointerToken(std::string_view key);

// "a, b, c" or "(none)": the lists of allowed values in messages.
std::string joinNames(const std::vector<std::string>& names);

// The "type" of an object (a node, material or light; `what` says which), checked against
// `known` so that a missing or misspelt type lists the alternatives.
std::string parseType(const JsonRef& v, std::string_view what,
                      const std::vector<std::string>& known);

// A node transform: a 12- or 16-number row-major matrix, or an object of translate / rotate /
// scale applied as T * R * S.
Affine parseTransform(const JsonRef& v);

// Top-level sections (scene_loader_settings.cpp).
Camera parseCamera(const JsonRef& v);
SceneRenderSettings parseRenderSettings(const JsonRef& v);
void parseTextures(const JsonRef& v, Scene& scene);
void parseMaterials(const JsonRef& v, Scene& scene);
void parseLights(const JsonRef& v, Scene& scene);

// The node hierarchy: "prototypes" (may be null) and "nodes" (scene_loader_nodes.cpp). Fills
// Scene::root and Scene::prototypes, dependencies first.
void parseHierarchy(const JsonRef* prototypes, const JsonRef& nodes, Scene& scene,
                    const std::filesystem::path& sceneDir);

// Shape leaves (scene_loader_shapes.cpp). parseShapeGeometry fills the geometry of `shape`
// (not its material or emission) from a node of shape type `type`; `objCache` shares the mesh
// of an OBJ file among all nodes that name it.
std::vector<std::string> shapeTypeNames();
std::vector<std::string_view> shapeKeys(std::string_view type); // keys beyond the common ones
void parseShapeGeometry(const JsonRef& v, std::string_view type, Shape& shape,
                        const std::filesystem::path& sceneDir,
                        std::map<std::string, std::shared_ptr<const TriangleMesh>>& objCache);

} // namespace scene_json
} // namespace rayproc
