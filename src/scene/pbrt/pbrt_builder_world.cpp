// SceneBuilder, the world block: materials, textures, lights, shapes and object instancing,
// and the final resolution of names.
#include "scene/pbrt/pbrt_builder.h"

#include "core/error.h"
#include "scene/pbrt/pbrt_materials.h"
#include "scene/pbrt/pbrt_shapes.h"

#include <algorithm>
#include <cstring>

namespace rayproc::pbrt {

int SceneBuilder::addMaterial(const std::string& type, const ParamList& params,
                              const std::string& name, const SourceLoc& loc) {
    MaterialResult r = convertMaterial(type, params, m_values, m_warnings, loc);
    reportUnused(params, "Material \"" + type + "\"");
    r.material.name = name.empty() ? type + " (" + loc.fileAndLine() + ")" : name;
    m_scene.materials.push_back(r.material);
    m_isInterface.push_back(r.interface);
    int index = int(m_scene.materials.size()) - 1;
    if (r.material.type == MaterialType::Mix)
        m_pendingMixes.push_back({index, {r.mixNames[0], r.mixNames[1]}, loc});
    return index;
}

// pbrt's default material: diffuse, reflectance 0.5.
int SceneBuilder::defaultMaterial() {
    if (m_defaultMaterial < 0) {
        Material m;
        m.name = "pbrt default (diffuse 0.5)";
        m.type = MaterialType::Diffuse;
        m.color = Vec3(0.5f);
        m_scene.materials.push_back(m);
        m_isInterface.push_back(false);
        m_defaultMaterial = int(m_scene.materials.size()) - 1;
    }
    return m_defaultMaterial;
}

void SceneBuilder::material(const std::string& type, const ParamList& params,
                            const SourceLoc& loc) {
    requireWorld("Material", loc);
    m_state.material = addMaterial(type, params, "", loc);
    m_state.materialName.clear();
}

void SceneBuilder::makeNamedMaterial(const std::string& name, const ParamList& params,
                                     const SourceLoc& loc) {
    requireWorld("MakeNamedMaterial", loc);
    if (m_namedMaterials.count(name)) failAt(loc, "material \"" + name + "\" is defined twice");
    const Param* type = params.get("type", {"string"});
    if (!type || type->strings.size() != 1)
        failAt(loc, "MakeNamedMaterial \"" + name + "\" needs \"string type\"");
    m_namedMaterials[name] = addMaterial(type->strings[0], params, name, loc);
}

void SceneBuilder::namedMaterial(const std::string& name, const SourceLoc& loc) {
    requireWorld("NamedMaterial", loc);
    m_state.material = -1;
    m_state.materialName = name;
    m_state.materialLoc = loc;
}

void SceneBuilder::texture(const std::string& name, const std::string& type, const std::string& cls,
                           const ParamList& params, const SourceLoc& loc) {
    requireWorld("Texture", loc);
    if (type != "float" && type != "spectrum" && type != "color")
        failAt(loc, "Texture \"" + name + "\": the type must be \"float\" or \"spectrum\", not \"" +
                        type + "\"");
    m_values.defineTexture(name, type, cls, params, loc, m_worldFix * m_state.ctm);
    reportUnused(params, "Texture \"" + cls + "\"");
}

void SceneBuilder::lightSource(const std::string& type, const ParamList& params,
                               const SourceLoc& loc) {
    requireWorld("LightSource", loc);
    convertLight(type, params, m_worldFix * m_state.ctm, m_values, m_warnings, loc, m_scene);
    reportUnused(params, "LightSource \"" + type + "\"");
}

void SceneBuilder::areaLightSource(const std::string& type, const ParamList& params,
                                   const SourceLoc& loc) {
    requireWorld("AreaLightSource", loc);
    m_state.area = convertAreaLight(type, params, m_values, m_warnings, loc);
    reportUnused(params, "AreaLightSource \"" + type + "\"");
}

// Consecutive shapes under the same transform share one group.
std::vector<Node*> SceneBuilder::place(std::vector<Shape>& shapes, bool grouped,
                                       const Affine& groupTransform) {
    Node* container = m_object ? m_object : m_scene.root.get();
    if (grouped) {
        Node* last = container->children.empty() ? nullptr : container->children.back().get();
        if (!last || last->kind != Node::Kind::Group ||
            std::memcmp(last->transform.m, groupTransform.m, sizeof groupTransform.m) != 0) {
            auto g = std::make_unique<Node>();
            g->kind = Node::Kind::Group;
            g->transform = groupTransform;
            container->children.push_back(std::move(g));
        }
        container = container->children.back().get();
    }
    std::vector<Node*> leaves;
    for (Shape& s : shapes) {
        auto n = std::make_unique<Node>();
        n->kind = Node::Kind::Shape;
        n->shape = std::move(s);
        leaves.push_back(n.get());
        container->children.push_back(std::move(n));
    }
    return leaves;
}

void SceneBuilder::shape(const std::string& type, const ParamList& params, const SourceLoc& loc,
                         const std::filesystem::path& dir) {
    requireWorld("Shape", loc);
    bool emissive = m_state.area && !isBlack(m_state.area->radiance);
    ShapeContext ctx{placement(), m_state.reverseOrientation, emissive, dir, m_mainDir, loc,
                     &m_loads};
    ShapeResult r = convertShape(type, params, ctx, m_warnings);
    FloatParam alpha = m_values.floatParam(params, "alpha", 1.0f); // cut-outs
    if (alpha.value < 0 || alpha.value > 1) failAt(loc, "shape \"alpha\" must lie in [0, 1]");
    reportUnused(params, "Shape \"" + type + "\"");
    if (r.shapes.empty()) return;
    if (!m_state.mediumOutside.empty())
        m_warnings.add(loc, "participating media around shapes are not supported: the medium "
                            "\"" + m_state.mediumOutside + "\" outside this shape is ignored");

    int material = m_state.material;
    bool pending = false;
    if (material < 0 && !m_state.materialName.empty()) {
        auto it = m_namedMaterials.find(m_state.materialName);
        if (it != m_namedMaterials.end())
            material = it->second;
        else
            pending = true;
    } else if (material < 0) {
        material = defaultMaterial();
    }
    if (!pending && m_isInterface[std::size_t(material)] && !emissive) {
        m_warnings.add(loc, "shapes of material \"interface\" only bound participating media, "
                            "which are not supported; skipped");
        return;
    }
    Vec3 radiance = emissive ? m_state.area->radiance : Vec3(0.0f);
    if (emissive && m_state.area->power > 0) // pbrt-v4: "power" sets L from the emitting area
        radiance = areaRadianceForPower(
            *m_state.area,
            shapesArea(r.shapes, r.grouped ? r.groupTransform : Affine::identity()));
    bool cut = alpha.textured() || alpha.value < 1;
    if (cut && std::any_of(r.shapes.begin(), r.shapes.end(),
                           [](const Shape& s) { return s.type != ShapeType::Mesh; }))
        m_warnings.add(loc, "\"alpha\" cut-outs are supported on triangle meshes only; ignored here");
    for (Shape& s : r.shapes) {
        s.material = pending ? 0 : material;
        if (s.type == ShapeType::Mesh) s.alpha = alpha;
        if (emissive) {
            s.emission = radiance;
            s.emissionSpectrum = m_state.area->spectrum;
            s.twoSided = m_state.area->twoSided;
        }
    }
    for (Node* n : place(r.shapes, r.grouped, r.groupTransform)) {
        if (r.deferred) m_deferredMeshes.push_back(n);
        if (pending) m_pendingMaterials.push_back({n, m_state.materialName, m_state.materialLoc});
        if (!m_state.mediumInside.empty())
            m_interiorMedia.push_back({n, m_state.mediumInside, loc});
    }
}

// Object instancing ----------------------------------------------------------------------------

void SceneBuilder::makeNamedMedium(const std::string& name, const ParamList& params,
                                   const SourceLoc& loc) {
    if (m_media.count(name)) failAt(loc, "medium \"" + name + "\" is defined twice");
    // Homogeneous media that only absorb are rendered (inside closed shapes); others are
    // reported where a shape uses them.
    Medium m;
    m.type = params.getString("type", "");
    double scale = params.getFloat("scale", 1.0);
    m.sigmaA = m_values.color(params, "sigma_a", SpectrumUse::Unbounded, Vec3(0.0011f, 0.0024f, 0.014f)) *
               float(scale);
    Vec3 sigmaS = m_values.color(params, "sigma_s", SpectrumUse::Unbounded, Vec3(2.55f, 3.21f, 3.77f));
    m.absorbingOnly = m.type == "homogeneous" && isBlack(sigmaS) && !params.find("Le") &&
                      !params.find("preset");
    for (const Param& p : params.all()) p.used = true;
    m_media[name] = m;
}

void SceneBuilder::mediumInterface(const std::string& inside, const std::string& outside,
                                   const SourceLoc& loc) {
    for (const std::string* name : {&inside, &outside})
        if (!name->empty()) m_mediumUses.push_back({nullptr, *name, loc});
    m_state.mediumInside = inside;
    m_state.mediumOutside = outside;
}

void SceneBuilder::objectBegin(const std::string& name, const SourceLoc& loc) {
    requireWorld("ObjectBegin", loc);
    if (m_object)
        failAt(loc, "ObjectBegin inside the definition of object \"" + m_object->name + "\"");
    if (m_objects.count(name)) failAt(loc, "object \"" + name + "\" is defined twice");
    begin("Object", loc);
    auto proto = std::make_unique<Node>();
    proto->kind = Node::Kind::Group;
    proto->name = name;
    m_object = proto.get();
    m_objects[name] = m_object;
    m_scene.prototypes.push_back(std::move(proto));
}

void SceneBuilder::objectEnd(const SourceLoc& loc) {
    requireWorld("ObjectEnd", loc);
    if (!m_object) failAt(loc, "ObjectEnd without ObjectBegin");
    end("Object", loc);
    m_object = nullptr;
}

void SceneBuilder::objectInstance(const std::string& name, const SourceLoc& loc) {
    requireWorld("ObjectInstance", loc);
    if (m_object)
        failAt(loc, "ObjectInstance inside the definition of object \"" + m_object->name + "\"");
    Mat4 toWorld = m_worldFix * m_state.ctm;
    if (!toWorld.isAffine() || toWorld.det3() == 0) {
        m_warnings.add(loc, "object instance under a singular or projective transform; skipped");
        return;
    }
    auto node = std::make_unique<Node>();
    node->kind = Node::Kind::Instance;
    node->name = name;
    node->transform = toWorld.toAffine();
    m_instances.push_back({node.get(), name, loc});
    m_scene.root->children.push_back(std::move(node));
}

// Resolution -----------------------------------------------------------------------------------

bool SceneBuilder::hasGeometry() const {
    auto hasLeaf = [](const Node& n, auto&& self) -> bool {
        if (n.kind == Node::Kind::Shape) return true;
        if (n.kind == Node::Kind::Instance) return n.prototype && self(*n.prototype, self);
        for (const auto& c : n.children)
            if (self(*c, self)) return true;
        return false;
    };
    return hasLeaf(*m_scene.root, hasLeaf);
}

// Mix materials name their two materials, which may be defined later; a mix that reaches
// itself through other mixes is an error (it would never resolve to a surface).
void SceneBuilder::resolveMixes() {
    for (const PendingMix& p : m_pendingMixes) {
        Material& m = m_scene.materials[std::size_t(p.material)];
        for (int k = 0; k < 2; ++k) {
            auto it = m_namedMaterials.find(p.names[k]);
            if (it == m_namedMaterials.end())
                failAt(p.loc, "Material \"mix\" names \"" + p.names[k] +
                                  "\", which was never defined (MakeNamedMaterial)");
            if (m_isInterface[std::size_t(it->second)])
                failAt(p.loc, "Material \"mix\" cannot mix \"" + p.names[k] +
                                  "\", an interface material");
            m.mix[k] = it->second;
        }
    }
    for (const PendingMix& p : m_pendingMixes)
        if (mixContainsItself(m_scene.materials, p.material))
            failAt(p.loc, "Material \"mix\" \"" + m_scene.materials[std::size_t(p.material)].name +
                              "\" contains itself");
}

// Every shape leaf under `n` gets the medium's absorption.
void SceneBuilder::setInteriorAbsorption(Node& n, const Vec3& sigmaA) {
    if (n.kind == Node::Kind::Shape) n.shape.interiorAbsorption = sigmaA;
    for (auto& c : n.children) setInteriorAbsorption(*c, sigmaA);
}

void SceneBuilder::finish() {
    joinLoads();
    if (!m_stack.empty()) {
        const Frame& f = m_stack.back();
        failAt(f.loc, f.kind + "Begin has no matching " + f.kind + "End");
    }
    if (!m_inWorld) throw InputError(m_scene.path + ": no WorldBegin: the file has no world block");
    for (const Pending& p : m_pendingMaterials) {
        auto it = m_namedMaterials.find(p.name);
        if (it == m_namedMaterials.end())
            failAt(p.loc, "NamedMaterial \"" + p.name + "\" was never defined (MakeNamedMaterial)");
        p.node->shape.material = it->second;
    }
    resolveMixes();
    for (const Pending& p : m_mediumUses) // pbrt-v4 resolves medium names after parsing too
        if (!m_media.count(p.name))
            failAt(p.loc, "MediumInterface names \"" + p.name + "\", which was never defined "
                          "(MakeNamedMedium)");
    for (const Pending& p : m_interiorMedia) {
        const Medium& m = m_media.at(p.name);
        if (m.absorbingOnly)
            setInteriorAbsorption(*p.node, m.sigmaA);
        else
            m_warnings.add(p.loc, "participating media that scatter or emit are not supported: "
                                  "medium \"" + p.name + "\" (type \"" + m.type +
                                  "\") inside this shape is ignored");
    }
    for (const Pending& p : m_instances) {
        auto it = m_objects.find(p.name);
        if (it == m_objects.end())
            failAt(p.loc, "ObjectInstance of \"" + p.name + "\", which was never defined");
        p.node->prototype = it->second;
    }
    if (!hasGeometry())
        throw InputError(m_scene.path + ": the scene has no geometry (no supported Shape)");
    m_scene.computeBounds();
}

} // namespace rayproc::pbrt
