// The bench's reference images: path mode at high spp, rendered once and kept in
// <out>/refs/<scene>-<w>x<h>-path-<spp>-<hash>.exr (a spectral one, for `bench --spectral`:
// -path-spectral-<spp>-), where <hash> is a 64-bit FNV-1a hash of
// the scene file's bytes (first 16 hex digits). A changed scene file, resolution or spp gives a
// new name, so a stale reference is never reused. The reference uses its own seed, so its noise
// is independent of the path renders it judges.
#pragma once

#include "accel/embree_scene.h"
#include "image/image.h"
#include "scene/scene.h"

#include <cstdint>
#include <string>

namespace rayproc::bench {

constexpr std::uint64_t kReferenceSeed = 0x7265666572656e63ull; // "referenc"

// FNV-1a over a file's bytes; throws InputError if it cannot be read.
std::uint64_t hashFile(const std::string& path);

// <refsDir>/<name>-<w>x<h>-path-<spp>-<hash>.exr (-path-spectral-<spp>- when `spectral`); the
// name is the scene's in its suite, else (empty) the file's stem.
std::string referencePath(const std::string& refsDir, const std::string& sceneFile, int width,
                          int height, int spp, const std::string& name = "",
                          bool spectral = false);

struct Reference {
    Image image;
    std::string path;
    bool rendered = false; // false: read from the cache
    double seconds = 0;    // render time when rendered
    bool cancelled = false;
};

// The cached reference for the scene (already at its render size), rendered with path
// mode at `spp` (spectrally when `spectral`: the spectral renders are measured against the
// image they converge to) and written atomically if absent. A cancelled render (Ctrl-C) is not
// written.
Reference loadOrRenderReference(const Scene& scene, const EmbreeScene& accel,
                                const std::string& sceneFile, const std::string& refsDir, int spp,
                                int threads, const std::string& name = "",
                                bool spectral = false);

} // namespace rayproc::bench
