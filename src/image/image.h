// Image: the renderer's output buffer, and its reading and writing in PNG, EXR, HDR and PFM.
//
// Pixels are linear RGB radiance. Float formats (EXR, PFM, HDR) store them as they are; PNG
// stores 8-bit sRGB after exposure and a tone map (see ToneMap). Every writer is atomic: the
// destination either keeps its old contents or receives the complete new file, never a part.
// Every I/O failure is reported as an ImageIoError whose message names the file and the cause.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace rayproc {

// Linear RGB radiance, row-major, top row first, 3 floats per pixel.
struct Image {
    int width = 0, height = 0;
    std::vector<float> pixels; // size width*height*3

    Image() = default;
    // Zero-filled; negative sizes throw std::invalid_argument.
    Image(int w, int h);

    // The 3 floats (R, G, B) of pixel (x, y); (0, 0) is the top-left pixel.
    float* at(int x, int y);
    const float* at(int x, int y) const;
};

// How radiance above 1 is brought into the displayable range [0, 1] for 8-bit output.
// All operators see the exposure-scaled value and clamp negatives and NaN to 0.
enum class ToneMap {
    Clamp,    // min(x, 1): exact below 1, hard clip above
    Reinhard, // x / (1 + x) per channel: never clips, compresses highlights, darkens midtones
    Aces,     // Narkowicz's ACES filmic fit x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14), clamped
};

struct ToneMapSettings {
    float exposure = 0.0f; // in stops: radiance is scaled by 2^exposure before the tone map
    ToneMap op = ToneMap::Clamp;
};

// Thrown for every I/O failure; what() is a complete user-facing message naming the file and
// the cause (errno text where applicable).
class ImageIoError : public std::runtime_error {
    using std::runtime_error::runtime_error;
};

enum class ImageFormat { Png, Exr, Hdr, Pfm };

// The format of `path` by its extension, case-insensitive; an unknown extension throws an
// ImageIoError listing the supported ones (.png .exr .hdr .pfm).
ImageFormat imageFormatFromPath(const std::string& path);

// A named single-channel image beside the RGB one (an EXR layer "name.Y"), one value per pixel.
struct ImageLayer {
    std::string name;
    std::vector<float> values;
};
// Writes `img` as OpenEXR with each layer as the channel "<name>.Y" (tev and compositors show
// them as layers), atomically as writeImage. The path must end in .exr.
void writeExrWithLayers(const std::string& path, const Image& img,
                        const std::vector<ImageLayer>& layers);

// Writes `img` in the format given by the extension of `path`, atomically (temporary file in
// the same directory, fsync, rename). `tm` only affects PNG; the float formats store radiance.
void writeImage(const std::string& path, const Image& img, const ToneMapSettings& tm = {});

// Writes `bytes` to `path` the same atomic way (statistics, logs: any output that must never be
// left half-written). Failures throw ImageIoError "cannot write "<path>": <cause>", and leave
// neither a temporary file nor a changed destination.
void writeFileAtomically(const std::string& path, const std::string& bytes);

// Removes "<path>.tmp.<pid>.<n>" files that a writer of `path` left when it was killed (kill -9
// during --progressive-output) and whose process no longer exists on this machine; files of
// live processes and of other names stay. Returns how many were removed. Never throws.
std::size_t removeStaleTemporaries(const std::string& path);

// Checks on an image file for readers outside src/image (the texture loader's OpenImageIO):
// the file is a regular file of a sane size (not /dev/zero, a FIFO), the EXR header's attribute
// sizes against the file (OpenEXR allocates what they claim), a PNG's chunk CRCs and zlib
// checksum, and a claimed width x height against what a file of its size can hold. Throw
// ImageIoError. A file that cannot be examined (missing) passes: its reader reports that.
void checkImageHeader(const std::string& path);
void checkImageDimensions(const std::string& path, std::int64_t width, std::int64_t height);

// Reads an image as linear RGB floats, in the format given by the extension of `path`.
// PNG is decoded from sRGB to linear; greyscale inputs are replicated to RGB. Devices, FIFOs,
// files over 4 GiB and corrupt files (a PNG chunk's CRC, a zlib checksum) throw ImageIoError.
Image readImage(const std::string& path);

// 8-bit sRGB conversion used by PNG, exposed for tests: exposure, tone map, sRGB OETF, round to
// nearest.
std::uint8_t toSrgb8(float linear, const ToneMapSettings& tm);

// The sRGB transfer functions on [0, 1] (IEC 61966-2-1): linear -> encoded and its exact inverse.
float srgbOetf(float linear);
float srgbToLinear(float encoded);

} // namespace rayproc
