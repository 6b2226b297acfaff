// Internal to src/image: the checksum rayproc writes into its EXR files' headers.
//
// OpenEXR has no checksum of its own: ZIP-compressed chunks carry zlib's Adler-32, but a chunk
// that does not shrink is stored raw, uncompressed files have none, and the header (a channel's
// pixel type, the data window) has none. One flipped bit there read as an image with changed
// pixels. So rayproc's writer adds the attribute "rayprocPixelCrc32", the CRC-32 of the R, G, B
// pixels as written (little-endian floats, rows top to bottom), and its reader refuses a file
// whose decoded pixels do not match it. Files without the attribute (other writers) are read as
// before: only what OpenEXR itself checks is checked.
#pragma once

#include "image/image.h"

#include <ImfHeader.h>

#include <string>

namespace rayproc::image_detail {

constexpr const char* kExrChecksumAttribute = "rayprocPixelCrc32";

// Adds the checksum of `img` to `header`.
void addExrChecksum(Imf::Header& header, const Image& img);
// Throws a read error naming `path` when `header` has the checksum and `img` does not match it.
void verifyExrChecksum(const std::string& path, const Imf::Header& header, const Image& img);

} // namespace rayproc::image_detail
