// Image storage, the display transform (exposure, tone map, sRGB) and the format dispatch.
// The codecs live in one file per format family: stb_io.cpp (PNG, HDR), exr_io.cpp, pfm_io.cpp.
#include "image/image.h"

#include "image/image_io_detail.h"

#include <algorithm>
#include <cassert>
#include <cctype>
#include <cmath>
#include <cstddef>

namespace rayproc {

using namespace image_detail;

Image::Image(int w, int h) {
    if (w < 0 || h < 0)
        throw std::invalid_argument("Image size must not be negative: " + std::to_string(w) + "x" +
                                    std::to_string(h));
    width = w;
    height = h;
    pixels.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3, 0.0f);
}

float* Image::at(int x, int y) {
    assert(x >= 0 && x < width && y >= 0 && y < height);
    return pixels.data() + (static_cast<std::size_t>(y) * width + x) * 3;
}

const float* Image::at(int x, int y) const {
    assert(x >= 0 && x < width && y >= 0 && y < height);
    return pixels.data() + (static_cast<std::size_t>(y) * width + x) * 3;
}

// Display transform -------------------------------------------------------------------------

float srgbOetf(float linear) {
    // IEC 61966-2-1: a linear toe below 0.0031308, a 1/2.4 power above.
    if (linear <= 0.0031308f) return 12.92f * linear;
    return 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

float srgbToLinear(float encoded) {
    if (encoded <= 0.04045f) return encoded / 12.92f;
    return std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

namespace {

// Maps exposure-scaled radiance x >= 0 into [0, 1].
float applyToneMap(float x, ToneMap op) {
    switch (op) {
    case ToneMap::Clamp:
        return std::min(x, 1.0f);
    case ToneMap::Reinhard:
        return x / (1.0f + x);
    case ToneMap::Aces: {
        // Narkowicz 2015, "ACES Filmic Tone Mapping Curve": a rational fit of the ACES RRT+ODT.
        float v = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
        return std::clamp(v, 0.0f, 1.0f);
    }
    }
    return std::min(x, 1.0f);
}

} // namespace

std::uint8_t toSrgb8(float linear, const ToneMapSettings& tm) {
    float x = linear * std::exp2(tm.exposure);
    // Negative and NaN radiance display as black. Capping at 1e9 keeps the rational tone maps
    // finite (inf/inf would be NaN) while every operator already returns 1 there.
    if (!(x > 0.0f)) x = 0.0f;
    x = std::min(x, 1e9f);
    float encoded = srgbOetf(applyToneMap(x, tm.op));
    return static_cast<std::uint8_t>(std::clamp(encoded, 0.0f, 1.0f) * 255.0f + 0.5f);
}

// Format dispatch ---------------------------------------------------------------------------

ImageFormat imageFormatFromPath(const std::string& path) {
    std::string::size_type dot = path.find_last_of('.');
    std::string::size_type slash = path.find_last_of('/');
    std::string ext;
    if (dot != std::string::npos && (slash == std::string::npos || dot > slash))
        ext = path.substr(dot);
    std::string lower = ext;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (lower == ".png") return ImageFormat::Png;
    if (lower == ".exr") return ImageFormat::Exr;
    if (lower == ".hdr") return ImageFormat::Hdr;
    if (lower == ".pfm") return ImageFormat::Pfm;
    std::string what = ext.empty() ? "no file extension" : "unsupported extension \"" + ext + "\"";
    throw ImageIoError("cannot determine the image format of \"" + path + "\": " + what +
                       "; supported extensions are .png .exr .hdr .pfm");
}

void writeImage(const std::string& path, const Image& img, const ToneMapSettings& tm) {
    ImageFormat format = imageFormatFromPath(path);
    // Validate before touching the file system, so a bad image never creates a temporary file.
    std::size_t expected =
        img.width > 0 && img.height > 0 ? static_cast<std::size_t>(img.width) * img.height * 3 : 0;
    if (img.width <= 0 || img.height <= 0)
        throwWriteError(path, "invalid image size " + std::to_string(img.width) + "x" +
                                  std::to_string(img.height) + " (both must be positive)");
    if (img.pixels.size() != expected)
        throwWriteError(path, "pixel buffer holds " + std::to_string(img.pixels.size()) +
                                  " floats but a " + std::to_string(img.width) + "x" +
                                  std::to_string(img.height) + " RGB image needs " +
                                  std::to_string(expected));
    switch (format) {
    case ImageFormat::Png:
        return writePng(path, img, tm);
    case ImageFormat::Exr:
        return writeExr(path, img);
    case ImageFormat::Hdr:
        return writeHdr(path, img);
    case ImageFormat::Pfm:
        return writePfm(path, img);
    }
}

void checkImageHeader(const std::string& path) {
    if (!image_detail::checkInputFile(path)) return; // the reader says why it cannot open it
    image_detail::checkExrHeader(path);
    image_detail::checkExrChecksum(path);
    image_detail::checkPngFile(path);
}

void checkImageDimensions(const std::string& path, std::int64_t width, std::int64_t height) {
    image_detail::checkClaimedSize(path, width, height, image_detail::fileSize(path));
}

Image readImage(const std::string& path) {
    const ImageFormat format = imageFormatFromPath(path);
    image_detail::checkInputFile(path);
    switch (format) {
    case ImageFormat::Png:
        return readPng(path);
    case ImageFormat::Exr:
        return readExr(path);
    case ImageFormat::Hdr:
        return readHdr(path);
    case ImageFormat::Pfm:
        return readPfm(path);
    }
    throwReadError(path, "unknown image format");
}

} // namespace rayproc
