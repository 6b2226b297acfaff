// Portable Float Map: a three-line text header, then raw 32-bit floats, bottom row first.
//
//   PF            "PF" colour (3 floats per pixel) or "Pf" greyscale (1 float per pixel)
//   <w> <h>       width and height
//   <scale>       sign gives the byte order (negative: little-endian); magnitude is ignored
//
// The header ends with a single whitespace byte, after which w * h * channels floats follow,
// rows stored from the bottom of the image to the top. We always write colour little-endian.
#include "image/image_io_detail.h"

#include <bit>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace rayproc::image_detail {

namespace {

constexpr bool kHostLittleEndian = std::endian::native == std::endian::little;

float byteSwapped(float v) {
    std::uint32_t bits = std::bit_cast<std::uint32_t>(v);
    bits = (bits >> 24) | ((bits >> 8) & 0xff00u) | ((bits << 8) & 0xff0000u) | (bits << 24);
    return std::bit_cast<float>(bits);
}

// Reads the next whitespace-delimited header token and consumes the one whitespace byte that
// ends it (for the scale, that byte separates the header from the pixel data).
std::string readToken(FileReader& in) {
    int c = std::fgetc(in.get());
    while (c != EOF && std::isspace(c)) c = std::fgetc(in.get());
    std::string token;
    while (c != EOF && !std::isspace(c) && token.size() < 64) {
        token += static_cast<char>(c);
        c = std::fgetc(in.get());
    }
    return token;
}

[[noreturn]] void throwHeaderError(const std::string& path, const std::string& expected,
                                   const std::string& found) {
    throwReadError(path, "malformed PFM header: expected " + expected + ", found " +
                             (found.empty() ? "the end of the file" : "\"" + found + "\""));
}

int parseDimension(const std::string& path, const std::string& token, const char* what) {
    char* end = nullptr;
    errno = 0;
    long value = std::strtol(token.c_str(), &end, 10);
    if (token.empty() || !std::isdigit(static_cast<unsigned char>(token[0])) || *end != '\0' ||
        errno == ERANGE || value <= 0 || value > INT_MAX)
        throwHeaderError(path, std::string("a positive integer ") + what, token);
    return static_cast<int>(value);
}

} // namespace

void writePfm(const std::string& path, const Image& img) {
    AtomicFileWriter out(path);
    std::string header =
        "PF\n" + std::to_string(img.width) + " " + std::to_string(img.height) + "\n-1.0\n";
    out.write(header.data(), header.size());
    // PFM stores the bottom row first; our images are top row first.
    std::vector<float> row(static_cast<std::size_t>(img.width) * 3);
    for (int y = img.height - 1; y >= 0 && !out.failed(); --y) {
        const float* src = img.at(0, y);
        for (std::size_t i = 0; i < row.size(); ++i)
            row[i] = kHostLittleEndian ? src[i] : byteSwapped(src[i]);
        out.write(row.data(), row.size() * sizeof(float));
    }
    out.commit();
}

Image readPfm(const std::string& path) {
    FileReader in(path);
    char magic[2] = {};
    if (std::fread(magic, 1, 2, in.get()) != 2 || magic[0] != 'P' ||
        (magic[1] != 'F' && magic[1] != 'f'))
        throwReadError(path, "malformed PFM header: expected \"PF\" (colour) or \"Pf\" "
                             "(greyscale) at the start of the file");
    int channels = magic[1] == 'F' ? 3 : 1;
    int afterMagic = std::fgetc(in.get());
    if (afterMagic == EOF || !std::isspace(afterMagic))
        throwHeaderError(path, "whitespace after the \"P" + std::string(1, magic[1]) + "\" magic",
                         afterMagic == EOF ? "" : std::string(1, static_cast<char>(afterMagic)));

    int width = parseDimension(path, readToken(in), "width");
    int height = parseDimension(path, readToken(in), "height");
    std::string scaleToken = readToken(in);
    char* end = nullptr;
    double scale = std::strtod(scaleToken.c_str(), &end);
    if (scaleToken.empty() || *end != '\0' || !std::isfinite(scale) || scale == 0.0)
        throwHeaderError(path, "a non-zero scale (negative means little-endian)", scaleToken);
    bool fileLittleEndian = scale < 0.0;

    // Check the size before allocating: a corrupt header must not trigger a huge allocation.
    std::uint64_t rowBytes = std::uint64_t(width) * channels * sizeof(float);
    std::uint64_t available = in.remainingBytes();
    if (std::uint64_t(height) > available / rowBytes)
        throwReadError(path, "truncated PFM pixel data: a " + std::to_string(width) + "x" +
                                 std::to_string(height) + " image needs " +
                                 std::to_string(rowBytes * height) + " bytes but only " +
                                 std::to_string(available) + " follow the header");

    Image img(width, height);
    std::vector<float> row(static_cast<std::size_t>(width) * channels);
    bool swap = fileLittleEndian != kHostLittleEndian;
    for (int fileRow = 0; fileRow < height; ++fileRow) {
        if (std::fread(row.data(), sizeof(float), row.size(), in.get()) != row.size()) {
            int err = errno;
            throwReadError(path, std::ferror(in.get()) ? errnoText(err)
                                                       : "unexpected end of the PFM pixel data");
        }
        float* dst = img.at(0, height - 1 - fileRow);
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c) {
                float v = row[std::size_t(x) * channels + (channels == 3 ? c : 0)];
                dst[x * 3 + c] = swap ? byteSwapped(v) : v;
            }
    }
    return img;
}

} // namespace rayproc::image_detail
