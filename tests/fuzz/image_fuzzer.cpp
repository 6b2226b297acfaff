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
// PNG inputs are read twice: as they are, and with every chunk's CRC-32 recomputed. The readers
// refuse a chunk whose CRC does not match (src/image/png_check.cpp), so without the repair
// almost no mutation would get past the check to stb_image's and libpng's decoders; with it,
// mutated headers and palettes reach them (mutated image data still fails zlib's Adler-32).
//
// The contract under test: every input either reads or throws rayproc::ImageIoError; a read
// image has the size it claims and every value finite or not, but no more values than pixels.
// Any other exception, a crash, a sanitizer report, an allocation beyond -malloc_limit_mb or a
// hang is a finding.
#include "core/error.h"
#include "image/image.h"
#include "texture/texture_image.h"

#include <unistd.h>
#include <zlib.h>

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

// Every reader that takes a file of this kind; any failure but ImageIoError aborts.
void readAll(const std::string& path, const char* ext) {
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
}

// Recomputes the CRC of every whole chunk after the PNG signature; false when none changed.
bool repairPngCrcs(std::string& png) {
    bool changed = false;
    std::size_t pos = 8;
    while (pos + 12 <= png.size()) {
        auto byte = [&](std::size_t i) { return std::uint32_t(std::uint8_t(png[i])); };
        const std::uint32_t length =
            byte(pos) << 24 | byte(pos + 1) << 16 | byte(pos + 2) << 8 | byte(pos + 3);
        if (length > png.size() - pos - 12) break;
        const std::size_t crcAt = pos + 8 + length;
        const std::uint32_t crc = std::uint32_t(
            crc32(0, reinterpret_cast<const Bytef*>(png.data() + pos + 4), uInt(length + 4)));
        for (int i = 0; i < 4; ++i) {
            const char c = char(crc >> (24 - 8 * i));
            changed |= png[crcAt + std::size_t(i)] != c;
            png[crcAt + std::size_t(i)] = c;
        }
        pos = crcAt + 4;
    }
    return changed;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const char* ext = extensionFor(data, size);
    std::string bytes(reinterpret_cast<const char*>(data), size);
    const bool png = std::strcmp(ext, ".png") == 0;
    for (int pass = 0; pass < (png ? 2 : 1); ++pass) {
        if (pass == 1 && !repairPngCrcs(bytes)) break;
        std::string path = workDirectory() + "/input" + ext;
        std::FILE* f = std::fopen(path.c_str(), "wb");
        if (!f) std::abort();
        if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size())
            std::abort();
        std::fclose(f);
        readAll(path, ext);
        ::unlink(path.c_str());
    }
    return 0;
}
