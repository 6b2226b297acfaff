// libFuzzer target for the image readers: readImage() (PNG through stb_image, EXR through
// OpenEXR, Radiance HDR and PFM through rayproc's own decoders), as `rayproc diff` and
// `--reference` read images, and loadTextureImage() (OpenImageIO), as image textures and sky
// maps are read.
//
// The readers take paths, so each input is written to a file in a private temporary
// directory. Its extension follows the input's magic bytes (\x89PNG, the EXR magic, "PF"/"Pf",
// "#?"), so the seed corpus is plain image files; an input without a known magic takes the
// format its first byte picks. Every input goes through readImage() and, for the formats a
// texture can be, loadTextureImage().
//
// The contract under test: every input either reads or throws rayproc::ImageIoError; a read
// image has the size it claims and every value finite or not, but no more values than pixels.
// Any other exception, a crash, a sanitizer report, an allocation beyond -malloc_limit_mb or a
// hang is a finding.
#include "core/error.h"
#include "image/image.h"
#include "texture/texture_image.h"

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

const char* extensionFor(const std::uint8_t* data, std::size_t size) {
    auto starts = [&](const char* magic, std::size_t n) {
        return size >= n && std::memcmp(data, magic, n) == 0;
    };
    if (starts("\x89PNG", 4)) return ".png";
    if (starts("\x76\x2f\x31\x01", 4)) return ".exr";
    if (starts("PF", 2) || starts("Pf", 2)) return ".pfm";
    if (starts("#?", 2)) return ".hdr";
    static const char* const kAll[] = {".png", ".exr", ".pfm", ".hdr", ".tga"};
    return size > 0 ? kAll[data[0] % 5] : ".pfm";
}

const std::string& workDirectory() {
    static const std::string dir = [] {
        char pattern[] = "/tmp/rayproc-image-fuzz-XXXXXX";
        if (!::mkdtemp(pattern)) std::abort();
        return std::string(pattern);
    }();
    return dir;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const char* ext = extensionFor(data, size);
    std::string path = workDirectory() + "/input" + ext;
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) std::abort();
    if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
    std::fclose(f);

    if (std::strcmp(ext, ".tga") != 0) {
        try {
            rayproc::Image img = rayproc::readImage(path);
            if (img.width < 0 || img.height < 0 ||
                img.pixels.size() != std::size_t(img.width) * std::size_t(img.height) * 3)
                std::abort();
        } catch (const rayproc::ImageIoError&) {
        }
    }
    try {
        auto tex = rayproc::loadTextureImage(path, rayproc::TextureEncoding{});
        if (tex->levels.empty() || tex->levels[0].rgb.size() !=
                                       std::size_t(tex->width()) * std::size_t(tex->height()) * 3)
            std::abort();
    } catch (const rayproc::ImageIoError&) {
    }
    ::unlink(path.c_str());
    return 0;
}
