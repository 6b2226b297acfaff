#include "image/exr_checksum.h"

#include "image/image_io_detail.h"

#include <ImfInputFile.h>
#include <ImfIntAttribute.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdio>

namespace rayproc::image_detail {

namespace {

static_assert(std::endian::native == std::endian::little,
              "the EXR checksum is defined over little-endian floats");

std::uint32_t pixelCrc(const Image& img) {
    std::uint32_t crc = std::uint32_t(crc32(0, nullptr, 0));
    const auto* bytes = reinterpret_cast<const Bytef*>(img.pixels.data());
    std::size_t left = img.pixels.size() * sizeof(float);
    while (left > 0) { // zlib takes at most 4 GiB at once
        const uInt n = uInt(std::min<std::size_t>(left, std::size_t(1) << 30));
        crc = std::uint32_t(crc32(crc, bytes, n));
        bytes += n;
        left -= n;
    }
    return crc;
}

std::string hex(std::uint32_t v) {
    char text[16];
    std::snprintf(text, sizeof text, "0x%08x", v);
    return text;
}

} // namespace

void addExrChecksum(Imf::Header& header, const Image& img) {
    header.insert(kExrChecksumAttribute, Imf::IntAttribute(int(pixelCrc(img))));
}

void verifyExrChecksum(const std::string& path, const Imf::Header& header, const Image& img) {
    const auto* stored = header.findTypedAttribute<Imf::IntAttribute>(kExrChecksumAttribute);
    if (!stored) return;
    const std::uint32_t expected = std::uint32_t(stored->value()), actual = pixelCrc(img);
    if (expected != actual)
        throwReadError(path, "corrupt EXR file: its pixels do not match the checksum rayproc "
                             "wrote with them (" + std::string(kExrChecksumAttribute) + " " +
                                 hex(expected) + ", pixels " + hex(actual) +
                                 "); if a tool changed the pixels on purpose and kept rayproc's "
                                 "header, remove that attribute");
}

void checkExrChecksum(const std::string& path) {
    bool has = false;
    try {
        if (!startsAsExr(path)) return; // OpenEXR would refuse it, after opening it
        Imf::InputFile file(path.c_str());
        has = file.header().findTypedAttribute<Imf::IntAttribute>(kExrChecksumAttribute);
    } catch (const std::exception&) {
        return; // not an EXR, or one OpenEXR refuses: the reader will say why
    }
    if (has) readExr(path); // decodes the pixels and compares them with the checksum
}

} // namespace rayproc::image_detail
