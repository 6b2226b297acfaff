#include "serve/session.h"

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
#include "scene/camera_check.h"
#include "scene/scene_loader.h"
#include "scene/scene_loader_detail.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace rayproc::serve {

namespace {

// Two changes closer than kMotionGap are one drag (or key repeat, or wheel spin); then the
// full-size frame waits up to kMotionWait after the coarse one for the next change (the page
// sends it when the coarse frame arrives, or at the next event of a 60 Hz mouse: 17 ms).
constexpr std::chrono::milliseconds kMotionGap{250}, kMotionWait{50};
// A drag's coarse frames aim to take at most this (20 frames/s with the page's round trip):
// slower, the next is coarser (1/8, then 1/16 of each side); three times faster, finer again.
constexpr std::chrono::milliseconds kMotionFrame{40};

const std::vector<std::string> kMessageTypes = {
    "state", "camera", "pick", "transform", "material", "emission", "light",
    "undo", "redo", "save", "render", "cancel"};
constexpr std::size_t kUndoDepth = 256;

[[noreturn]] void refuse(const std::string& what) { throw InputError(what); }

const Json& field(const Json& m, const char* key, const char* type) {
    if (!m.contains(key)) refuse(std::string(type) + ": missing \"" + key + "\"");
    return m[key];
}

double finite(const Json& v, const std::string& where) {
    if (!v.is_number()) refuse(where + ": expected a number");
    double d = v.get<double>();
    if (!std::isfinite(d) || std::abs(d) > 3.0e38) refuse(where + ": expected a finite number");
    return d;
}

Vec3 vec3(const Json& v, const std::string& where) {
    if (!v.is_array() || v.size() != 3) refuse(where + ": expected an array of 3 numbers");
    return {float(finite(v[0], where)), float(finite(v[1], where)), float(finite(v[2], where))};
}

Json vec3Json(const Vec3& v) { return Json::array({double(v.x), double(v.y), double(v.z)}); }

// Keys a message may carry, besides "type".
void expectKeys(const Json& m, std::initializer_list<const char*> allowed) {
    for (auto it = m.begin(); it != m.end(); ++it) {
        if (it.key() == "type") continue;
        bool ok = false;
        for (const char* a : allowed) ok |= it.key() == a;
        if (!ok) refuse(m["type"].get<std::string>() + ": unknown key \"" + it.key() + "\"");
    }
}

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

} // namespace

std::vector<std::uint8_t> encodeFrame(const Image& image, std::uint32_t number,
                                      std::uint64_t version) {
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
    ToneMapSettings tm;
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
};

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
        loaded->scene = loadScene(scenePath);
        loaded->accel = std::make_unique<EmbreeScene>(*loaded->scene);
        loaded->bounds = sceneBounds(*loaded->scene);
        m_camera = loaded->scene->camera;
        m_loaded = loaded;
    }
    m_home = m_camera;
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

Json Session::reply(const Json& m, int client) {
    const std::string type = m["type"].get<std::string>();
    if (type == "state") {
        expectKeys(m, {});
        Json s = state();
        s["type"] = "state";
        return s;
    }
    if (type == "camera") {
        expectKeys(m, {"position", "look_at", "up", "fov", "undo_step"});
        bool undoStep = false;
        if (m.contains("undo_step")) {
            if (!m["undo_step"].is_boolean()) refuse("camera.undo_step: expected true or false");
            undoStep = m["undo_step"].get<bool>();
        }
        std::lock_guard<std::mutex> lk(m_mutex);
        if (m_rendering || m_request) refuse("camera: a render is running; cancel it first");
        Camera c = m_camera;
        if (m.contains("position")) c.position = vec3(m["position"], "camera.position");
        if (m.contains("look_at")) c.lookAt = vec3(m["look_at"], "camera.look_at");
        if (m.contains("up")) c.up = vec3(m["up"], "camera.up");
        if (m.contains("fov")) c.fovY = float(finite(m["fov"], "camera.fov"));
        // The check the scene loaders make: a camera serve accepts (and saves) renders.
        if (auto problem = cameraProblem(c))
            refuse("camera." + problem->field + ": " + problem->message);
        if (undoStep) pushUndo({std::nullopt, m_camera});
        setCamera(c);
        changed();
        // The version the new view's frames carry: the page sends its next view once one of
        // them has arrived.
        return {{"type", "camera"}, {"version", std::uint32_t(m_version)}};
    }
    if (type == "pick") {
        expectKeys(m, {"x", "y"});
        return pick(m);
    }
    if (type == "transform") {
        expectKeys(m, {"object", "translate", "rotate", "scale"});
        const Json& obj = field(m, "object", "transform");
        if (!obj.is_number_integer()) refuse("transform.object: expected an object index");
        long long index = obj.get<long long>();
        Affine edit = Affine::identity();
        Vec3 translate{0, 0, 0};
        if (m.contains("translate")) {
            translate = vec3(m["translate"], "transform.translate");
            // One move at most kMaxTranslate along each axis (the page's step is refused
            // beyond it too): 1e9 would put the object where Embree loses all precision.
            for (float t : {translate.x, translate.y, translate.z})
                if (!(std::abs(t) <= kMaxTranslate))
                    refuse("transform.translate: each component must be in [-" +
                           std::to_string(int(kMaxTranslate)) + ", " +
                           std::to_string(int(kMaxTranslate)) + "] (repeat a move to go further)");
        }
        Affine about = Affine::identity();
        if (m.contains("rotate")) {
            const Json& r = m["rotate"];
            if (!r.is_object()) refuse("transform.rotate: expected {\"angle\": degrees, \"axis\": [x, y, z]}");
            Vec3 axis = vec3(field(r, "axis", "transform.rotate"), "transform.rotate.axis");
            if (!(length(axis) > 0)) refuse("transform.rotate.axis: must not be zero");
            about = Affine::rotate(float(finite(field(r, "angle", "transform.rotate"), "transform.rotate.angle")), axis) * about;
        }
        if (m.contains("scale")) {
            double s = finite(m["scale"], "transform.scale");
            if (!(s > 1e-3 && s < 1e3)) refuse("transform.scale: expected a factor in (0.001, 1000)");
            about = Affine::scale(Vec3(float(s))) * about;
        }
        return applyEdit(m, [&](Json& doc) {
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
            edit = Affine::translate(translate) * Affine::translate(centre) * about *
                   Affine::translate(-centre) * old;
            Json matrix = Json::array();
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 4; ++c) matrix.push_back(double(edit.m[r][c]));
            node["transform"] = matrix;
        });
    }
    if (type == "material") {
        expectKeys(m, {"name", "material"});
        const Json& name = field(m, "name", "material");
        if (!name.is_string()) refuse("material.name: expected a string");
        const Json& value = field(m, "material", "material");
        if (!value.is_object()) refuse("material.material: expected a material object");
        return applyEdit(m, [&](Json& doc) {
            std::string n = name.get<std::string>();
            if (!doc.contains("materials") || !doc["materials"].contains(n))
                refuse("material.name: no material \"" + n + "\"");
            doc["materials"][n] = value;
        });
    }
    if (type == "emission") {
        expectKeys(m, {"object", "emission"});
        const Json& obj = field(m, "object", "emission");
        if (!obj.is_number_integer()) refuse("emission.object: expected an object index");
        long long index = obj.get<long long>();
        Vec3 e = vec3(field(m, "emission", "emission"), "emission.emission");
        return applyEdit(m, [&](Json& doc) {
            if (!doc.contains("nodes") || index < 0 || index >= (long long)doc["nodes"].size())
                refuse("emission.object: no object " + std::to_string(index));
            Json& node = doc["nodes"][std::size_t(index)];
            if (e.x == 0 && e.y == 0 && e.z == 0)
                node.erase("emission");
            else
                node["emission"] = vec3Json(e);
        });
    }
    if (type == "light") {
        expectKeys(m, {"index", "set"});
        const Json& idx = field(m, "index", "light");
        if (!idx.is_number_integer()) refuse("light.index: expected a light index");
        long long index = idx.get<long long>();
        const Json& set = field(m, "set", "light");
        if (!set.is_object()) refuse("light.set: expected an object of light fields");
        return applyEdit(m, [&](Json& doc) {
            if (!doc.contains("lights") || index < 0 || index >= (long long)doc["lights"].size())
                refuse("light.index: no light " + std::to_string(index));
            for (auto it = set.begin(); it != set.end(); ++it)
                doc["lights"][std::size_t(index)][it.key()] = it.value();
        });
    }
    if (type == "undo" || type == "redo") {
        expectKeys(m, {});
        std::lock_guard<std::mutex> lk(m_mutex);
        if (m_rendering || m_request) refuse(type + ": a render is running; cancel it first");
        std::vector<Step>& from = type == "undo" ? m_undo : m_redo;
        std::vector<Step>& to = type == "undo" ? m_redo : m_undo;
        if (from.empty()) refuse(type + ": nothing to " + type);
        Step back = swapStep(from.back());
        from.pop_back();
        to.push_back(std::move(back));
        return {{"type", "edited"}, {"undo_depth", m_undo.size()}, {"redo_depth", m_redo.size()}};
    }
    if (type == "save") {
        expectKeys(m, {"path"});
        const Json& p = field(m, "path", "save");
        if (!p.is_string() || p.get<std::string>().empty()) refuse("save.path: expected a file name");
        std::string path = p.get<std::string>();
        if (std::filesystem::path(path).extension() != ".json")
            refuse("save.path: the scene is saved as JSON: give a name ending in .json");
        std::string text;
        {
            std::lock_guard<std::mutex> lk(m_mutex);
            if (!m_editable) refuse("save: only JSON scenes can be saved (" + m_path + " is not one)");
            text = toText(m_doc, 2) + "\n";
        }
        try {
            writeFileAtomically(path, text);
        } catch (const ImageIoError& e) {
            refuse(std::string("save: ") + e.what());
        }
        return {{"type", "saved"}, {"path", std::filesystem::absolute(path).string()}};
    }
    if (type == "render") {
        expectKeys(m, {"mode", "spp"});
        const Json& mode = field(m, "mode", "render");
        if (!mode.is_string() || !findMode(mode.get<std::string>()))
            refuse("render.mode: expected preview, raytrace, gi or path");
        int spp = 0;
        if (m.contains("spp")) {
            if (!m["spp"].is_number_integer() || m["spp"].get<long long>() < 1 ||
                m["spp"].get<long long>() > 65536)
                refuse("render.spp: expected a whole number of samples in 1..65536");
            spp = m["spp"].get<int>();
        }
        std::lock_guard<std::mutex> lk(m_mutex);
        if (m_rendering || m_request) refuse("render: a render is already running");
        m_request = RenderRequest{mode.get<std::string>(), spp, client};
        m_wake.notify_all();
        return {{"type", "render_started"}, {"mode", mode}};
    }
    if (type == "cancel") {
        expectKeys(m, {});
        std::lock_guard<std::mutex> lk(m_mutex);
        if (!m_rendering && !m_request) refuse("cancel: no render is running");
        m_request.reset();
        if (m_rendering) requestInterrupt();
        return {{"type", "cancelling"}};
    }
    refuse("unknown message type \"" + type + "\"; known types: " +
           scene_json::joinNames(kMessageTypes));
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
    Json objects = Json::array();
    if (m_editable && m_doc.contains("nodes")) {
        for (std::size_t i = 0; i < m_doc["nodes"].size(); ++i) {
            const Json& n = m_doc["nodes"][i];
            Json o = {{"index", i}, {"type", n.value("type", "")}, {"name", n.value("name", "")}};
            if (n.contains("material")) o["material"] = n["material"];
            if (n.contains("emission")) o["emission"] = n["emission"];
            objects.push_back(o);
        }
    } else if (!m_editable) {
        // A pbrt scene: the objects a pick can name (the scene's top-level nodes), read-only,
        // so the page lists what the server picks.
        const Scene& scene = *m_loaded->scene;
        for (std::size_t i = 0; i < scene.root->children.size(); ++i) {
            const Node& n = *scene.root->children[i];
            const char* kind = n.kind == Node::Kind::Shape      ? "shape"
                               : n.kind == Node::Kind::Instance ? "instance"
                                                                : "group";
            objects.push_back({{"index", i}, {"type", kind}, {"name", n.name}});
        }
    }
    s["objects"] = objects;
    s["materials"] = m_editable && m_doc.contains("materials") ? m_doc["materials"] : Json::object();
    s["lights"] = m_editable && m_doc.contains("lights") ? m_doc["lights"] : Json::array();
    s["analysis"] = m_loaded->analysis;
    s["undo_depth"] = m_undo.size();
    s["redo_depth"] = m_redo.size();
    s["home"] = {{"position", vec3Json(m_home.position)},
                 {"look_at", vec3Json(m_home.lookAt)},
                 {"up", vec3Json(m_home.up)},
                 {"fov", double(m_home.fovY)}};
    // The page scales its fly, zoom and orbit pivot to the scene's extent.
    if (!m_loaded->bounds.empty()) s["bounds"] = m_loaded->bounds;
    s["rendering"] = m_rendering || m_request.has_value();
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
    if (m_request && m_request->client == client) m_request.reset();
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
    std::vector<std::uint8_t> frame = encodeFrame(image, ++m_frameNumber, version);
    // Checked and sent under the lock a change takes: a page that has the reply to its camera
    // move (or the state after it) gets no frame of the view before it.
    std::lock_guard<std::mutex> lk(m_frameMutex);
    if (m_version != version) return false;
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
        renderPreview(loaded, version);
        lk.lock();
        // A change during the render is shown by the next round.
        m_previewedVersion = version;
    }
}

void Session::renderPreview(const std::shared_ptr<Loaded>& loaded, std::uint64_t version) {
    Scene& scene = *loaded->scene;
    Camera full = scene.camera;
    // The live view's size: the scene's aspect, the longer side at most previewMaxSide.
    int maxSide = std::max(full.width, full.height);
    double shrink = std::min(1.0, double(m_options.previewMaxSide) / double(maxSide));
    int w = std::max(1, int(std::lround(full.width * shrink)));
    int h = std::max(1, int(std::lround(full.height * shrink)));
    EngineSettings engine;
    engine.threads = m_options.threads;
    engine.quiet = true;
    PreviewSettings settings = previewSettings(scene.render, {});
    // A newer change (a camera drag sends one per mouse move) makes this preview stale: it
    // stops emitting at once, through the engine's own stop rather than the interrupt, which
    // is Ctrl-C's and a render's Cancel.
    engine.stop = [this, version] {
        return m_version.load(std::memory_order_relaxed) != version ||
               m_quit.load(std::memory_order_relaxed);
    };
    // Coarse first (a quarter of each side; during a drag, coarser while frames take longer
    // than kMotionFrame), then full while nothing changed.
    bool motion;
    {
        std::lock_guard<std::mutex> lk(m_mutex);
        motion = m_lastChange - m_changeBefore < kMotionGap;
    }
    const int coarse = motion ? m_motionStep : 4;
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
                                                settings, engine);
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
    }
    scene.camera = full;
}

void Session::renderMode(const std::shared_ptr<Loaded>& loaded, const RenderRequest& request,
                         std::uint64_t version) {
    const Scene& scene = *loaded->scene;
    EngineSettings engine;
    engine.threads = m_options.threads;
    engine.quiet = true;
    // While the passes run, four times a second: the image with the tiles done so far, and
    // the progress.
    PeriodicReport watch(0.25, [&](const Film& film, const PeriodicReport::Progress& p) {
        sendFrame(film.resolveInProgress(), version);
        sendText({{"type", "progress"}, {"mode", request.mode}, {"fraction", p.fraction},
                  {"seconds", p.seconds},
                  {"eta_seconds", p.fraction > 0 ? p.seconds * (1 - p.fraction) / p.fraction : -1.0},
                  {"rays_per_second", p.seconds > 0 ? double(p.rays) / p.seconds : 0.0}});
    });
    engine.watcher = watch.watcher();
    ModeOverrides overrides{request.spp, 0, 0};
    sendText({{"type", "render_begin"}, {"mode", request.mode}});
    RenderResult r;
    try {
        r = findMode(request.mode)->render(scene, *loaded->accel,
                                           ModeSettings::forScene(scene, overrides), engine);
    } catch (const std::exception& e) {
        sendText({{"type", "error"}, {"message", std::string("render: ") + e.what()}});
        return;
    }
    sendFrame(r.image, version);
    {
        std::lock_guard<std::mutex> lk(m_mutex);
        m_lastRender = r.image;
    }
    Json stats = Json::parse(r.stats.toJson());
    sendText({{"type", "render_end"}, {"mode", request.mode}, {"cancelled", r.cancelled},
              {"spp", r.samplesDone}, {"seconds", r.stats.wallSeconds}, {"stats", stats}});
}

} // namespace rayproc::serve
