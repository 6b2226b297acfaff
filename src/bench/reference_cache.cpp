#include "bench/reference_cache.h"

#include "bench/bench_render.h"
#include "core/error.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace rayproc::bench {

std::uint64_t hashFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot read");
    std::uint64_t h = 0xcbf29ce484222325ull;
    char buf[65536];
    while (in.read(buf, sizeof buf) || in.gcount() > 0) {
        for (std::streamsize i = 0; i < in.gcount(); ++i) {
            h ^= std::uint8_t(buf[i]);
            h *= 0x100000001b3ull;
        }
        if (in.eof()) break;
    }
    return h;
}

std::string referencePath(const std::string& refsDir, const std::string& sceneFile, int width,
                          int height, int spp, const std::string& name, bool spectral) {
    char hash[20];
    std::snprintf(hash, sizeof hash, "%016llx", (unsigned long long)hashFile(sceneFile));
    std::string stem = name.empty() ? std::filesystem::path(sceneFile).stem().string() : name;
    return (std::filesystem::path(refsDir) /
            (stem + "-" + std::to_string(width) + "x" + std::to_string(height) +
             (spectral ? "-path-spectral-" : "-path-") +
             std::to_string(spp) + "-" + hash + ".exr"))
        .string();
}

Reference loadOrRenderReference(const Scene& scene, const EmbreeScene& accel,
                                const std::string& sceneFile, const std::string& refsDir, int spp,
                                int threads, const std::string& name, bool spectral) {
    Reference ref;
    ref.path = referencePath(refsDir, sceneFile, scene.camera.width, scene.camera.height, spp,
                             name, spectral);
    if (std::filesystem::exists(ref.path)) {
        ref.image = readImage(ref.path);
        if (ref.image.width == scene.camera.width && ref.image.height == scene.camera.height)
            return ref;
        // A file of the wrong size under this name was not written by the bench: render anew.
    }
    RenderConfig c = RenderConfig::forMode(scene, "path", spp);
    c.engine.seed = kReferenceSeed;
    c.engine.threads = threads;
    c.engine.spectral = spectral;
    TimedRender t = renderTimed(scene, accel, c);
    ref.rendered = true;
    ref.seconds = t.seconds;
    ref.cancelled = t.cancelled;
    ref.image = std::move(t.image);
    if (!ref.cancelled) {
        std::filesystem::create_directories(refsDir);
        writeImage(ref.path, ref.image);
    }
    return ref;
}

} // namespace rayproc::bench
