// The PNG file's own integrity checks, made before any decoder sees the file.
//
// A PNG protects each chunk with a CRC-32 and its image data with zlib's Adler-32. stb_image
// checks neither, so one flipped bit in a PNG's pixel data read as an image with changed pixels
// (27 of 40 random single-bit flips, issue 36); OpenImageIO's libpng checks only some. Here every
// chunk's length must fit in the file (stb grows its buffer to whatever an IDAT chunk claims),
// every chunk's CRC must match, and the IDAT chunks' zlib stream must inflate to its end, which
// verifies the Adler-32. A single flipped bit anywhere after the signature fails a CRC.
#include "image/image_io_detail.h"

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace rayproc::image_detail {

namespace {

std::uint32_t be32(const unsigned char* p) {
    return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 |
           std::uint32_t(p[3]);
}

std::string hex(std::uint32_t v) {
    char text[16];
    std::snprintf(text, sizeof text, "0x%08x", v);
    return text;
}

// Inflates the concatenated IDAT data into a scratch buffer and throws away the output: only
// whether the stream is intact matters (zlib checks the Adler-32 at its end).
class ZlibCheck {
public:
    explicit ZlibCheck(const std::string& path) : m_path(path) {
        if (inflateInit(&m_stream) != Z_OK) throwReadError(path, "zlib could not be started");
    }
    ~ZlibCheck() { inflateEnd(&m_stream); }
    ZlibCheck(const ZlibCheck&) = delete;
    ZlibCheck& operator=(const ZlibCheck&) = delete;

    void feed(const unsigned char* data, std::size_t size) {
        m_sawData = true;
        m_stream.next_in = const_cast<unsigned char*>(data);
        m_stream.avail_in = uInt(size);
        while (m_stream.avail_in > 0 && !m_ended) {
            m_stream.next_out = m_scratch;
            m_stream.avail_out = sizeof m_scratch;
            int r = inflate(&m_stream, Z_NO_FLUSH);
            if (r == Z_STREAM_END) m_ended = true;
            else if (r != Z_OK && r != Z_BUF_ERROR)
                throwReadError(m_path, std::string("corrupt PNG file: the image data's zlib stream "
                                                   "is damaged (") +
                                           (m_stream.msg ? m_stream.msg : "zlib error") + ")");
        }
    }
    // After the last IDAT chunk: the stream must have reached its end (and its checksum).
    void finish() {
        for (int i = 0; i < 1 << 20 && m_sawData && !m_ended; ++i) { // drain buffered output
            m_stream.next_out = m_scratch;
            m_stream.avail_out = sizeof m_scratch;
            int r = inflate(&m_stream, Z_NO_FLUSH);
            if (r == Z_STREAM_END) m_ended = true;
            else if (r != Z_OK) break;
        }
        if (m_sawData && !m_ended)
            throwReadError(m_path, "corrupt PNG file: the image data's zlib stream ends early "
                                   "(truncated or damaged file)");
    }

private:
    std::string m_path;
    z_stream m_stream{};
    unsigned char m_scratch[65536];
    bool m_sawData = false, m_ended = false;
};

} // namespace

void checkPngFile(const std::string& path) {
    static const unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    FileReader in(path);
    std::FILE* f = in.get();
    unsigned char head[8];
    if (std::fread(head, 1, 8, f) != 8 || std::memcmp(head, kSignature, 8) != 0) return;
    const std::uint64_t size = fileSize(path);
    std::uint64_t pos = 8;
    std::vector<unsigned char> block(65536);
    ZlibCheck zlib(path);
    bool inIdat = false;
    while (pos + 8 <= size && std::fread(head, 1, 8, f) == 8) {
        const std::uint32_t length = be32(head);
        std::string type(reinterpret_cast<const char*>(head + 4), 4);
        for (char& c : type)
            if (c < 32 || c > 126) c = '?';
        const std::uint64_t left = size - pos - 8; // the data and the CRC
        if (std::uint64_t(length) + 4 > left)
            throwReadError(path, "corrupt PNG file: the " + type + " chunk claims " +
                                     std::to_string(length) + " bytes, but the file has " +
                                     std::to_string(left) + " left");
        const bool idat = std::memcmp(head + 4, "IDAT", 4) == 0;
        if (inIdat && !idat) zlib.finish(); // the image data is one run of IDAT chunks
        inIdat = idat;
        // The CRC covers the type and the data; the data is read in blocks, never whole.
        std::uint32_t crc = std::uint32_t(crc32(0, head + 4, 4));
        for (std::uint32_t done = 0; done < length;) {
            const std::size_t n = std::min<std::size_t>(block.size(), length - done);
            if (std::fread(block.data(), 1, n, f) != n)
                throwReadError(path, "reading the file failed");
            crc = std::uint32_t(crc32(crc, block.data(), uInt(n)));
            if (idat) zlib.feed(block.data(), n);
            done += std::uint32_t(n);
        }
        unsigned char stored[4];
        if (std::fread(stored, 1, 4, f) != 4) throwReadError(path, "reading the file failed");
        if (crc != be32(stored))
            throwReadError(path, "corrupt PNG file: the " + type + " chunk at byte " +
                                     std::to_string(pos) + " fails its CRC check (stored " +
                                     hex(be32(stored)) + ", computed " + hex(crc) + ")");
        pos += 12 + std::uint64_t(length);
        if (std::memcmp(head + 4, "IEND", 4) == 0) return;
    }
    throwReadError(path, "corrupt PNG file: no IEND chunk (truncated file)");
}

} // namespace rayproc::image_detail
