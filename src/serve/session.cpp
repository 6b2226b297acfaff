#include "serve/session.h"
#include "serve/session_detail.h"

#include "accel/embree_scene.h"
#include "core/error.h"
#include "engine/camera_emitter.h"
#include "engine/film.h"
#include "engine/cancel.h"
#include "engine/intersect.h"
#include "engine/ray_batch.h"
#include "kernels/camera_rays.h"
#include "modes/mode_registry.h"
#include "modes/modes.h"
#include "modes/render_plan.h"
#include "modes/render_watch.h"
#include "scene/pbrt/pbrt_loader.h"
#include "scene/pbrt/pbrt_spectrum.h"
#include "scene/scene_loader.h"
#include "scene/scene_loader_detail.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace rayproc::serve {

using namespace session_detail;

namespace {

// Two changes closer than kMotionGap are one drag (or key repeat, or wheel spin); then the
// full-size frame waits up to kMotionWait after the coarse one for the next change (the page
// sends it when the coarse frame arrives, or at the next event of a 60 Hz mouse: 17 ms).
constexpr std::chrono::milliseconds kMotionGap{250}, kMotionWait{50};
// A drag's coarse frames aim to take at most this (20 frames/s with the page's round trip):
// slower, the next is coarser (1/8, then 1/16 of each side); three times faster, finer again.
constexpr std::chrono::milliseconds kMotionFrame{40};
// A view unchanged this long after its last change refines (Session::refinePreview): longer
// than the gaps of a drag, a wheel spin or a key repeat (kMotionGap).
constexpr std::chrono::milliseconds kRefineRest{kMotionGap};

constexpr std::size_t kUndoDepth = 256;

// The top-level node an Embree hit belongs to: the node whose subtree holds the hit shape
// (instances: whose prototype does), the one whose bounds hold the hit point when several do.
bool holdsShape(const Node& node, const Shape* shape) {
    if (node.kind == Node::Kind::Shape) return &node.shape == shape;
    if (node.kind == Node::Kind::Instance) return node.prototype && holdsShape(*node.prototype, shape);
    for (const auto& c : node.children)
        if (holdsShape(*c, shape)) return true;
    return false;
}

// The scene's bounds and its extent, the length the page scales its navigation to: the
// diagonal of the box holding the middle 80% of the top-level objects' centres along each axis,
// at least the median object's diagonal and at most the bounds' own: a ground plane far wider
// than the room around it (Bitterli's classroom, docs/serve.md) does not set the scale.
Json sceneBounds(const Scene& scene) {
    Bounds3 all = scene.worldBounds();
    if (all.empty()) return Json::object();
    std::vector<float> xs, ys, zs, sizes;
    for (const auto& n : scene.root->children) {
        if (n->bounds.empty()) continue;
        Vec3 c = n->bounds.center();
        xs.push_back(c.x), ys.push_back(c.y), zs.push_back(c.z);
        sizes.push_back(length(n->bounds.hi - n->bounds.lo));
    }
    float diagonal = length(all.hi - all.lo), extent = diagonal;
    if (!sizes.empty()) {
        auto at = [](std::vector<float>& v, double q) {
            auto it = v.begin() + std::ptrdiff_t(q * double(v.size() - 1) + 0.5);
            std::nth_element(v.begin(), it, v.end());
            return *it;
        };
        Vec3 lo{at(xs, 0.1), at(ys, 0.1), at(zs, 0.1)}, hi{at(xs, 0.9), at(ys, 0.9), at(zs, 0.9)};
        extent = std::min(diagonal, std::max(length(hi - lo), at(sizes, 0.5)));
    }
    return {{"lo", vec3Json(all.lo)}, {"hi", vec3Json(all.hi)}, {"extent", double(extent)}};
}

// A pbrt scene's lights without geometry (the sun, the sky...) in the JSON scene format's
// terms, read-only: the page's lights panel lists them.
Json sceneLightsJson(const Scene& scene) {
    Json lights = Json::array();
    for (const Light& l : scene.lights) {
        Json j;
        switch (l.type) {
        case LightType::Point: j = {{"type", "point"}, {"intensity", vec3Json(l.intensity)}}; break;
        case LightType::Spot: j = {{"type", "spot"}, {"intensity", vec3Json(l.intensity)}}; break;
        case LightType::Directional:
            j = {{"type", "directional"}, {"irradiance", vec3Json(l.intensity)},
                 {"direction", vec3Json(l.direction)}};
            break;
        case LightType::Environment: j = {{"type", "environment"}, {"radiance", vec3Json(l.intensity)}}; break;
        case LightType::Goniometric: j = {{"type", "goniometric"}, {"intensity", vec3Json(l.intensity)}}; break;
        }
        if (!l.name.empty()) j["name"] = l.name;
        if (!l.imageFile.empty()) j["image"] = l.imageFile;
        lights.push_back(j);
    }
    return lights;
}

// A JSON scene's lights as written; a blackbody colour ({"blackbody": K, "scale": s}) also as
// the RGB that RGB mode renders ("<key>_rgb"), which the page's three fields show: setting them
// replaces the blackbody by that RGB (docs/serve.md).
Json docLightsJson(const Json& doc) {
    Json lights = doc.contains("lights") ? doc["lights"] : Json::array();
    for (Json& l : lights) {
        if (!l.is_object()) continue;
        for (const char* key : {"intensity", "radiance", "irradiance"}) {
            const Json* c = l.contains(key) ? &l[key] : nullptr;
            if (!c || !c->is_object() || !c->contains("blackbody") || !(*c)["blackbody"].is_number())
                continue;
            const double scale = c->contains("scale") && (*c)["scale"].is_number()
                                     ? (*c)["scale"].get<double>()
                                     : 1.0;
            l[std::string(key) + "_rgb"] =
                vec3Json(pbrt::blackbodyRgb((*c)["blackbody"].get<double>()) * float(scale));
        }
    }
    return lights;
}

} // namespace

std::vector<std::uint8_t> encodeFrame(const Image& image, std::uint32_t number,
                                      std::uint64_t version, const ToneMapSettings& tm) {
    constexpr std::size_t h = kFrameHeaderBytes;
    std::vector<std::uint8_t> out(h + std::size_t(image.width) * std::size_t(image.height) * 4);
    auto put = [&](std::size_t at, std::uint32_t v) {
        for (int b = 0; b < 4; ++b) out[at + std::size_t(b)] = std::uint8_t(v >> (8 * b));
    };
    out[0] = 'R', out[1] = 'P', out[2] = 'F', out[3] = '2';
    put(4, std::uint32_t(image.width));
    put(8, std::uint32_t(image.height));
    put(12, number);
    put(16, std::uint32_t(version));
    std::size_t n = std::size_t(image.width) * std::size_t(image.height);
    for (std::size_t p = 0; p < n; ++p) {
        for (int c = 0; c < 3; ++c)
            out[h + p * 4 + std::size_t(c)] = toSrgb8(image.pixels[p * 3 + std::size_t(c)], tm);
        out[h + p * 4 + 3] = 255;
    }
    return out;
}

std::string toText(const Json& json, int indent) {
    return json.dump(indent, ' ', false, Json::error_handler_t::replace);
}

struct Session::Loaded {
    std::unique_ptr<Scene> scene;
    std::unique_ptr<EmbreeScene> accel;
    std::optional<LightSet> previewLights; // made at the first preview, kept for every frame
    Json analysis = Json::array();         // what each mode skips and why
    Json bounds;                           // the page's scale (sceneBounds)
    Json defaultSpp;                       // per mode, without an spp (state's default_spp)
};

namespace {

// Read at load: the worker thread changes the scene's camera later, state() must not read it.
Json defaultSppOf(const Scene& scene) {
    return {{"raytrace", raytraceSettings(scene.render, {}).spp},
            {"gi", giSettings(scene, {}).spp},
            {"path", pathSettings(scene.render, {}).spp}};
}

} // namespace

Session::Session(const std::string& scenePath, const Options& options)
    : m_path(scenePath), m_options(options) {
    m_editable = std::filesystem::path(scenePath).extension() == ".json";
    if (m_editable) {
        std::ifstream in(scenePath, std::ios::binary);
        if (!in) refuse("cannot read " + scenePath);
        std::stringstream text;
        text << in.rdbuf();
        try {
            m_doc = Json::parse(text.str());
        } catch (const Json::exception&) {
            // The loader says where the syntax error is.
            loadSceneFromString(text.str(), scenePath);
            throw;
        }
        load(m_doc);
    } else {
        auto loaded = std::make_shared<Loaded>();
        // The pbrt loader's warnings (a missing texture, an unsupported material...) go to
        // the page, and to stderr as `rayproc render` prints them.
        if (isPbrtPath(scenePath)) {
            loaded->scene = loadPbrtScene(scenePath, &m_warnings);
            for (const std::string& w : m_warnings) std::fprintf(stderr, "%s\n", w.c_str());
        } else {
            loaded->scene = loadScene(scenePath);
        }
        loaded->accel = std::make_unique<EmbreeScene>(*loaded->scene);
        loaded->bounds = sceneBounds(*loaded->scene);
        loaded->defaultSpp = defaultSppOf(*loaded->scene);
        m_camera = loaded->scene->camera;
        m_loaded = loaded;
    }
    m_home = m_camera;
    m_spectralView = m_loaded->scene->render.spectral;
    m_version = 1;
}

Session::~Session() { stop(); }

void Session::stop() {
    {
        std::lock_guard<std::mutex> lk(m_mutex);
        m_quit = true;
        if (m_rendering) requestInterrupt();
    }
    m_wake.notify_all();
    m_idle.notify_all();
    if (m_thread.joinable()) {
        m_thread.join();
        clearRequestedInterrupt();
    }
}

void Session::start(Events events) {
    m_events = std::move(events);
    m_thread = std::thread([this] { worker(); });
}

void Session::load(const Json& doc) {
    auto loaded = std::make_shared<Loaded>();
    loaded->scene = loadSceneFromString(doc.dump(), m_path);
    try {
        loaded->accel = std::make_unique<EmbreeScene>(*loaded->scene);
    } catch (const InputError& e) {
        refuse(m_path + ": " + e.what());
    }
    // The scene analysis of each mode, for the page.
    EngineSettings quiet;
    quiet.quiet = true;
    LightSet lights = LightSet::build(*loaded->scene, *loaded->accel);
    RenderPlan plan = planRender(*loaded->scene, *loaded->accel, lights, quiet, kPlanAllModes);
    for (const PlanSkip& s : plan.skipped) {
        Json modes = Json::array();
        for (auto [bit, name] : {std::pair{kPlanPreview, "preview"}, {kPlanRaytrace, "raytrace"},
                                 {kPlanGi, "gi"}, {kPlanPath, "path"}})
            if (s.modes & bit) modes.push_back(name);
        loaded->analysis.push_back({{"what", s.what}, {"why", s.why}, {"modes", modes}});
    }
    loaded->bounds = sceneBounds(*loaded->scene);
    loaded->defaultSpp = defaultSppOf(*loaded->scene);
    m_camera = loaded->scene->camera;
    m_loaded = loaded;
}

std::string Session::handle(const std::string& message, int client) {
    Json out;
    try {
        Json m;
        try {
            m = Json::parse(message);
        } catch (const Json::parse_error& e) {
            refuse(std::string("malformed message (not JSON): ") + e.what());
        }
        if (!m.is_object() || !m.contains("type") || !m["type"].is_string())
            refuse("a message is an object with a \"type\" string; known types: " +
                   scene_json::joinNames(kMessageTypes));
        out = reply(m, client);
    } catch (const InputError& e) {
        out = {{"type", "error"}, {"message", e.what()}};
    } catch (const Json::exception& e) {
        out = {{"type", "error"}, {"message", std::string("malformed message: ") + e.what()}};
    } catch (const std::exception& e) {
        // Whatever else a message runs into is its error, never the server's end.
        out = {{"type", "error"}, {"message", std::string("the message failed: ") + e.what()}};
    }
    return toText(out);
}

Json Session::applyEdit(const Json& m, const std::function<void(Json& doc)>& edit) {
    std::lock_guard<std::mutex> lk(m_mutex);
    if (!m_editable)
        refuse(m["type"].get<std::string>() + ": only JSON scenes can be edited (" + m_path +
               " is not one); the camera, renders and downloads still work");
    if (m_rendering || m_request)
        refuse(m["type"].get<std::string>() + ": a render is running; cancel it first");
    Json doc = m_doc;
    edit(doc);
    Camera view = m_camera;
    load(doc); // throws, with the loader's message, before anything changes
    m_camera = view;
    // The view is the page's: it survives edits, and the saved file keeps it.
    pushUndo({std::move(m_doc), std::nullopt});
    m_doc = std::move(doc);
    changed();
    return {{"type", "edited"}, {"undo_depth", m_undo.size()}};
}

void Session::pushUndo(Step step) {
    m_undo.push_back(std::move(step));
    if (m_undo.size() > kUndoDepth) m_undo.erase(m_undo.begin());
    m_redo.clear();
}

void Session::setCamera(const Camera& c) {
    m_camera = c;
    if (!m_editable) return;
    Json& cam = m_doc["camera"];
    cam["position"] = vec3Json(c.position);
    cam["look_at"] = vec3Json(c.lookAt);
    cam["up"] = vec3Json(c.up);
    cam["fov"] = double(c.fovY);
    cam["resolution"] = {c.width, c.height};
}

Session::Step Session::swapStep(const Step& step) {
    Step back;
    if (step.doc) {
        Camera view = m_camera;
        load(*step.doc); // loaded once before; should it fail now, it throws before any change
        back.doc = std::move(m_doc);
        m_doc = *step.doc;
        setCamera(view); // the view stays the page's, in the document too
    }
    if (step.camera) {
        back.camera = m_camera;
        setCamera(*step.camera);
    }
    changed();
    return back;
}

void Session::transformNode(Json& doc, long long index, const Vec3& translate,
                            const Affine& about) const {
    if (!doc.contains("nodes") || index < 0 || index >= (long long)doc["nodes"].size())
        refuse("transform.object: no object " + std::to_string(index));
    Json& node = doc["nodes"][std::size_t(index)];
    std::string file = m_path;
    Affine old = Affine::identity();
    if (node.contains("transform"))
        old = scene_json::parseTransform(scene_json::JsonRef(
            node["transform"], file, "/nodes/" + std::to_string(index) + "/transform"));
    // Rotation and scale about the object's centre (its bounds in the world), then
    // the translation: new = T * C * R S * C^-1 * old.
    Vec3 centre{0, 0, 0};
    const Scene& scene = *m_loaded->scene; // applyEdit holds the lock
    if (std::size_t(index) < scene.root->children.size())
        centre = scene.root->children[std::size_t(index)]->bounds.center();
    Affine edit = Affine::translate(translate) * Affine::translate(centre) * about *
                  Affine::translate(-centre) * old;
    Json matrix = Json::array();
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) matrix.push_back(double(edit.m[r][c]));
    node["transform"] = matrix;
}

Json Session::pick(const Json& m) const {
    double x = finite(field(m, "x", "pick"), "pick.x"), y = finite(field(m, "y", "pick"), "pick.y");
    if (!(x >= 0 && x <= 1 && y >= 0 && y <= 1))
        refuse("pick: x and y are fractions of the image's width and height, in [0, 1]");
    std::shared_ptr<Loaded> loaded;
    Camera cam;
    {
        std::lock_guard<std::mutex> lk(m_mutex);
        loaded = m_loaded;
        cam = m_camera;
    }
    // One camera ray through the engine's intersection handler.
    kernels::CameraFrame frame = cameraFrame(cam);
    float fx = float(x) * float(cam.width), fy = float(y) * float(cam.height), lu = 0.5f, lv = 0.5f;
    auto batch = std::make_unique<RayBatch>();
    batch->push(0, 0, 0, 0, 0, 1, 0.0f, kInfinity);
    kernels::generateCameraRays(frame, 1, &fx, &fy, &lu, &lv, batch->ox.data(), batch->oy.data(),
                                batch->oz.data(), batch->dx.data(), batch->dy.data(),
                                batch->dz.data());
    Intersector intersector(loaded->accel->root(), 1);
    ThreadStats stats;
    intersector.trace(*batch, stats);
    Json out = {{"type", "picked"}, {"object", nullptr}};
    if (!batch->hit(0)) return out;
    Vec3 o{batch->ox[0], batch->oy[0], batch->oz[0]}, d{batch->dx[0], batch->dy[0], batch->dz[0]};
    SurfaceHit h = loaded->accel->surface(batch->instId[0], batch->geomId[0], batch->primId[0],
                                          batch->u[0], batch->v[0], o, d, batch->t[0]);
    const Scene& scene = *loaded->scene;
    int found = -1;
    for (std::size_t i = 0; i < scene.root->children.size(); ++i) {
        const Node& n = *scene.root->children[i];
        if (!holdsShape(n, h.shape)) continue;
        Bounds3 b = n.bounds;
        bool inside = b.empty() || (h.p.x >= b.lo.x - 1e-3f * (1 + std::abs(h.p.x)) &&
                                    h.p.x <= b.hi.x + 1e-3f * (1 + std::abs(h.p.x)) &&
                                    h.p.y >= b.lo.y - 1e-3f * (1 + std::abs(h.p.y)) &&
                                    h.p.y <= b.hi.y + 1e-3f * (1 + std::abs(h.p.y)) &&
                                    h.p.z >= b.lo.z - 1e-3f * (1 + std::abs(h.p.z)) &&
                                    h.p.z <= b.hi.z + 1e-3f * (1 + std::abs(h.p.z)));
        if (found < 0 || inside) found = int(i);
        if (inside) break;
    }
    out["point"] = vec3Json(h.p);
    out["shape"] = h.shape ? h.shape->name : "";
    if (h.material >= 0 && std::size_t(h.material) < scene.materials.size())
        out["material"] = scene.materials[std::size_t(h.material)].name;
    if (found >= 0) {
        out["object"] = found;
        out["name"] = scene.root->children[std::size_t(found)]->name;
    }
    return out;
}

std::string Session::previewSizeNote(int requested) const {
    std::lock_guard<std::mutex> lk(m_mutex);
    int longer = std::max(m_camera.width, m_camera.height);
    if (requested <= longer) return "";
    return "--preview-size " + std::to_string(requested) + " is above the scene's resolution (" +
           std::to_string(m_camera.width) + "x" + std::to_string(m_camera.height) +
           "): the live preview is " + std::to_string(m_camera.width) + "x" +
           std::to_string(m_camera.height) + ", at most the scene's resolution (raise the " +
           "camera's resolution in the scene for a larger one)";
}

// The objects a page lists: a JSON scene's nodes (editable); a pbrt scene's top-level nodes
// (the objects a pick can name), read-only. m_mutex held.
Json Session::objectsJson() const {
    Json objects = Json::array();
    // Each top-level object's world bounds: the page draws the selection's box over the image.
    const auto& nodes = m_loaded->scene->root->children;
    auto withBounds = [&](Json o, std::size_t i) {
        if (i < nodes.size() && !nodes[i]->bounds.empty())
            o["bounds"] = {{"lo", vec3Json(nodes[i]->bounds.lo)}, {"hi", vec3Json(nodes[i]->bounds.hi)}};
        return o;
    };
    if (m_editable && m_doc.contains("nodes")) {
        for (std::size_t i = 0; i < m_doc["nodes"].size(); ++i) {
            const Json& n = m_doc["nodes"][i];
            Json o = {{"index", i}, {"type", n.value("type", "")}, {"name", n.value("name", "")}};
            if (n.contains("material")) o["material"] = n["material"];
            if (n.contains("emission")) o["emission"] = n["emission"];
            objects.push_back(withBounds(o, i));
        }
    } else if (!m_editable) {
        const Scene& scene = *m_loaded->scene;
        for (std::size_t i = 0; i < scene.root->children.size(); ++i) {
            const Node& n = *scene.root->children[i];
            const char* kind = n.kind == Node::Kind::Shape      ? "shape"
                               : n.kind == Node::Kind::Instance ? "instance"
                                                                : "group";
            objects.push_back(withBounds({{"index", i}, {"type", kind}, {"name", n.name}}, i));
        }
    }
    return objects;
}

Json Session::state() const {
    std::lock_guard<std::mutex> lk(m_mutex);
    Json s;
    s["scene"] = m_path;
    s["editable"] = m_editable;
    s["preview_max_side"] = m_options.previewMaxSide;
    s["camera"] = {{"position", vec3Json(m_camera.position)},
                   {"look_at", vec3Json(m_camera.lookAt)},
                   {"up", vec3Json(m_camera.up)},
                   {"fov", double(m_camera.fovY)},
                   {"resolution", {m_camera.width, m_camera.height}}};
    s["objects"] = objectsJson();
    s["materials"] = m_editable && m_doc.contains("materials") ? m_doc["materials"] : Json::object();
    // A pbrt scene's lights are listed read-only (the sun and the sky among them).
    s["lights"] = m_editable ? docLightsJson(m_doc) : sceneLightsJson(*m_loaded->scene);
    s["warnings"] = m_warnings;
    s["analysis"] = m_loaded->analysis;
    // The samples per pixel a render takes when the page gives none, per mode.
    s["default_spp"] = m_loaded->defaultSpp;
    s["undo_depth"] = m_undo.size();
    s["redo_depth"] = m_redo.size();
    s["home"] = {{"position", vec3Json(m_home.position)},
                 {"look_at", vec3Json(m_home.lookAt)},
                 {"up", vec3Json(m_home.up)},
                 {"fov", double(m_home.fovY)}};
    // The page scales its fly, zoom and orbit pivot to the scene's extent.
    if (!m_loaded->bounds.empty()) s["bounds"] = m_loaded->bounds;
    s["rendering"] = m_rendering || m_request.has_value();
    s["spectral_view"] = m_spectralView;
    s["refine"] = m_options.refine;
    {
        std::lock_guard<std::mutex> frames(m_frameMutex);
        s["display"] = displayJson(m_display);
    }
    s["version"] = std::uint32_t(m_version); // as in the frames' header
    return s;
}

bool Session::lastFrame(Image& out, std::uint64_t* version) const {
    std::lock_guard<std::mutex> lk(m_frameMutex);
    if (m_lastImage.width == 0) return false;
    out = m_lastImage;
    if (version) *version = m_lastImageVersion;
    return true;
}

bool Session::lastRender(Image& out) const {
    std::lock_guard<std::mutex> lk(m_mutex);
    if (m_lastRender.width == 0) return false;
    out = m_lastRender;
    return true;
}

void Session::clientClosed(int client) {
    std::lock_guard<std::mutex> lk(m_mutex);
    if (m_request && m_request->client == client) {
        m_request.reset();
        m_requestPending = false;
    }
    if (m_rendering && m_renderClient == client) requestInterrupt();
}

void Session::waitIdle() {
    std::unique_lock<std::mutex> lk(m_mutex);
    m_idle.wait(lk, [&] {
        return m_quit || (!m_busy && !m_request && m_version == m_previewedVersion);
    });
}

void Session::sendText(const Json& json) const {
    if (m_events.text) m_events.text(toText(json));
}

void Session::changed() {
    m_changeBefore = m_lastChange;
    m_lastChange = std::chrono::steady_clock::now();
    {
        std::lock_guard<std::mutex> frames(m_frameMutex);
        ++m_version;
    }
    m_wake.notify_all();
}

bool Session::sendFrame(Image image, std::uint64_t version) {
    // Encoded before the lock, so a camera message (which takes it) does not wait for that.
    ToneMapSettings tm = display();
    std::vector<std::uint8_t> frame = encodeFrame(image, ++m_frameNumber, version, tm);
    // Checked and sent under the lock a change takes: a page that has the reply to its camera
    // move (or the state after it) gets no frame of the view before it.
    std::lock_guard<std::mutex> lk(m_frameMutex);
    if (m_version != version) return false;
    if (m_display.exposure != tm.exposure || m_display.op != tm.op) // changed meanwhile
        frame = encodeFrame(image, m_frameNumber, version, m_display);
    m_lastImage = std::move(image);
    m_lastImageVersion = version;
    if (m_events.frame) m_events.frame(frame);
    return true;
}

void Session::worker() {
    std::unique_lock<std::mutex> lk(m_mutex);
    for (;;) {
        m_busy = false;
        m_idle.notify_all();
        m_wake.wait(lk, [&] { return m_quit || m_request || m_version != m_previewedVersion; });
        if (m_quit) return;
        m_busy = true;
        std::shared_ptr<Loaded> loaded = m_loaded;
        Camera view = m_camera;
        std::uint64_t version = m_version;
        if (m_request) {
            RenderRequest request = *m_request;
            m_request.reset();
            m_requestPending = false;
            m_rendering = true;
            m_renderClient = request.client;
            lk.unlock();
            loaded->scene->camera = view; // only this thread touches the scene's camera
            renderMode(loaded, request, version);
            lk.lock();
            m_rendering = false;
            m_renderClient = -1;
            // A finished render stays on screen until the next change; a cancelled one
            // returns to the live preview at once.
            bool cancelled = interruptRequested();
            clearRequestedInterrupt(); // a Ctrl-C to the server stays: it is shutting down
            m_previewedVersion = cancelled ? 0 : m_version.load();
            continue;
        }
        lk.unlock();
        loaded->scene->camera = view;
        bool shown = renderPreview(loaded, version);
        lk.lock();
        // A change during the render is shown by the next round.
        m_previewedVersion = version;
        if (!shown || !m_options.refine) continue;
        // The preview is on screen (waitIdle returns); once the view has rested for
        // kRefineRest, its raytrace passes follow. A drag's changes come faster than that.
        m_busy = false;
        m_idle.notify_all();
        bool moved = m_wake.wait_until(lk, m_lastChange + kRefineRest, [&] {
            return m_quit || m_request || m_version != version;
        });
        if (moved) continue;
        // Not busy while refining: waitIdle (tests) waits for the preview, not the passes.
        lk.unlock();
        loaded->scene->camera = view;
        refinePreview(loaded, version);
        lk.lock();
    }
}

void Session::previewSize(const Camera& full, int& width, int& height) const {
    int maxSide = std::max(full.width, full.height);
    double shrink = std::min(1.0, double(m_options.previewMaxSide) / double(maxSide));
    width = std::max(1, int(std::lround(full.width * shrink)));
    height = std::max(1, int(std::lround(full.height * shrink)));
}

std::function<bool()> Session::staleStop(std::uint64_t version) const {
    // Atomics only: the render's threads poll it before each emission.
    return [this, version] {
        return m_version.load(std::memory_order_relaxed) != version ||
               m_requestPending.load(std::memory_order_relaxed) ||
               m_quit.load(std::memory_order_relaxed);
    };
}

// Cycles' viewport does the same: a still view keeps improving. raytrace mode (soft shadows,
// antialiasing, the mode's spp) renders at the preview's size, and the image after each pass
// goes out as a frame of the same version, followed by a "refine" message with the samples so
// far; the last one ("done") is the raytrace render of that view at that size.
void Session::refinePreview(const std::shared_ptr<Loaded>& loaded, std::uint64_t version) {
    Scene& scene = *loaded->scene;
    const Camera full = scene.camera;
    previewSize(full, scene.camera.width, scene.camera.height);
    EngineSettings engine;
    engine.threads = m_options.threads;
    engine.quiet = true;
    engine.spectral = spectralView();
    RenderControl control;
    control.stop = staleStop(version);
    control.progressiveSeconds = 0; // every pass
    const RaytraceSettings settings = raytraceSettings(scene.render, {});
    std::function<double()> fraction; // of the passes done, while they run
    RenderControl::Watcher watcher{
        [&](std::function<Image()>, std::function<double()> f, std::function<std::uint64_t()>) {
            fraction = std::move(f);
        },
        [&] { fraction = nullptr; }};
    control.watcher = &watcher;
    auto send = [&](Image image, int spp, bool done) {
        if (!sendFrame(std::move(image), version)) return;
        sendText({{"type", "refine"}, {"version", std::uint32_t(version)}, {"spp", spp},
                  {"of", settings.spp}, {"done", done}});
    };
    control.onProgress = [&](const Image& image) {
        double f = fraction ? fraction() : 0.0;
        send(image, int(std::lround(f * settings.spp)), false);
    };
    RenderResult r;
    try {
        r = renderRaytrace(scene, *loaded->accel, settings, engine, control);
    } catch (const std::exception& e) {
        sendText({{"type", "error"}, {"message", std::string("refining the view: ") + e.what()}});
        r.cancelled = true;
    }
    if (!r.cancelled) send(std::move(r.image), r.samplesDone, true);
    scene.camera = full;
}

bool Session::renderPreview(const std::shared_ptr<Loaded>& loaded, std::uint64_t version) {
    Scene& scene = *loaded->scene;
    Camera full = scene.camera;
    // The live view's size: the scene's aspect, the longer side at most previewMaxSide.
    int w = 0, h = 0;
    previewSize(full, w, h);
    EngineSettings engine;
    engine.threads = m_options.threads;
    engine.quiet = true;
    engine.spectral = spectralView();
    PreviewSettings settings = previewSettings(scene.render, {});
    // A newer change (a camera drag sends one per mouse move) makes this preview stale: it
    // stops emitting at once, through the engine's own stop rather than the interrupt, which
    // is Ctrl-C's and a render's Cancel.
    RenderControl control;
    control.stop = staleStop(version);
    // Coarse first (a quarter of each side; during a drag, coarser while frames take longer
    // than kMotionFrame), then full while nothing changed.
    bool motion;
    {
        std::lock_guard<std::mutex> lk(m_mutex);
        motion = m_lastChange - m_changeBefore < kMotionGap;
    }
    const int coarse = motion ? m_motionStep : 4;
    bool fullSent = false;
    for (int step : {coarse, 1}) {
        {
            std::unique_lock<std::mutex> lk(m_mutex);
            // During a drag (changes less than kMotionGap apart) the page sends its next view
            // once the coarse frame arrives: wait for it rather than start a full-size frame
            // that it would stop, whose setup and teardown cost as much as a coarse frame.
            if (step == 1 && motion)
                m_wake.wait_for(lk, kMotionWait, [&] {
                    return m_version != version || m_request || m_quit;
                });
            if (m_version != version || m_request || m_quit) break;
        }
        scene.camera.width = std::max(1, w / step);
        scene.camera.height = std::max(1, h / step);
        if (!loaded->previewLights) // only this thread renders previews
            loaded->previewLights = LightSet::buildPreview(scene, *loaded->accel);
        auto start = std::chrono::steady_clock::now();
        ++m_previewsStarted;
        RenderResult r = rayproc::renderPreview(scene, *loaded->accel, *loaded->previewLights,
                                                settings, engine, control);
        if (r.cancelled) ++m_previewsStopped;
        if (step > 1 && motion) {
            // A coarse frame that the next change stopped was too slow for the changes' pace
            // (a client that does not wait for frames, as the page does): the next is coarser,
            // so frames still come.
            auto took = std::chrono::steady_clock::now() - start;
            if ((r.cancelled || took > kMotionFrame) && m_motionStep < 16) m_motionStep *= 2;
            else if (!r.cancelled && took < kMotionFrame / 3 && m_motionStep > 4) m_motionStep /= 2;
        }
        if (r.cancelled || !sendFrame(std::move(r.image), version)) break;
        fullSent = step == 1;
    }
    scene.camera = full;
    return fullSent;
}

// Until a render's passes begin (gi traces its photons and fills its irradiance cache first:
// seconds on a large scene), the page hears that it is starting, at once and then every
// quarter second.
class Session::StartingTicker {
public:
    StartingTicker(const Session& session, const std::string& mode) {
        auto start = std::chrono::steady_clock::now();
        m_thread = std::thread([this, &session, mode, start] {
            std::unique_lock<std::mutex> lk(m_mutex);
            do { // at once, then every quarter second
                double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
                session.sendText({{"type", "progress"}, {"mode", mode}, {"phase", "starting"},
                                  {"what", mode == "gi" ? "photon passes, irradiance cache prepass"
                                                        : "light set, scene analysis"},
                                  {"seconds", seconds}, {"fraction", 0.0}});
            } while (!m_wake.wait_for(lk, std::chrono::milliseconds(250), [&] { return m_done; }));
        });
    }
    ~StartingTicker() { stop(); }
    void stop() {
        {
            std::lock_guard<std::mutex> lk(m_mutex);
            m_done = true;
        }
        m_wake.notify_all();
        if (m_thread.joinable()) m_thread.join();
    }

private:
    std::mutex m_mutex;
    std::condition_variable m_wake;
    bool m_done = false;
    std::thread m_thread;
};

void Session::renderMode(const std::shared_ptr<Loaded>& loaded, const RenderRequest& request,
                         std::uint64_t version) {
    const Scene& scene = *loaded->scene;
    EngineSettings engine;
    engine.threads = m_options.threads;
    engine.quiet = true;
    engine.spectral = request.spectral;
    // While the passes run, four times a second: the image with the tiles done so far, and
    // the progress. Before them, the StartingTicker's messages.
    PeriodicReport watch(0.25, [&](Image image, const PeriodicReport::Progress& p) {
        sendFrame(std::move(image), version);
        sendText({{"type", "progress"}, {"mode", request.mode}, {"fraction", p.fraction},
                  {"seconds", p.seconds},
                  {"eta_seconds", p.fraction > 0 ? p.seconds * (1 - p.fraction) / p.fraction : -1.0},
                  {"rays_per_second", p.seconds > 0 ? double(p.rays) / p.seconds : 0.0}});
    });
    sendText({{"type", "render_begin"}, {"mode", request.mode}, {"spectral", request.spectral}});
    StartingTicker starting(*this, request.mode);
    const RenderControl::Watcher* report = watch.watcher();
    RenderControl::Watcher watcher{
        [&](std::function<Image()> image, std::function<double()> fraction,
            std::function<std::uint64_t()> rays) {
            starting.stop();
            report->begin(std::move(image), std::move(fraction), std::move(rays));
        },
        [&] { report->end(); }};
    RenderControl control;
    control.watcher = &watcher;
    RenderResult r;
    try {
        r = runMode(scene, *loaded->accel, request, engine, control);
    } catch (const std::exception& e) {
        starting.stop();
        sendText({{"type", "error"}, {"message", std::string("render: ") + e.what()}});
        return;
    }
    starting.stop();
    sendFrame(r.image, version);
    {
        std::lock_guard<std::mutex> lk(m_mutex);
        m_lastRender = r.image;
    }
    Json stats = Json::parse(r.stats.toJson());
    sendText({{"type", "render_end"}, {"mode", request.mode}, {"cancelled", r.cancelled},
              {"spp", r.samplesDone}, {"seconds", r.stats.wallSeconds}, {"stats", stats}});
}

RenderResult Session::runMode(const Scene& scene, const EmbreeScene& accel,
                              const RenderRequest& request, const EngineSettings& engine,
                              const RenderControl& control) {
    ModeOverrides overrides{request.spp, 0, 0};
    return findMode(request.mode)->render(scene, accel, ModeSettings::forScene(scene, overrides),
                                          engine, control);
}

} // namespace rayproc::serve
