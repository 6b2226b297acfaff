// PNG: 8-bit sRGB RGB through stb_image_write / stb_image (implementations in stb_impl.cpp).
//
// Writing applies the display transform (toSrgb8) and streams stb's output through a callback
// into the AtomicFileWriter, which checks every write. Reading decodes sRGB back to linear with
// the exact inverse of the OETF, from a FILE* we opened ourselves so that open failures carry
// the errno text, after png_check.cpp has verified the chunk lengths, CRCs and zlib checksum
// (stb_image checks none of them).
#include "image/image_io_detail.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

namespace rayproc::image_detail {

namespace {

// Owns a buffer returned by stb's decoders.
struct StbFree {
    void operator()(void* data) const { stbi_image_free(data); }
};

// stb's output callback: forwards into the writer, which records (never throws) failures.
void writeToAtomicFile(void* context, void* data, int size) {
    static_cast<AtomicFileWriter*>(context)->write(data, static_cast<std::size_t>(size));
}

// True if the file starts with the 8-byte PNG signature; rewinds the file either way.
bool hasPngSignature(std::FILE* file) {
    static const unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    unsigned char head[8] = {};
    bool match = std::fread(head, 1, 8, file) == 8 && std::memcmp(head, kSignature, 8) == 0;
    std::rewind(file);
    return match;
}

} // namespace

void writePng(const std::string& path, const Image& img, const ToneMapSettings& tm) {
    std::vector<unsigned char> bytes(img.pixels.size());
    std::transform(img.pixels.begin(), img.pixels.end(), bytes.begin(),
                   [&](float v) { return toSrgb8(v, tm); });
    AtomicFileWriter out(path);
    if (!stbi_write_png_to_func(writeToAtomicFile, &out, img.width, img.height, 3, bytes.data(),
                                img.width * 3))
        out.fail("the PNG encoder failed (out of memory?)");
    out.commit();
}

Image readPng(const std::string& path) {
    FileReader in(path);
    // Without this check stb would also decode a Radiance file here (it accepts any format it
    // was built with), silently tone-mapping it.
    if (!hasPngSignature(in.get()))
        throwReadError(path, "not a PNG file (the PNG signature is missing)");
    checkPngFile(path);
    int w = 0, h = 0, channels = 0;
    long start = std::ftell(in.get());
    if (stbi_info_from_file(in.get(), &w, &h, &channels))
        checkClaimedSize(path, w, h, fileSize(path));
    std::fseek(in.get(), start, SEEK_SET);
    // The 16-bit entry point serves 8-bit files too (v -> v * 257), so both decode exactly.
    std::unique_ptr<stbi_us[], StbFree> data(
        stbi_load_from_file_16(in.get(), &w, &h, &channels, 3));
    if (!data) {
        const char* reason = stbi_failure_reason();
        throwReadError(path, std::string("corrupt PNG file: ") + (reason ? reason : "unknown"));
    }
    Image img(w, h);
    for (std::size_t i = 0; i < img.pixels.size(); ++i)
        img.pixels[i] = srgbToLinear(static_cast<float>(data[i] / 65535.0));
    return img;
}

} // namespace rayproc::image_detail
