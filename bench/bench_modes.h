// The render configurations the scaling and engine-efficiency benchmarks share: one per mode,
// so that a mode's frame in BM_Mode and the rays recorded for its replay are the same work.
//
//   preview   512x512, 1 spp (one pass)
//   raytrace  512x512, spp 4 (4 passes of 1 spp), 4 light samples
//   path      512x512, spp 1 (one pass), max depth 64, Russian roulette after 3 bounces
//   gi        256x256, spp 1, the mode's defaults otherwise: 200K global and 200K caustic
//             photons, irradiance-cache prepass at 1/16 .. full resolution, 64 gather rays
//
// The scene's camera is resized in place (loadedScene() is shared; every benchmark that
// renders sets the size it needs).
#pragma once

#include "bench_scenes.h"

#include "modes/modes.h"

#include <stdexcept>
#include <string>

namespace rayproc::bench {

struct ModeFrame {
    int resolution;
    int spp;
};

inline ModeFrame modeFrame(const std::string& mode) {
    if (mode == "preview") return {512, 1};
    if (mode == "raytrace") return {512, 4};
    if (mode == "path") return {512, 1};
    if (mode == "gi") return {256, 1};
    throw std::invalid_argument("unknown mode " + mode);
}

// One frame of `mode` on `sceneName` with `threads` engine threads (0: all cores).
inline RenderResult renderModeFrame(const std::string& mode, const std::string& sceneName,
                                    int threads) {
    LoadedScene& loaded = loadedScene(sceneName);
    Scene& scene = *loaded.scene;
    ModeFrame f = modeFrame(mode);
    scene.camera = loaded.nativeCamera;
    scene.camera.width = f.resolution;
    scene.camera.height = f.resolution;
    EngineSettings engine;
    engine.threads = threads;
    engine.quiet = true;
    ModeOverrides o;
    o.spp = f.spp;
    const EmbreeScene& accel = *loaded.accel;
    if (mode == "preview")
        return renderPreview(scene, accel, previewSettings(scene.render, o), engine);
    if (mode == "raytrace")
        return renderRaytrace(scene, accel, raytraceSettings(scene.render, o), engine);
    if (mode == "path") return renderPath(scene, accel, pathSettings(scene.render, o), engine);
    return renderGi(scene, accel, giSettings(scene, o), engine);
}

// Seconds of the render (gi: the final render pass only; its photon, precompute and cache
// passes are reported as extras and are not in the stage statistics).
inline double renderPhaseSeconds(const RenderResult& r) {
    double seconds = r.stats.wallSeconds;
    for (const auto& [name, value] : r.stats.extras)
        if (name == "gi/photon_seconds" || name == "gi/precompute_seconds" ||
            name == "gi/cache_seconds")
            seconds -= value;
    return seconds;
}

} // namespace rayproc::bench
