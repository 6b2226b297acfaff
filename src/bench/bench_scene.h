// A suite's scene ready to bench: loaded, set to its render size (the scene's own in the suite,
// else the suite's), its BVH built, and its
// reference image (from the cache, rendered, or given with --reference).
#pragma once

#include "accel/embree_scene.h"
#include "bench/reference_cache.h"
#include "image/image.h"
#include "scene/scene.h"

#include <memory>
#include <string>

namespace rayproc::bench {

// Where a scene's reference comes from.
enum class ReferenceSource { Cache, Shipped, Given };

// A scene to bench, the size it renders at and the reference image to use (empty: the cache).
struct SceneJob {
    std::string file;
    std::string name; // empty: the file's stem
    int width = 0, height = 0;
    std::string reference;
    // A given reference (--reference), read once when the job was made (its size is the
    // render's); null for shipped and cached ones, which are read when the scene is prepared.
    std::shared_ptr<const Image> givenImage;
    int referenceSpp = 0; // of a shipped reference; 0 if unknown
    ReferenceSource source = ReferenceSource::Cache;
};

struct BenchScene {
    std::string name; // the file's stem: the results' scene column
    std::string file;
    int nativeWidth = 0, nativeHeight = 0; // the scene file's own resolution
    std::unique_ptr<Scene> scene;
    std::unique_ptr<EmbreeScene> accel;
    Reference reference;
    ReferenceSource source = ReferenceSource::Cache;
    int referenceSpp = 0; // 0: unknown (a given image)
    bool referenceSpectral = false; // a cached reference rendered spectrally (bench --spectral)
};

// The results' name of the job's scene: its name, else its file's stem.
std::string sceneJobName(const SceneJob& job);

// Loads the job's scene at the job's width x height and its reference: a given image must have
// that size (InputError otherwise); a shipped one of another size is passed over for the cache,
// which renders path mode at `cacheSpp` (spectrally when `spectral`) if it has no such image
// yet. A cancelled reference render leaves reference.cancelled set.
BenchScene prepareBenchScene(const SceneJob& job, const std::string& refsDir, int cacheSpp,
                             int threads, bool spectral = false);

} // namespace rayproc::bench
