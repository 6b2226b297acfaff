// The semantic half of the pbrt reader: the graphics state (CTM, attribute stack, material,
// area light, ReverseOrientation), named coordinate systems, materials, textures and objects,
// and the rayproc Scene they build. The parser (pbrt_parser.cpp) calls one method per directive.
//
// Shapes at the top level are leaves of Scene::root; ObjectBegin / ObjectEnd collect shapes
// into a prototype group and ObjectInstance places it as an instance node with the CTM, so the
// geometry is stored once however often it is placed. Named materials and object instances may
// be used before they are defined (pbrt-v4 resolves them after parsing); they are resolved in
// finish().
#pragma once

#include "scene/pbrt/deferred_loads.h"
#include "scene/pbrt/pbrt_camera.h"
#include "scene/pbrt/pbrt_lights.h"
#include "scene/pbrt/pbrt_values.h"

#include <filesystem>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace rayproc::pbrt {

class SceneBuilder {
public:
    SceneBuilder(Scene& scene, Warnings& warnings, const std::filesystem::path& mainFile);
    ~SceneBuilder();
    SceneBuilder(const SceneBuilder&) = delete;
    SceneBuilder& operator=(const SceneBuilder&) = delete;

    // Transformations (CTM = CTM * M) and named coordinate systems.
    void identity();
    void concat(const Mat4& m);
    void setTransform(const Mat4& m);
    void lookAt(const double v[9], const SourceLoc& loc);
    void rotate(double degrees, const Vec3d& axis, const SourceLoc& loc);
    void coordinateSystem(const std::string& name);
    void coordSysTransform(const std::string& name, const SourceLoc& loc);
    void reverseOrientation() { m_state.reverseOrientation = !m_state.reverseOrientation; }
    // ColorSpace: "srgb", "rec2020", "dci-p3" or "aces2065-1" for the "rgb" values that follow
    // (part of the graphics state, as in pbrt-v4); another name is an error.
    void colorSpace(const std::string& name, const SourceLoc& loc);

    // Blocks. `kind` is "Attribute", "Transform" or "Object".
    void begin(const std::string& kind, const SourceLoc& loc);
    void end(const std::string& kind, const SourceLoc& loc);

    // The options block (before WorldBegin).
    void camera(const std::string& type, ParamList params, const SourceLoc& loc);
    void film(ParamList params, const SourceLoc& loc);
    void pixelFilter(const std::string& type, ParamList params, const SourceLoc& loc);
    void sampler(const std::string& type, const ParamList& params, const SourceLoc& loc);
    void integrator(const std::string& type, const ParamList& params, const SourceLoc& loc);
    void worldBegin(const SourceLoc& loc);
    void worldEnd(const SourceLoc& loc);

    // The world block.
    void material(const std::string& type, const ParamList& params, const SourceLoc& loc);
    void makeNamedMaterial(const std::string& name, const ParamList& params, const SourceLoc& loc);
    void namedMaterial(const std::string& name, const SourceLoc& loc);
    void texture(const std::string& name, const std::string& type, const std::string& cls,
                 const ParamList& params, const SourceLoc& loc);
    void lightSource(const std::string& type, const ParamList& params, const SourceLoc& loc);
    void areaLightSource(const std::string& type, const ParamList& params, const SourceLoc& loc);
    void shape(const std::string& type, const ParamList& params, const SourceLoc& loc,
               const std::filesystem::path& dir);
    // Participating media are not rendered: a named medium is accepted, and a warning is given
    // once where a shape or the camera is actually placed inside or outside of one.
    void makeNamedMedium(const std::string& name, const ParamList& params, const SourceLoc& loc);
    void mediumInterface(const std::string& inside, const std::string& outside,
                         const SourceLoc& loc);
    void objectBegin(const std::string& name, const SourceLoc& loc);
    void objectEnd(const SourceLoc& loc);
    void objectInstance(const std::string& name, const SourceLoc& loc);

    // A directive that is valid pbrt but has no effect in rayproc.
    void unsupported(const std::string& directive, const std::string& fallback,
                     const SourceLoc& loc);
    // Options-block directives may not follow WorldBegin, world-block ones may not precede it.
    void requireOptions(const std::string& directive, const SourceLoc& loc) const;
    void requireWorld(const std::string& directive, const SourceLoc& loc) const;

    // Checks the blocks are closed, resolves names, and computes the scene's bounds; first
    // waits for the PLY files read in the background.
    void finish();
    // Waits for the background reads and throws the first one's error (DeferredLoads): the
    // load's error when the parser fails later in the file.
    void joinLoads();

private:
    struct GraphicsState {
        Mat4 ctm;
        bool reverseOrientation = false;
        int material = -1;        // index into Scene::materials; -1: the named one, or default
        std::string materialName; // NamedMaterial, when material == -1
        SourceLoc materialLoc;
        std::optional<AreaEmission> area;
        std::string mediumInside, mediumOutside; // MediumInterface; empty: vacuum
        const spectral::ColorSpace* colorSpace = &spectral::colorSpace(spectral::ColorSpaceId::Srgb);
    };
    struct Frame {
        std::string kind;
        GraphicsState saved;
        SourceLoc loc;
    };
    struct Pending {
        Node* node;
        std::string name;
        SourceLoc loc;
    };

    Mat4 placement() const; // the CTM as rayproc's world (or object) space sees it
    int addMaterial(const std::string& type, const ParamList& params, const std::string& name,
                    const SourceLoc& loc);
    int defaultMaterial();
    void reportUnused(const ParamList& params, const std::string& what) const;
    std::vector<Node*> place(std::vector<Shape>& shapes, bool grouped,
                             const Affine& groupTransform);
    bool hasGeometry() const;
    void resolveMixes();
    void setInteriorAbsorption(Node& n, const Vec3& sigmaA);

    Scene& m_scene;
    Warnings& m_warnings;
    std::filesystem::path m_mainDir;
    ValueReader m_values;
    GraphicsState m_state;
    std::vector<Frame> m_stack;
    std::unordered_map<std::string, Mat4> m_coordSystems;
    CameraDirective m_camera;
    FilmDirective m_film;
    FilterDirective m_filter;
    bool m_inWorld = false;
    Mat4 m_worldFix; // identity, or the mirror that makes rayproc's camera show pbrt's image
    std::unordered_map<std::string, int> m_namedMaterials;
    std::vector<bool> m_isInterface; // per Scene::materials entry
    int m_defaultMaterial = -1;
    std::vector<Pending> m_pendingMaterials; // shape nodes whose named material comes later
    struct PendingMix {
        int material;
        std::string names[2];
        SourceLoc loc;
    };
    std::vector<PendingMix> m_pendingMixes;
    struct Medium {
        std::string type;
        Vec3 sigmaA;
        bool absorbingOnly = false;
    };
    std::unordered_map<std::string, Medium> m_media; // MakeNamedMedium
    std::vector<Pending> m_mediumUses;              // MediumInterface names (node unused)
    std::vector<Pending> m_interiorMedia;           // shapes filled with a medium
    std::unordered_map<std::string, Node*> m_objects;
    Node* m_object = nullptr; // the prototype being defined
    std::vector<Pending> m_instances;
    DeferredLoads m_loads;              // PLY files read while the parser goes on
    std::vector<Node*> m_deferredMeshes; // their shapes: isQuad is known once joined
};

} // namespace rayproc::pbrt
