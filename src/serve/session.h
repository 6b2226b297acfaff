// rayproc serve's model (docs/serve.md): one scene shared by every connected page. The scene's
// JSON document is the truth: each edit changes the document, the scene is loaded again from
// it by the same loader `rayproc render` uses (so a malformed edit is refused with the loader's
// message and changes nothing, and a saved scene renders exactly as shown), and the previous
// document goes on the undo stack.
//
// A worker thread renders: the live preview (preview mode at 1/4 resolution within a frame of
// any change, then at full resolution while idle), or one render in raytrace, gi or path mode
// whose passes stream in with progress until it ends or is cancelled, after which the live
// preview resumes. Frames and events go to every page through Events.
#pragma once

#include "image/image.h"
#include "modes/render_job.h"
#include "scene/scene.h"

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace rayproc {

class EmbreeScene;

namespace serve {

using Json = nlohmann::ordered_json;

// A frame message: "RPF2", width, height, frame number (increasing, with gaps where stale
// frames were dropped), version (little-endian u32 each), then width * height RGBA bytes
// (8-bit sRGB, the PNG tone map). The version is that of the scene and view the frame shows
// (the low 32 bits of Session's, as in the state's "version").
constexpr std::size_t kFrameHeaderBytes = 20;
// `tm`: the page's exposure and tone map (the "display" message).
std::vector<std::uint8_t> encodeFrame(const Image& image, std::uint32_t number,
                                      std::uint64_t version, const ToneMapSettings& tm = {});

// JSON text for the pages. Bytes that are not UTF-8 in a string (a client's malformed message
// quoted in an error, a file name) become U+FFFD: nlohmann's dump would throw (type_error 316).
std::string toText(const Json& json, int indent = -1);

class Session {
public:
    struct Events {
        std::function<void(const std::string& json)> text; // to every page
        std::function<void(const std::vector<std::uint8_t>& frame)> frame;
    };
    // The largest translation one transform message may make along an axis.
    static constexpr float kMaxTranslate = 1000.0f;
    // Why the live preview is smaller than `requested` pixels on its longer side (it never
    // exceeds the scene's resolution), or "" when it is not.
    std::string previewSizeNote(int requested) const;

    struct Options {
        int threads = 0;
        int previewMaxSide = 512; // the live preview's longer side (the aspect is the scene's)
        // A still view refines after its preview: raytrace mode's passes at the preview's
        // size, each sent as a frame with a "refine" message (docs/serve.md).
        bool refine = true;
    };

    // Loads the scene (JSON scenes are editable; pbrt scenes can be viewed and rendered).
    Session(const std::string& scenePath, const Options& options);
    ~Session();
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;

    // Starts the worker; the first preview follows at once.
    void start(Events events);
    // Cancels a running render and ends the worker: no event is sent after it returns (the
    // server stops its page traffic next). The destructor calls it too.
    void stop();
    // One message from page `client` (JSON text, docs/serve.md); returns the reply (JSON text:
    // {"type": "error", "message": ...} for anything refused, which changes nothing).
    std::string handle(const std::string& message, int client);
    // A page closed: its render, if one runs, is cancelled.
    void clientClosed(int client);
    // What a page shows: objects, materials, lights, camera, mode, analysis, undo depth.
    Json state() const;
    // The image shown last (a preview or a render's frame) and the version it shows; false
    // before the first.
    bool lastFrame(Image& out, std::uint64_t* version = nullptr) const;
    // The page's exposure and tone map: the frames' and the PNG download's.
    ToneMapSettings display() const;
    // The last render in raytrace, gi or path mode, partial when it was cancelled (it stays
    // downloadable after the live preview resumes); false before the first.
    bool lastRender(Image& out) const;
    // Blocks until the worker has nothing to do (tests).
    void waitIdle();

    // Live-preview renders begun (coarse and full size each count) and those a newer change
    // stopped before they finished (tests: a stale preview is stopped, not waited for).
    struct PreviewCounts {
        std::uint32_t started = 0, stopped = 0;
    };
    PreviewCounts previewCounts() const {
        return {m_previewsStarted.load(), m_previewsStopped.load()};
    }

private:
    struct Loaded; // a scene, its Embree scene and what the page lists
    struct RenderRequest {
        std::string mode;
        int spp = 0;
        int client = -1;
        bool spectral = false; // EngineSettings::spectral (docs/spectral.md)
    };

    Json reply(const Json& message, int client);
    // One function per message type (reply dispatches); each validates its message.
    Json replyState(const Json& m, int client);
    Json replyCamera(const Json& m, int client);
    Json replyPick(const Json& m, int client);
    Json replyTransform(const Json& m, int client);
    Json replyMaterial(const Json& m, int client);
    Json replyEmission(const Json& m, int client);
    Json replyLight(const Json& m, int client);
    Json replyUndoRedo(const Json& m, int client);
    Json replySave(const Json& m, int client);
    Json replyRender(const Json& m, int client);
    Json replyCancel(const Json& m, int client);
    Json replyDisplay(const Json& m, int client);
    Json replyView(const Json& m, int client);
    bool spectralView() const; // takes m_mutex
    // The document's node `index` moved by `translate` after `about` (rotation and scale
    // about its centre); m_mutex held.
    void transformNode(Json& doc, long long index, const Vec3& translate,
                       const Affine& about) const;
    Json applyEdit(const Json& message, const std::function<void(Json& doc)>& edit);
    void load(const Json& doc); // throws InputError; replaces m_loaded on success
    Json pick(const Json& message) const;
    Json objectsJson() const; // the state's "objects" (m_mutex held)
    void worker();
    // `version`: the m_version the scene and view are of (the frames carry it). A newer change
    // stops the preview in progress, and its frame is not sent.
    // True when the full-size frame was sent.
    bool renderPreview(const std::shared_ptr<Loaded>& loaded, std::uint64_t version);
    // The still view's raytrace passes at the preview's size, until they end or a change or
    // a render request stops them.
    void refinePreview(const std::shared_ptr<Loaded>& loaded, std::uint64_t version);
    // The preview's size for the scene's camera (the longer side at most previewMaxSide).
    void previewSize(const Camera& full, int& width, int& height) const;
    // Stops a preview (or its refinement) once a newer change, a render request or the end
    // makes it stale.
    std::function<bool()> staleStop(std::uint64_t version) const;
    void renderMode(const std::shared_ptr<Loaded>& loaded, const RenderRequest& request,
                    std::uint64_t version);
    class StartingTicker;
    // The render the request names (its mode and spp), with the engine settings and the
    // watcher and stop given.
    static RenderResult runMode(const Scene& scene, const EmbreeScene& accel,
                                const RenderRequest& request, const EngineSettings& engine,
                                const RenderControl& control);
    void sendText(const Json& json) const;
    // Sends the frame unless a change made it stale (false then).
    bool sendFrame(Image image, std::uint64_t version);
    void changed(); // a change the preview must show (m_mutex held)

    std::string m_path;
    bool m_editable = false; // JSON scenes
    Options m_options;
    Events m_events;

    mutable std::mutex m_mutex;
    std::condition_variable m_wake;
    Json m_doc;
    // One undo (or redo) step: an edit (the document before it) or a camera move (the view
    // before it); undoing one puts the other state on the opposite stack. Camera steps are the
    // moves the page marks "undo_step" (the first message of a drag, a wheel burst, a key).
    struct Step {
        std::optional<Json> doc;
        std::optional<Camera> camera;
    };
    void pushUndo(Step step);        // a new step: the redo stack is cleared
    Step swapStep(const Step& step); // applies it; returns the step that undoes that
    void setCamera(const Camera& c); // the view, written into the document too
    std::vector<Step> m_undo, m_redo;
    Camera m_home; // the scene file's view: the page's Home button
    std::shared_ptr<Loaded> m_loaded;
    Camera m_camera; // the page's view; the worker copies it into the scene it renders
    // Bumps at every change the preview must show, under m_mutex and m_frameMutex; the
    // preview's stop reads it without a lock.
    std::atomic<std::uint64_t> m_version{0};
    std::uint64_t m_previewedVersion = 0; // what the worker has shown
    // When the last two changes came (m_mutex): changes less than kMotionGap apart are a
    // drag, and the full-size frame waits for the next one (renderPreview).
    std::chrono::steady_clock::time_point m_lastChange{}, m_changeBefore{};
    int m_motionStep = 4; // a drag's coarse frames: 1/m_motionStep of each side (worker only)
    std::optional<RenderRequest> m_request;
    std::atomic<bool> m_requestPending{false}; // m_request is set (read by staleStop)
    std::vector<std::string> m_warnings;       // the pbrt loader's, for the page
    // The live view and its refinement render spectrally (m_mutex): the scene's
    // render.spectral at first, then the page's "view" message.
    bool m_spectralView = false;
    bool m_rendering = false;
    int m_renderClient = -1;
    std::atomic<bool> m_quit{false};
    bool m_busy = false;
    std::atomic<std::uint32_t> m_frameNumber{0};
    std::atomic<std::uint32_t> m_previewsStarted{0}, m_previewsStopped{0};
    // Held while a frame is checked against m_version and sent, and while m_version changes:
    // once a change is accepted, no frame of an older version goes out. Guards the last image.
    // Taken after m_mutex, never before.
    mutable std::mutex m_frameMutex;
    Image m_lastImage;
    ToneMapSettings m_display;
    std::uint64_t m_lastImageVersion = 0;
    Image m_lastRender;
    std::condition_variable m_idle;
    std::thread m_thread;
};

} // namespace serve
} // namespace rayproc
