// libFuzzer target for scene cameras against Embree: a JSON scene or a pbrt-v4 file (the first
// non-blank byte a letter or '#') is loaded and built into an EmbreeScene; for a scene that
// loads, the camera rays through the film's corners and centre, from the lens's centre and
// edge, must be finite and within Embree's range, and are traced. The seeds and the
// dictionary (tests/fuzz/camera-seeds/, scene.dict) push the camera's numbers to their limits:
// positions, look_at, up, fov, apertures and focus distances of 1e16..1e38.
//
// The contract under test: loading and building either succeed or throw rayproc::InputError
// (scene/camera_check.h refuses what Embree cannot trace); any other exception, a ray out of
// range, Embree's own assertion, a crash or a sanitizer report is a finding. Unlike
// scene_fuzzer this links the engine: it is what sees a camera that loads but aborts.
#include "accel/embree_scene.h"
#include "core/error.h"
#include "engine/camera_emitter.h"
#include "engine/intersect.h"
#include "engine/ray_batch.h"
#include "kernels/camera_rays.h"
#include "scene/camera_check.h"
#include "scene/pbrt/pbrt_loader.h"
#include "scene/scene_loader.h"

#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

namespace {

using namespace rayproc;

bool isPbrt(const std::string& text) {
    for (char c : text) {
        if (c == ' ' || c == '\t' || c == '\n' || c == '\r') continue;
        return std::isalpha(static_cast<unsigned char>(c)) || c == '#';
    }
    return false;
}

bool inRange(float v) {
    return std::isfinite(v) && std::abs(double(v)) <= kEmbreeRayLimit;
}

// Nine film points times three lens points, traced one by one.
void traceCorners(const Scene& scene, const EmbreeScene& accel) {
    kernels::CameraFrame frame = cameraFrame(scene.camera);
    auto batch = std::make_unique<RayBatch>();
    std::vector<float> fx, fy, lu, lv;
    for (float x : {0.0f, 0.5f, 1.0f})
        for (float y : {0.0f, 0.5f, 1.0f})
            for (float l : {0.0f, 0.5f, 0.999f}) {
                fx.push_back(x * float(scene.camera.width));
                fy.push_back(y * float(scene.camera.height));
                lu.push_back(l);
                lv.push_back(1.0f - l);
                batch->push(0, 0, 0, 0, 0, 1, 0.0f, kInfinity);
            }
    kernels::generateCameraRays(frame, batch->count, fx.data(), fy.data(), lu.data(), lv.data(),
                                batch->ox.data(), batch->oy.data(), batch->oz.data(),
                                batch->dx.data(), batch->dy.data(), batch->dz.data());
    for (int i = 0; i < batch->count; ++i)
        if (!inRange(batch->ox[i]) || !inRange(batch->oy[i]) || !inRange(batch->oz[i]) ||
            !inRange(batch->dx[i]) || !inRange(batch->dy[i]) || !inRange(batch->dz[i]))
            std::abort(); // a camera the checks let through gives a ray Embree cannot take
    Intersector intersector(accel.root(), 1);
    ThreadStats stats;
    intersector.trace(*batch, stats);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        std::unique_ptr<Scene> scene;
        if (isPbrt(text)) {
            std::vector<std::string> warnings;
            scene =
                loadPbrtSceneFromString(text, "/nonexistent/rayproc-fuzz/scene.pbrt", &warnings);
        } else {
            scene = loadSceneFromString(text, "/nonexistent/rayproc-fuzz/scene.json");
        }
        EmbreeScene accel(*scene);
        traceCorners(*scene, accel);
    } catch (const InputError&) {
        // A clear error: the expected outcome for a camera out of range.
    }
    return 0;
}
