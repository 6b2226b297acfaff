// Session's answers to the page's messages (docs/serve.md, "Messages"): one function per type,
// each checking its message field by field before anything changes.
#include "serve/session.h"
#include "serve/session_detail.h"

#include "engine/cancel.h"
#include "image/image.h"
#include "modes/mode_registry.h"
#include "scene/camera_check.h"
#include "scene/scene_loader_detail.h"

#include <filesystem>
#include <mutex>

namespace rayproc::serve {

using namespace session_detail;

// Each message type is answered by its own function (docs/serve.md lists them).
Json Session::reply(const Json& m, int client) {
    using Handler = Json (Session::*)(const Json&, int);
    static const std::vector<std::pair<std::string, Handler>> handlers = {
        {"state", &Session::replyState},       {"camera", &Session::replyCamera},
        {"pick", &Session::replyPick},         {"transform", &Session::replyTransform},
        {"material", &Session::replyMaterial}, {"emission", &Session::replyEmission},
        {"light", &Session::replyLight},       {"undo", &Session::replyUndoRedo},
        {"redo", &Session::replyUndoRedo},     {"save", &Session::replySave},
        {"render", &Session::replyRender},     {"cancel", &Session::replyCancel},
        {"display", &Session::replyDisplay},   {"view", &Session::replyView}};
    const std::string type = m["type"].get<std::string>();
    for (const auto& [name, handler] : handlers)
        if (name == type) return (this->*handler)(m, client);
    refuse("unknown message type \"" + type + "\"; known types: " +
           scene_json::joinNames(kMessageTypes));
}

Json Session::replyState(const Json& m, int) {
    expectKeys(m, {});
    Json s = state();
    s["type"] = "state";
    return s;
}

Json Session::replyCamera(const Json& m, int) {
    expectKeys(m, {"position", "look_at", "up", "fov", "resolution", "undo_step"});
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
    if (m.contains("resolution")) {
        const Json& r = m["resolution"];
        auto side = [&](std::size_t i) {
            if (!r[i].is_number_integer() || r[i].get<long long>() < 1 || r[i].get<long long>() > 16384)
                refuse("camera.resolution: expected [width, height], whole numbers in 1..16384");
            return r[i].get<int>();
        };
        if (!r.is_array() || r.size() != 2)
            refuse("camera.resolution: expected [width, height], whole numbers in 1..16384");
        c.width = side(0);
        c.height = side(1);
    }
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

Json Session::replyPick(const Json& m, int) {
    expectKeys(m, {"x", "y"});
    return pick(m);
}

// A move, a rotation and a scale of one top-level object, as a new transform in the document.
Json Session::replyTransform(const Json& m, int) {
    expectKeys(m, {"object", "translate", "rotate", "scale"});
    const Json& obj = field(m, "object", "transform");
    if (!obj.is_number_integer()) refuse("transform.object: expected an object index");
    long long index = obj.get<long long>();
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
    return applyEdit(m, [&](Json& doc) { transformNode(doc, index, translate, about); });
}

Json Session::replyMaterial(const Json& m, int) {
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

Json Session::replyEmission(const Json& m, int) {
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

Json Session::replyLight(const Json& m, int) {
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

Json Session::replyUndoRedo(const Json& m, int) {
    const std::string type = m["type"].get<std::string>();
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

Json Session::replySave(const Json& m, int) {
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

Json Session::replyRender(const Json& m, int client) {
    expectKeys(m, {"mode", "spp", "spectral"});
    const Json& mode = field(m, "mode", "render");
    if (!mode.is_string() || !findMode(mode.get<std::string>()))
        refuse("render.mode: expected " + modeNameList(" or "));
    const bool spectral = m.contains("spectral") && m["spectral"].is_boolean() &&
                          m["spectral"].get<bool>();
    if (m.contains("spectral") && !m["spectral"].is_boolean())
        refuse("render.spectral: expected true or false");
    int spp = 0;
    if (m.contains("spp")) {
        if (!m["spp"].is_number_integer() || m["spp"].get<long long>() < 1 ||
            m["spp"].get<long long>() > 65536)
            refuse("render.spp: expected a whole number of samples in 1..65536");
        spp = m["spp"].get<int>();
    }
    std::lock_guard<std::mutex> lk(m_mutex);
    if (m_rendering || m_request) refuse("render: a render is already running");
    m_request = RenderRequest{mode.get<std::string>(), spp, client, spectral};
    m_requestPending = true; // a refining preview stops for it
    m_wake.notify_all();
    return {{"type", "render_started"}, {"mode", mode}};
}

// The page's exposure (stops) and tone map, as `rayproc render --exposure --tone-map` apply
// them: every page's frames and the PNG download follow; the last frame is sent again at once.
Json Session::replyDisplay(const Json& m, int) {
    expectKeys(m, {"exposure", "tone_map"});
    std::lock_guard<std::mutex> lk(m_frameMutex);
    ToneMapSettings tm = m_display;
    if (m.contains("exposure")) {
        double e = finite(m["exposure"], "display.exposure");
        if (!(e >= -20 && e <= 20)) refuse("display.exposure: expected stops in [-20, 20]");
        tm.exposure = float(e);
    }
    if (m.contains("tone_map")) {
        const Json& op = m["tone_map"];
        bool known = false;
        for (const auto& [name, value] : kToneMaps)
            if (op.is_string() && op.get<std::string>() == name) tm.op = value, known = true;
        if (!known) refuse("display.tone_map: expected clamp, reinhard or aces");
    }
    m_display = tm;
    if (m_lastImage.width > 0 && m_events.frame)
        m_events.frame(encodeFrame(m_lastImage, ++m_frameNumber, m_lastImageVersion, tm));
    Json out = displayJson(tm);
    out["type"] = "display";
    return out;
}

// How the live view renders: spectrally or in RGB (docs/spectral.md). A change is a new view:
// the preview and its refinement start again.
Json Session::replyView(const Json& m, int) {
    expectKeys(m, {"spectral"});
    if (!m.contains("spectral") || !m["spectral"].is_boolean())
        refuse("view.spectral: expected true or false");
    const bool spectral = m["spectral"].get<bool>();
    std::lock_guard<std::mutex> lk(m_mutex);
    if (m_rendering || m_request) refuse("view: a render is running; cancel it first");
    if (m_spectralView != spectral) {
        m_spectralView = spectral;
        changed();
    }
    return {{"type", "view"}, {"spectral", spectral}};
}

bool Session::spectralView() const {
    std::lock_guard<std::mutex> lk(m_mutex);
    return m_spectralView;
}

ToneMapSettings Session::display() const {
    std::lock_guard<std::mutex> lk(m_frameMutex);
    return m_display;
}

Json Session::replyCancel(const Json& m, int) {
    expectKeys(m, {});
    std::lock_guard<std::mutex> lk(m_mutex);
    if (!m_rendering && !m_request) refuse("cancel: no render is running");
    m_request.reset();
    m_requestPending = false;
    if (m_rendering) requestInterrupt();
    return {{"type", "cancelling"}};
}

} // namespace rayproc::serve
