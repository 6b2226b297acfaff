// Scene loading: the node hierarchy. Groups own children, instances place a prototype again,
// shapes are leaves. Prototypes are parsed on first use, depth first, so that Scene::prototypes
// lists every prototype after the ones it instances (computeBounds relies on that) and an
// instance cycle shows up as a prototype met again while it is still being parsed.
#include "core/error.h"
#include "scene/scene_loader_detail.h"

#include <nlohmann/json.hpp>

#include <unordered_map>

namespace rayproc::scene_json {

namespace {

// Deeper nesting is surely a mistake, and the recursive parser and bounds pass must not
// exhaust the stack.
constexpr int kMaxNesting = 256;
constexpr const char* kEmitterMaterial = "__emitter_black";

class HierarchyParser {
public:
    HierarchyParser(const JsonRef* prototypes, Scene& scene, const std::filesystem::path& dir)
        : m_prototypes(prototypes), m_scene(scene), m_dir(dir) {
        m_nodeTypes = {"group", "instance"};
        for (const std::string& t : shapeTypeNames()) m_nodeTypes.push_back(t);
        // Name lookups by map: a JSON object and Scene::findMaterial search linearly, which
        // turns large scenes quadratic.
        for (std::size_t i = 0; i < scene.materials.size(); ++i)
            m_materialIndex.emplace(scene.materials[i].name, int(i));
        if (m_prototypes && m_prototypes->isObject()) {
            for (const std::string& name : m_prototypes->keys())
                m_prototypeJson.emplace(name, m_prototypes->child(name));
        }
    }

    // Every prototype, used or not, in file order unless dependencies come first.
    void parsePrototypes() {
        if (!m_prototypes) return;
        if (!m_prototypes->isObject())
            m_prototypes->fail("expected an object mapping prototype names to groups");
        if (auto it = m_prototypeJson.find(""); it != m_prototypeJson.end())
            it->second.fail("prototype name must not be empty");
        for (const std::string& name : m_prototypes->keys())
            resolve(name, m_prototypeJson.at(name), 0);
    }

    std::unique_ptr<Node> parseNode(const JsonRef& v, int depth) {
        if (depth > kMaxNesting)
            v.fail("nodes nested too deeply (more than " + std::to_string(kMaxNesting) +
                   " levels)");
        std::string type = parseType(v, "node", m_nodeTypes);
        if (type == "group") {
            v.expectObject({"type", "name", "transform", "children"}, "a group node");
            auto node = parseGroupBody(v, depth);
            if (v.has("name")) node->name = v["name"].string();
            return node;
        }
        if (type == "instance") return parseInstance(v, depth);
        return parseShapeNode(v, type);
    }

private:
    // The transform and children of a group or prototype.
    std::unique_ptr<Node> parseGroupBody(const JsonRef& v, int depth) {
        auto node = std::make_unique<Node>();
        node->kind = Node::Kind::Group;
        if (v.has("transform")) node->transform = parseTransform(v["transform"]);
        if (v.has("children")) {
            JsonRef children = v["children"];
            if (!children.isArray()) children.fail("expected an array of nodes");
            for (std::size_t i = 0; i < children.arraySize(); ++i)
                node->children.push_back(parseNode(children[i], depth + 1));
        }
        return node;
    }

    std::unique_ptr<Node> parseInstance(const JsonRef& v, int depth) {
        v.expectObject({"type", "name", "transform", "prototype"}, "an instance node");
        auto node = std::make_unique<Node>();
        node->kind = Node::Kind::Instance;
        if (v.has("name")) node->name = v["name"].string();
        if (v.has("transform")) node->transform = parseTransform(v["transform"]);
        JsonRef ref = v["prototype"];
        std::string name = ref.nonEmptyString();
        if (m_prototypeJson.count(name) == 0) {
            std::vector<std::string> known =
                m_prototypes ? m_prototypes->keys() : std::vector<std::string>{};
            ref.fail("unknown prototype \"" + name + "\"; known prototypes: " + joinNames(known));
        }
        node->prototype = resolve(name, ref, depth + 1);
        return node;
    }

    // The prototype called `name`, parsing it first if need be. `ref` is where it is wanted
    // (an instance's "prototype", or the prototype itself when parsing them all).
    const Node* resolve(const std::string& name, const JsonRef& ref, int depth) {
        if (auto it = m_done.find(name); it != m_done.end()) return it->second;
        for (std::size_t i = 0; i < m_inProgress.size(); ++i) {
            if (m_inProgress[i] != name) continue;
            std::string cycle;
            for (std::size_t k = i; k < m_inProgress.size(); ++k) cycle += m_inProgress[k] + " -> ";
            ref.fail("instance cycle: " + cycle + name);
        }
        const JsonRef& v = m_prototypeJson.at(name);
        if (!v.isObject()) v.fail("expected an object (a prototype group)");
        v.expectObject({"type", "transform", "children"}, "a prototype");
        if (v.has("type") && v["type"].string() != "group")
            v["type"].fail("a prototype is a group; \"type\" may only be \"group\"");

        m_inProgress.push_back(name);
        auto node = parseGroupBody(v, depth);
        m_inProgress.pop_back();
        node->name = name;
        const Node* p = node.get();
        m_scene.prototypes.push_back(std::move(node)); // after everything it instances
        m_done[name] = p;
        return p;
    }

    std::unique_ptr<Node> parseShapeNode(const JsonRef& v, const std::string& type) {
        std::vector<std::string_view> allowed = {"type",     "name",     "transform",
                                                 "material", "emission", "two_sided"};
        for (std::string_view k : shapeKeys(type)) allowed.push_back(k);
        v.expectObject(allowed, "a " + type + " node");

        auto node = std::make_unique<Node>();
        node->kind = Node::Kind::Shape;
        Shape& shape = node->shape;
        if (v.has("name")) shape.name = node->name = v["name"].string();
        parseShapeGeometry(v, type, shape, m_dir, m_objCache);
        if (v.has("emission")) shape.emission = v["emission"].color();
        if (v.has("two_sided")) shape.twoSided = v["two_sided"].boolean();
        if (v.has("material")) {
            shape.material = materialIndex(v["material"]);
        } else if (shape.isEmissive()) {
            shape.material = emitterMaterial();
        } else {
            std::string known = joinNames(materialNames());
            v.fail("missing required key \"material\" (only emitters may omit it); known "
                   "materials: " +
                   known);
        }
        if (!v.has("transform")) return node;

        // Shapes live in their group's space: a shape's own transform becomes a group.
        auto group = std::make_unique<Node>();
        group->kind = Node::Kind::Group;
        group->name = node->name;
        group->transform = parseTransform(v["transform"]);
        group->children.push_back(std::move(node));
        return group;
    }

    std::vector<std::string> materialNames() const {
        std::vector<std::string> names;
        for (const Material& m : m_scene.materials)
            if (m.name != kEmitterMaterial) names.push_back(m.name);
        return names;
    }

    int materialIndex(const JsonRef& ref) {
        std::string name = ref.string();
        auto it = m_materialIndex.find(name);
        if (it == m_materialIndex.end() || name == kEmitterMaterial) {
            ref.fail("unknown material \"" + name +
                     "\"; known materials: " + joinNames(materialNames()));
        }
        return it->second;
    }

    // Pure emitters reflect nothing: one black diffuse material serves them all.
    int emitterMaterial() {
        if (auto it = m_materialIndex.find(kEmitterMaterial); it != m_materialIndex.end())
            return it->second;
        Material black;
        black.name = kEmitterMaterial;
        black.type = MaterialType::Diffuse;
        black.color = Vec3(0.0f);
        m_scene.materials.push_back(black);
        int index = int(m_scene.materials.size()) - 1;
        m_materialIndex.emplace(kEmitterMaterial, index);
        return index;
    }

    const JsonRef* m_prototypes;
    Scene& m_scene;
    std::filesystem::path m_dir;
    std::vector<std::string> m_nodeTypes;
    std::unordered_map<std::string, JsonRef> m_prototypeJson;
    std::unordered_map<std::string, int> m_materialIndex;
    std::unordered_map<std::string, const Node*> m_done;
    std::vector<std::string> m_inProgress; // the chain of prototypes being parsed
    std::map<std::string, std::shared_ptr<const TriangleMesh>> m_objCache;
};

} // namespace

void parseHierarchy(const JsonRef* prototypes, const JsonRef& nodes, Scene& scene,
                    const std::filesystem::path& sceneDir) {
    HierarchyParser parser(prototypes, scene, sceneDir);
    parser.parsePrototypes();
    if (!nodes.isArray()) nodes.fail("expected an array of nodes");
    if (nodes.arraySize() == 0) nodes.fail("scene has no geometry (\"nodes\" is empty)");
    auto root = std::make_unique<Node>();
    root->kind = Node::Kind::Group;
    root->name = "root";
    for (std::size_t i = 0; i < nodes.arraySize(); ++i)
        root->children.push_back(parser.parseNode(nodes[i], 1));
    scene.root = std::move(root);
}

} // namespace rayproc::scene_json
