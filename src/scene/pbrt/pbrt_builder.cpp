// SceneBuilder, the graphics state and the options block: transforms, attribute scopes, named
// coordinate systems, and Camera / Film / Sampler / Integrator up to WorldBegin.
#include "scene/pbrt/pbrt_builder.h"

#include "core/error.h"
#include "scene/pbrt/pbrt_shapes.h"

#include <algorithm>
#include <cmath>

namespace rayproc::pbrt {

SceneBuilder::SceneBuilder(Scene& scene, Warnings& warnings, const std::filesystem::path& mainFile)
    : m_scene(scene), m_warnings(warnings), m_mainDir(mainFile.parent_path()), m_values(warnings) {
    m_values.bindTextures(&m_scene.textures, m_mainDir);
    m_scene.path = mainFile.string();
    m_scene.root = std::make_unique<Node>();
    m_scene.root->kind = Node::Kind::Group;
    m_scene.root->name = "root";
    m_warnings.setBeforeAdd([this] { m_loads.join(m_warnings); });
}

SceneBuilder::~SceneBuilder() {
    m_warnings.setBeforeAdd(nullptr); // the list outlives the builder; m_loads waits
}

void SceneBuilder::joinLoads() {
    m_loads.join(m_warnings);
    for (Node* n : m_deferredMeshes) n->shape.isQuad = isQuadMesh(*n->shape.mesh);
    m_deferredMeshes.clear();
}

// Transformations ------------------------------------------------------------------------------

void SceneBuilder::identity() {
    m_state.ctm = Mat4();
}
void SceneBuilder::concat(const Mat4& m) {
    m_state.ctm = m_state.ctm * m;
}
void SceneBuilder::setTransform(const Mat4& m) {
    m_state.ctm = m;
}

void SceneBuilder::lookAt(const double v[9], const SourceLoc& loc) {
    Mat4 m;
    if (!Mat4::lookAt({v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}, m))
        failAt(loc, "LookAt: the eye and the target coincide, or up is parallel to the view");
    concat(m);
}

void SceneBuilder::rotate(double degrees, const Vec3d& axis, const SourceLoc& loc) {
    if (length(axis) == 0) failAt(loc, "Rotate: the axis is zero");
    concat(Mat4::rotate(degrees, axis.x, axis.y, axis.z));
}

void SceneBuilder::coordinateSystem(const std::string& name) {
    m_coordSystems[name] = m_state.ctm;
}

void SceneBuilder::coordSysTransform(const std::string& name, const SourceLoc& loc) {
    auto it = m_coordSystems.find(name);
    if (it == m_coordSystems.end()) {
        m_warnings.add(loc,
                       "no coordinate system named " + quote(name) + "; CoordSysTransform ignored");
        return;
    }
    m_state.ctm = it->second;
}

Mat4 SceneBuilder::placement() const {
    return m_object ? m_state.ctm : m_worldFix * m_state.ctm;
}

// Blocks ---------------------------------------------------------------------------------------

void SceneBuilder::begin(const std::string& kind, const SourceLoc& loc) {
    m_stack.push_back({kind, m_state, loc});
}

void SceneBuilder::end(const std::string& kind, const SourceLoc& loc) {
    if (m_stack.empty())
        failAt(loc, "unbalanced " + kind + "End: there is no open " + kind + "Begin");
    const Frame& f = m_stack.back();
    if (f.kind != kind)
        failAt(loc, kind + "End does not match the " + f.kind + "Begin at " + f.loc.str());
    if (kind == "Transform")
        m_state.ctm = f.saved.ctm;
    else
        m_state = f.saved;
    m_values.setColorSpace(*m_state.colorSpace);
    m_stack.pop_back();
}

void SceneBuilder::colorSpace(const std::string& name, const SourceLoc& loc) {
    const spectral::ColorSpace* cs = spectral::colorSpaceByName(name);
    if (!cs)
        failAt(loc, "unknown colour space \"" + name +
                        "\" (expected srgb, rec2020, dci-p3 or aces2065-1)");
    m_state.colorSpace = cs;
    m_values.setColorSpace(*cs);
}

void SceneBuilder::requireOptions(const std::string& directive, const SourceLoc& loc) const {
    if (m_inWorld) failAt(loc, "\"" + directive + "\" is not allowed after WorldBegin");
}

void SceneBuilder::requireWorld(const std::string& directive, const SourceLoc& loc) const {
    if (!m_inWorld) failAt(loc, "\"" + directive + "\" is only allowed after WorldBegin");
}

void SceneBuilder::unsupported(const std::string& directive, const std::string& fallback,
                               const SourceLoc& loc) {
    m_warnings.add(loc, directive + " is not supported; " + fallback);
}

void SceneBuilder::reportUnused(const ParamList& params, const std::string& what) const {
    for (const Param* p : params.unused())
        m_warnings.add(p->loc,
                       "parameter " + p->decl() + " of " + what + " is not supported; ignored");
}

// The options block ----------------------------------------------------------------------------

void SceneBuilder::camera(const std::string& type, ParamList params, const SourceLoc& loc) {
    requireOptions("Camera", loc);
    if (!m_state.mediumOutside.empty())
        m_warnings.add(loc, "participating media are not supported: the camera's medium \"" +
                                m_state.mediumOutside + "\" is ignored (vacuum)");
    m_camera = {true, m_state.ctm, type, std::move(params), loc};
    Mat4 worldFromCamera;
    if (m_state.ctm.inverse(worldFromCamera)) m_coordSystems["camera"] = worldFromCamera;
}

void SceneBuilder::film(ParamList params, const SourceLoc& loc) {
    requireOptions("Film", loc);
    if (m_state.colorSpace->id != spectral::ColorSpaceId::Srgb)
        m_warnings.add(loc, std::string("the film's colour space \"") + m_state.colorSpace->name +
                                "\" is not applied: rayproc writes linear sRGB");
    m_film = {true, std::move(params), loc};
}

void SceneBuilder::pixelFilter(const std::string& type, ParamList params, const SourceLoc& loc) {
    requireOptions("PixelFilter", loc);
    m_filter = {true, type, std::move(params), loc};
}

void SceneBuilder::sampler(const std::string& type, const ParamList& params,
                           const SourceLoc& loc) {
    requireOptions("Sampler", loc);
    long long spp = params.getInt("pixelsamples", 16);
    if (type == "stratified" && !params.has("pixelsamples"))
        spp = params.getInt("xsamples", 4) * params.getInt("ysamples", 4);
    if (spp < 1 || spp > 1000000) failAt(loc, "Sampler: pixel samples must be in 1..1000000");
    m_scene.render.spp = int(spp);
    long long seed = params.getInt("seed", -1);
    if (params.has("seed") && seed < 0) failAt(loc, "Sampler: \"seed\" must not be negative");
    if (seed >= 0) m_scene.render.seed = seed;
    for (const Param& p : params.all()) p.used = true; // rayproc's own stratified sampling
}

// The same limits as a JSON scene's "max_depth" (1..10000).
void SceneBuilder::integrator(const std::string& type, const ParamList& params,
                              const SourceLoc& loc) {
    requireOptions("Integrator", loc);
    // pbrt-v4's maxdepth D bounds the scattering events of a path: light is sampled at the
    // first D vertices and emission found at vertex D + 1. rayproc's max depth M counts the
    // bounces before the last vertex, which takes a light sample: M + 1 scattering events. So
    // D becomes M = D - 1 (the same paths); rayproc's shortest is M = 1 (two events).
    long long depth = params.getInt("maxdepth", 5);
    if (depth < 0) failAt(loc, "Integrator: maxdepth must not be negative");
    if (depth <= 1)
        m_warnings.add(loc, "maxdepth " + std::to_string(depth) +
                                " is not supported (rayproc's paths have at least two scattering "
                                "events); using 2");
    if (depth > 10001) m_warnings.add(loc, "maxdepth above 10001 is not supported; using 10001");
    m_scene.render.maxDepth = int(std::clamp<long long>(depth - 1, 1, 10000));
    if (type == "sppm") {
        // pbrt-v4's SPPM: a camera path makes its visible point at its D-th intersection at
        // the latest, after D - 1 specular bounces (gi's max depth D - 1 above: the same
        // chains), and a photon deposits at up to D intersections (gi's photon depth D).
        // Its photons per iteration and initial radius are gi's caustic photons per pass and
        // caustic radius; -1 photons (one per pixel) leaves gi's default, which follows the
        // image too.
        m_scene.render.maxPhotonDepth = int(std::clamp<long long>(depth, 2, 10001));
        long long photons = params.getInt("photonsperiteration", -1);
        if (photons > 100000000)
            failAt(loc, "Integrator \"sppm\": photonsperiteration above 10^8");
        if (photons > 0) m_scene.render.photonsPerPass = int(photons);
        double radius = params.getFloat("radius", 1.0);
        if (!(radius > 0) || !std::isfinite(radius))
            failAt(loc, "Integrator \"sppm\": radius must be positive");
        m_scene.render.photonRadius = float(radius);
    }
    for (const Param& p : params.all()) p.used = true; // the render mode decides the algorithm
}

void SceneBuilder::worldBegin(const SourceLoc& loc) {
    if (m_inWorld) failAt(loc, "a second WorldBegin");
    m_inWorld = true;
    m_worldFix = convertCamera(m_camera, m_film, m_scene, m_warnings, loc);
    reportUnused(m_camera.params, "Camera \"" + m_camera.type + "\"");
    reportUnused(m_film.params, "Film");
    m_scene.camera.filter = convertFilter(m_filter, m_warnings);
    reportUnused(m_filter.params, "PixelFilter \"" + m_filter.type + "\"");
    m_state.ctm = Mat4();
    m_coordSystems["world"] = Mat4();
}

void SceneBuilder::worldEnd(const SourceLoc& loc) {
    requireWorld("WorldEnd", loc);
}

} // namespace rayproc::pbrt
