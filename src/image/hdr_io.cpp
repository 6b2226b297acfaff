// Radiance HDR (RGBE): one shared 8-bit exponent per pixel, about 1% relative precision.
//
// Writing uses stbi_write_hdr_to_func (run-length encoded scanlines, "-Y h +X w" = top row
// first) through the AtomicFileWriter. Reading is our own decoder rather than stbi_loadf: the
// stb version we build against loops forever on a zero-length run, which is exactly what a
// truncated file produces (stb reads zeros past the end), and it silently returns zeros for
// truncated flat data. The decoder accepts what stb accepts (flat or new-style RLE scanlines,
// "-Y h +X w" layout) and reports every defect. No transfer function is applied: RGBE stores
// linear radiance. The EXPOSURE header is ignored, as stb does.
#include "image/image_io_detail.h"

#include <stb_image_write.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace rayproc::image_detail {

namespace {

void writeToAtomicFile(void* context, void* data, int size) {
    static_cast<AtomicFileWriter*>(context)->write(data, static_cast<std::size_t>(size));
}

// A cursor over the file's bytes.
struct ByteReader {
    const std::vector<unsigned char>& bytes;
    std::size_t pos = 0;
    bool atEnd() const { return pos >= bytes.size(); }
    // One header line without its '\n'; false at the end of the file.
    bool line(std::string& out) {
        if (atEnd()) return false;
        out.clear();
        while (pos < bytes.size() && bytes[pos] != '\n') out += char(bytes[pos++]);
        if (pos < bytes.size()) ++pos;
        return true;
    }
};

// RGBE -> linear float, bit-identical to stb's decoder: mantissa * 2^(exponent - 136).
void rgbeToFloat(const unsigned char* rgbe, float* rgb) {
    float scale = rgbe[3] ? std::ldexp(1.0f, int(rgbe[3]) - (128 + 8)) : 0.0f;
    for (int c = 0; c < 3; ++c) rgb[c] = float(rgbe[c]) * scale;
}

// Decodes one scanline of `width` RGBE pixels into `rgbe`; returns an error text or "".
std::string readScanline(ByteReader& in, int width, std::vector<unsigned char>& rgbe) {
    const auto& b = in.bytes;
    bool rle = width >= 8 && width < 32768 && in.pos + 4 <= b.size() && b[in.pos] == 2 &&
               b[in.pos + 1] == 2 && (b[in.pos + 2] & 0x80) == 0;
    if (!rle) {
        std::size_t size = std::size_t(width) * 4;
        if (b.size() - in.pos < size) return "truncated pixel data";
        std::copy_n(b.begin() + std::ptrdiff_t(in.pos), size, rgbe.begin());
        in.pos += size;
        return "";
    }
    int encodedWidth = (b[in.pos + 2] << 8) | b[in.pos + 3];
    in.pos += 4;
    if (encodedWidth != width) return "scanline length does not match the image width";
    // Each of the 4 components is stored separately as runs (count > 128: repeat the next
    // byte count - 128 times) and dumps (count <= 128: copy the next count bytes).
    for (int c = 0; c < 4; ++c) {
        int x = 0;
        while (x < width) {
            if (in.atEnd()) return "truncated pixel data";
            int count = b[in.pos++];
            bool run = count > 128;
            if (run) count -= 128;
            if (count == 0 || count > width - x) return "bad run-length encoding";
            std::size_t needed = run ? 1 : std::size_t(count);
            if (b.size() - in.pos < needed) return "truncated pixel data";
            for (int i = 0; i < count; ++i, ++x)
                rgbe[std::size_t(x) * 4 + c] = b[run ? in.pos : in.pos + std::size_t(i)];
            in.pos += needed;
        }
    }
    return "";
}

} // namespace

void writeHdr(const std::string& path, const Image& img) {
    // RGBE holds no negatives, NaN or infinity, and its exponent byte overflows at 2^127:
    // store the nearest representable radiance instead of letting the encoder wrap around.
    std::vector<float> rgb(img.pixels.size());
    std::transform(img.pixels.begin(), img.pixels.end(), rgb.begin(),
                   [](float v) { return v > 0.0f ? std::min(v, 1e38f) : 0.0f; });
    AtomicFileWriter out(path);
    if (!stbi_write_hdr_to_func(writeToAtomicFile, &out, img.width, img.height, 3, rgb.data()))
        out.fail("the Radiance HDR encoder failed (out of memory?)");
    out.commit();
}

Image readHdr(const std::string& path) {
    std::vector<unsigned char> bytes;
    {
        FileReader file(path);
        bytes.resize(file.remainingBytes());
        if (std::fread(bytes.data(), 1, bytes.size(), file.get()) != bytes.size())
            throwReadError(path, "read error: " + errnoText(errno));
    }
    ByteReader in{bytes};
    std::string line;
    if (!in.line(line) || (line != "#?RADIANCE" && line != "#?RGBE"))
        throwReadError(path, "not a Radiance HDR file (expected a \"#?RADIANCE\" or \"#?RGBE\" "
                             "first line)");
    // Header variables up to an empty line; only the pixel format matters to us.
    while (true) {
        if (!in.line(line)) throwReadError(path, "truncated Radiance HDR header");
        if (line.empty()) break;
        if (line.rfind("FORMAT=", 0) == 0 && line != "FORMAT=32-bit_rle_rgbe")
            throwReadError(path, "unsupported Radiance pixel format \"" + line.substr(7) +
                                     "\" (expected 32-bit_rle_rgbe)");
    }
    int width = 0, height = 0, consumed = 0;
    if (!in.line(line) ||
        std::sscanf(line.c_str(), "-Y %d +X %d%n", &height, &width, &consumed) != 2 ||
        consumed != int(line.size()) || width <= 0 || height <= 0)
        throwReadError(path, "unsupported Radiance resolution line \"" + line +
                                 "\" (expected \"-Y <height> +X <width>\")");
    // Every pixel takes at least one byte even when run-length encoded: reject impossible sizes
    // before allocating.
    if (std::uint64_t(width) * std::uint64_t(height) > (bytes.size() - in.pos) * 64 + 64)
        throwReadError(path, "truncated Radiance HDR pixel data");

    Image img(width, height);
    std::vector<unsigned char> rgbe(std::size_t(width) * 4);
    for (int y = 0; y < height; ++y) {
        std::string error = readScanline(in, width, rgbe);
        if (!error.empty())
            throwReadError(path, "corrupt Radiance HDR file: " + error + " in scanline " +
                                     std::to_string(y) + " of " + std::to_string(height));
        for (int x = 0; x < width; ++x) rgbeToFloat(&rgbe[std::size_t(x) * 4], img.at(x, y));
    }
    return img;
}

} // namespace rayproc::image_detail
