// PNG: 8-bit sRGB RGB through stb_image_write / stb_image (implementations in stb_impl.cpp).
//
// Writing applies the display transform (toSrgb8) and streams stb's output through a callback
// into the AtomicFileWriter, which checks every write. Reading decodes sRGB back to linear with
// the exact inverse of the OETF, from a FILE* we opened ourselves so that open failures carry
// the errno text.
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

namespace {

// stb_image grows its buffer to whatever an IDAT chunk's length field says (1.2 GB from a small
// file, found by tests/fuzz/image_fuzzer), so the chunk lengths are walked first: each must fit
// in what is left of the file.
void checkPngChunks(const std::string& path, std::FILE* f) {
    long start = std::ftell(f);
    std::uint64_t size = fileSize(path);
    std::uint64_t pos = 8; // after the signature
    unsigned char head[8];
    while (pos + 8 <= size) {
        if (std::fseek(f, long(pos), SEEK_SET) != 0 || std::fread(head, 1, 8, f) != 8) break;
        std::uint32_t length = std::uint32_t(head[0]) << 24 | std::uint32_t(head[1]) << 16 |
                               std::uint32_t(head[2]) << 8 | std::uint32_t(head[3]);
        std::string type(reinterpret_cast<const char*>(head + 4), 4);
        for (char& c : type)
            if (c < 32 || c > 126) c = '?';
        std::uint64_t left = size - pos - 8;
        if (length > left)
            throwReadError(path, "corrupt PNG file: the " + type + " chunk claims " +
                                     std::to_string(length) + " bytes, but the file has " +
                                     std::to_string(left) + " left");
        if (type == "IEND") break;
        pos += 12 + std::uint64_t(length); // length, type, data, CRC
    }
    std::fseek(f, start, SEEK_SET);
}

} // namespace

Image readPng(const std::string& path) {
    FileReader in(path);
    // Without this check stb would also decode a Radiance file here (it accepts any format it
    // was built with), silently tone-mapping it.
    if (!hasPngSignature(in.get()))
        throwReadError(path, "not a PNG file (the PNG signature is missing)");
    checkPngChunks(path, in.get());
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
