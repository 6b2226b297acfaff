// Decoded texture images: linear RGB floats and their MIP pyramid, read through OpenImageIO
// (TGA, PNG, JPEG, EXR, PFM, HDR, TIFF, ...: docs/dependencies.md). A file used by several
// textures is decoded once (a process-wide cache keyed by path and encoding).
#pragma once

#include "core/uninitialized.h"

#include <memory>
#include <string>
#include <vector>

namespace rayproc {

// How stored values become linear: pbrt-v4's "encoding" ("sRGB" is its default for 8-bit
// files; float files are always linear).
struct TextureEncoding {
    enum class Kind { Srgb, Linear, Gamma };
    Kind kind = Kind::Srgb;
    float gamma = 2.2f;
};

struct TextureImage {
    struct Level {
        int width = 0, height = 0;
        UninitializedFloats rgb; // row 0 is the top row of the file; every texel written
        const float* at(int x, int y) const { return &rgb[3 * (std::size_t(y) * width + x)]; }
    };
    std::vector<Level> levels; // levels[0]: the full resolution, then halved down to 1x1
    bool hasAlpha = false;
    std::vector<float> alpha; // level 0 only, when the file has an alpha channel

    int width() const { return levels.empty() ? 0 : levels[0].width; }
    int height() const { return levels.empty() ? 0 : levels[0].height; }
};

// Loads and caches; throws ImageIoError naming the file and the cause.
std::shared_ptr<const TextureImage> loadTextureImage(const std::string& path,
                                                     const TextureEncoding& encoding);

// Builds the pyramid of `img` from its level 0 (2x2 box averages, odd sizes round up). Exposed
// for tests.
void buildMipLevels(TextureImage& img);

} // namespace rayproc
