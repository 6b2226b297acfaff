#include "texture/direct_readers.h"

#include "image/image.h"

#include <stb_image.h>

#include <cctype>
#include <cstdint>
#include <cstdio>
#include <memory>

namespace rayproc {

namespace {

bool endsWith(const std::string& s, const char* suffix) {
    std::string t(suffix);
    if (s.size() < t.size()) return false;
    for (std::size_t i = 0; i < t.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(s[s.size() - t.size() + i])) != t[i])
            return false;
    return true;
}

// A TGA's 18-byte header: no colour map, raw true colour or grey, 24 or 8 bits, and the file
// long enough for its pixels (stb_image fills a short file's missing pixels with zeros without
// a word; run-length encoded files, whose length says nothing, go to OpenImageIO).
bool plainTga(const std::string& path) {
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), std::fclose);
    unsigned char h[18];
    if (!f || std::fread(h, 1, sizeof h, f.get()) != sizeof h) return false;
    const int colourMap = h[1], type = h[2], depth = h[16], alphaBits = h[17] & 0x0f;
    if (colourMap != 0 || alphaBits != 0) return false;
    if (!((type == 2 && depth == 24) || (type == 3 && depth == 8))) return false;
    const std::uint64_t width = std::uint64_t(h[12] | (h[13] << 8)),
                        height = std::uint64_t(h[14] | (h[15] << 8));
    const std::uint64_t need = 18 + std::uint64_t(h[0]) + width * height * std::uint64_t(depth / 8);
    if (std::fseek(f.get(), 0, SEEK_END) != 0) return false;
    long size = std::ftell(f.get());
    return size >= 0 && std::uint64_t(size) >= need;
}

bool readTga(const std::string& path, RawPixels& out) {
    int w = 0, h = 0, n = 0;
    if (!plainTga(path) || !stbi_info(path.c_str(), &w, &h, &n)) return false;
    if (w <= 0 || h <= 0 || std::int64_t(w) * h > (std::int64_t(1) << 28)) return false;
    checkImageDimensions(path, w, h);
    std::shared_ptr<const unsigned char> data(stbi_load(path.c_str(), &w, &h, &n, 0),
                                              [](const unsigned char* p) {
                                                  stbi_image_free(const_cast<unsigned char*>(p));
                                              });
    if (!data || (n != 1 && n != 3)) return false;
    out.width = w;
    out.height = h;
    out.channels = n;
    out.alphaChannel = -1;
    out.isFloat = false;
    out.bytes = std::move(data);
    return true;
}

bool readPfmTexture(const std::string& path, RawPixels& out) {
    Image img;
    try {
        img = readImage(path);
    } catch (const ImageIoError&) {
        return false; // OpenImageIO says what is wrong with it, as before
    }
    out.width = img.width;
    out.height = img.height;
    out.channels = 3;
    out.alphaChannel = -1;
    out.isFloat = true;
    out.pixels = std::move(img.pixels);
    return true;
}

} // namespace

bool readWithoutOiio(const std::string& path, RawPixels& out) {
    if (endsWith(path, ".tga")) return readTga(path, out);
    if (endsWith(path, ".pfm")) return readPfmTexture(path, out);
    return false;
}

} // namespace rayproc
