// One scene, rendered tiny in every mode: what render_fuzzer runs on each input and what
// tests/fuzz/render_seeds_test.cpp runs on its seeds. The input is a JSON scene, or a pbrt-v4
// one when its first non-blank byte is a letter or '#' (as scene_fuzzer picks).
//
// The contract: a scene either fails to load with InputError (or is refused by the scene
// analysis with one) or renders in preview, raytrace, path and gi without a crash, an abort or
// an exception, and every image it gives is finite. Light power and filter parameters near
// float's limits are what the seeds under tests/fuzz/render-seeds/ push on.
#pragma once

#include "accel/embree_scene.h"
#include "core/error.h"
#include "modes/modes.h"
#include "scene/pbrt/pbrt_loader.h"
#include "scene/scene_loader.h"

#include <cctype>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace rayproc::fuzz {

inline std::unique_ptr<Scene> loadAnyScene(const std::string& text) {
    for (char c : text) {
        if (c == ' ' || c == '\t' || c == '\n' || c == '\r') continue;
        if (std::isalpha(static_cast<unsigned char>(c)) || c == '#') {
            std::vector<std::string> warnings; // collected, not printed
            return loadPbrtSceneFromString(text, "/nonexistent/rayproc-fuzz/scene.pbrt",
                                           &warnings);
        }
        break;
    }
    return loadSceneFromString(text, "/nonexistent/rayproc-fuzz/scene.json");
}

// The images of the four modes at 8 x 8, one sample per pixel and a few hundred photons; empty
// when the text is not a scene rayproc accepts (InputError).
inline std::vector<Image> renderEveryMode(const std::string& text) {
    std::unique_ptr<Scene> scene;
    try {
        scene = loadAnyScene(text);
    } catch (const InputError&) {
        return {};
    }
    scene->camera.width = 8;
    scene->camera.height = 8;
    std::vector<Image> images;
    try {
        EmbreeScene accel(*scene);
        EngineSettings engine;
        engine.threads = 1;
        engine.quiet = true;
        ModeOverrides one{1, 4, 1};
        images.push_back(renderPreview(*scene, accel, previewSettings(scene->render, one), engine).image);
        images.push_back(renderRaytrace(*scene, accel, raytraceSettings(scene->render, one), engine).image);
        images.push_back(renderPath(*scene, accel, pathSettings(scene->render, one), engine).image);
        GiSettings gi = giSettings(*scene, one);
        gi.photons = 300;
        gi.causticPhotons = 100;
        gi.gatherRays = 4;
        images.push_back(renderGi(*scene, accel, gi, engine).image);
    } catch (const InputError&) {
        return {}; // refused before rendering (the scene analysis, Embree's range)
    }
    return images;
}

inline bool allFinite(const std::vector<Image>& images) {
    for (const Image& img : images)
        for (float v : img.pixels)
            if (!std::isfinite(v)) return false;
    return true;
}

} // namespace rayproc::fuzz
