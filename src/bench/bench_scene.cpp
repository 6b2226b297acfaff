#include "bench/bench_scene.h"

#include "core/error.h"
#include "scene/scene_loader.h"

#include <filesystem>

namespace rayproc::bench {

std::string sceneJobName(const SceneJob& job) {
    return job.name.empty() ? std::filesystem::path(job.file).stem().string() : job.name;
}

BenchScene prepareBenchScene(const SceneJob& job, const std::string& refsDir, int cacheSpp,
                             int threads, bool spectral) {
    const int width = job.width, height = job.height;
    BenchScene b;
    b.file = job.file;
    b.name = sceneJobName(job);
    b.scene = loadScene(job.file);
    b.nativeWidth = b.scene->camera.width;
    b.nativeHeight = b.scene->camera.height;
    b.scene->camera.width = width;
    b.scene->camera.height = height;
    b.accel = std::make_unique<EmbreeScene>(*b.scene);
    if (!job.reference.empty()) {
        Image image = job.givenImage ? *job.givenImage : readImage(job.reference);
        if (image.width == width && image.height == height) {
            b.source = job.source;
            b.referenceSpp = job.referenceSpp;
            b.reference.path = job.reference;
            b.reference.image = std::move(image);
            return b;
        }
        if (job.source == ReferenceSource::Given)
            throw InputError(job.reference + ": the reference is " + std::to_string(image.width) +
                             "x" + std::to_string(image.height) + " but the bench renders " +
                             b.name + " at " + std::to_string(width) + "x" +
                             std::to_string(height));
    }
    b.source = ReferenceSource::Cache;
    b.referenceSpp = cacheSpp;
    b.referenceSpectral = spectral;
    b.reference = loadOrRenderReference(*b.scene, *b.accel, job.file, refsDir, cacheSpp, threads,
                                        b.name, spectral);
    return b;
}

} // namespace rayproc::bench
