// OpenEXR: 32-bit float R, G, B scanlines, ZIP compressed, via Imf::OutputFile / Imf::InputFile.
//
// Writing goes through an Imf::OStream over the AtomicFileWriter rather than a file name.
// OpenEXR writes the line-offset table from ~OutputFile() and swallows any exception there, so
// a by-name write could silently lose a "disk full" at that point; our stream records it in the
// writer instead, and commit() refuses to publish the file. Iex exceptions are rethrown as
// ImageIoError naming the file. The header carries a checksum of the pixels (exr_checksum.h).
#include "image/exr_checksum.h"
#include "image/image_io_detail.h"

#include <Iex.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <openexr.h>

#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <new>
#include <utility>

namespace rayproc::image_detail {

namespace {

// An OpenEXR file's first four bytes.
constexpr char kExrMagic[4] = {'\x76', '\x2f', '\x31', '\x01'};

constexpr const char* kChannels[3] = {"R", "G", "B"};
constexpr std::size_t kPixelStride = 3 * sizeof(float);

// Imf::OStream over an AtomicFileWriter. OpenEXR expects write and seek failures as exceptions;
// the writer keeps the first failure so commit() reports it even if OpenEXR swallowed it.
class AtomicExrStream : public Imf::OStream {
public:
    explicit AtomicExrStream(AtomicFileWriter& out)
        : Imf::OStream(out.tempPath().c_str()), m_out(out) {}

    void write(const char c[], int n) override {
        if (!m_out.write(c, static_cast<std::size_t>(n))) throw Iex::IoExc(m_out.error());
    }
    uint64_t tellp() override { return m_out.tell(); }
    void seekp(uint64_t pos) override {
        if (!m_out.seek(pos)) throw Iex::IoExc(m_out.error());
    }

private:
    AtomicFileWriter& m_out;
};

std::string channelNames(const Imf::ChannelList& channels) {
    std::string names;
    for (auto it = channels.begin(); it != channels.end(); ++it)
        names += (names.empty() ? "" : ", ") + std::string(it.name());
    return names.empty() ? "none" : names;
}

} // namespace

void writeExr(const std::string& path, const Image& img, const std::vector<ImageLayer>& layers) {
    const std::size_t pixels = std::size_t(img.width) * std::size_t(img.height);
    for (const ImageLayer& l : layers)
        if (l.values.size() != pixels)
            throw ImageIoError("cannot write \"" + path + "\": layer " + l.name + " has " +
                               std::to_string(l.values.size()) + " values for " +
                               std::to_string(pixels) + " pixels");
    AtomicFileWriter out(path);
    try {
        Imf::Header header(img.width, img.height);
        header.compression() = Imf::ZIP_COMPRESSION;
        addExrChecksum(header, img); // OpenEXR has none of its own (exr_checksum.h)
        Imf::FrameBuffer frameBuffer;
        for (int c = 0; c < 3; ++c) {
            header.channels().insert(kChannels[c], Imf::Channel(Imf::FLOAT));
            frameBuffer.insert(kChannels[c], Imf::Slice::Make(Imf::FLOAT, img.pixels.data() + c,
                                                              header.dataWindow(), kPixelStride,
                                                              kPixelStride * img.width));
        }
        for (const ImageLayer& l : layers) {
            const std::string channel = l.name + ".Y";
            header.channels().insert(channel, Imf::Channel(Imf::FLOAT));
            frameBuffer.insert(channel, Imf::Slice::Make(Imf::FLOAT, l.values.data(),
                                                         header.dataWindow(), sizeof(float),
                                                         sizeof(float) * std::size_t(img.width)));
        }
        AtomicExrStream stream(out);
        Imf::OutputFile file(stream, header);
        file.setFrameBuffer(frameBuffer);
        file.writePixels(img.height);
    } catch (const std::exception& e) {
        out.fail(std::string("OpenEXR: ") + e.what());
    }
    out.commit();
}

namespace {
// An attribute name as it may be shown: printable ASCII, at most 40 characters.
std::string printable(const std::string& text, std::size_t limit = 40) {
    std::string out;
    for (char c : text.substr(0, limit)) out += (c >= 32 && c < 127) ? c : '?';
    return text.size() > limit ? out + "..." : out;
}

std::uint32_t le32At(const std::string& bytes, std::size_t pos) {
    return std::uint32_t(std::uint8_t(bytes[pos])) |
           std::uint32_t(std::uint8_t(bytes[pos + 1])) << 8 |
           std::uint32_t(std::uint8_t(bytes[pos + 2])) << 16 |
           std::uint32_t(std::uint8_t(bytes[pos + 3])) << 24;
}

// The value sizes of the fixed-size attribute types the C++ library knows. It reads these many
// bytes whatever the size field says, so a size field that disagrees moves it off the walk.
int fixedAttributeSize(const std::string& type) {
    static const std::pair<const char*, int> kSizes[] = {
        {"box2i", 16},      {"box2f", 16},   {"chromaticities", 32},
        {"compression", 1}, {"double", 8},   {"envmap", 1},
        {"float", 4},       {"int", 4},      {"keycode", 28},
        {"lineOrder", 1},   {"m33f", 36},    {"m33d", 72},
        {"m44f", 64},       {"m44d", 128},   {"rational", 8},
        {"tiledesc", 9},    {"timecode", 8}, {"v2i", 8},
        {"v2f", 8},         {"v2d", 16},     {"v3i", 12},
        {"v3f", 12},        {"v3d", 24},     {"deepImageState", 1}};
    for (const auto& [name, size] : kSizes)
        if (type == name) return size;
    return -1;
}

// Scan lines per compressed chunk, by OpenEXR's compression code (NONE .. DWAB).
constexpr int kLinesPerChunk[] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};

// Inflating one chunk: no codec OpenEXR has packs much more than deflate's 1032:1 into a byte
// of the file; the slack admits small images in small files.
constexpr double kMaxDecodedBytesPerFileByte = 1100.0;
constexpr double kDecodeSlackBytes = 16.0 * 1024 * 1024;

// What one part's header says about the buffers the C++ library will allocate for it.
struct ExrPart {
    bool hasWindow = false;
    std::int64_t x0 = 0, y0 = 0, x1 = -1, y1 = -1;
    int compression = 0;
    std::int64_t pixelBytes = 0; // bytes of one pixel over all channels (unsubsampled)
    bool tiled = false;
    std::int64_t tileW = 0, tileH = 0;
    std::int64_t chunkCount = -1; // a multi-part file's "chunkCount" attribute, if any
};

// Refuses a part whose chunk offset table, decoding buffer or image would be larger than the
// file can account for: OpenEXR allocates these while opening the file (805 MB for a 16-row
// ZIP buffer of a 4-million-pixel-wide window in a 300-byte file, found by the image fuzzer).
void checkExrPart(const std::string& path, const ExrPart& part, std::uint64_t fileBytes) {
    // A multi-part file states its parts' offset-table lengths, and the library allocates them.
    if (part.chunkCount != -1 &&
        (part.chunkCount < 0 || double(part.chunkCount) * 8.0 > double(fileBytes)))
        throwReadError(path, "the header's chunkCount " + std::to_string(part.chunkCount) +
                                 " does not fit a file of " + std::to_string(fileBytes) +
                                 " bytes (corrupt file)");
    if (!part.hasWindow) return; // the library refuses a header without a data window
    const std::int64_t w = part.x1 - part.x0 + 1, h = part.y1 - part.y0 + 1;
    if (w <= 0 || h <= 0) throwReadError(path, "invalid EXR data window");
    checkClaimedSize(path, w, h, fileBytes);
    double chunks, chunkBytes;
    if (part.tiled) {
        if (part.tileW <= 0 || part.tileH <= 0)
            throwReadError(path, "corrupt EXR header: a tile size of 0");
        chunks = std::ceil(double(w) / double(part.tileW)) * std::ceil(double(h) / part.tileH);
        chunkBytes = double(part.tileW) * double(part.tileH) * double(part.pixelBytes);
    } else {
        chunks = std::ceil(double(h) / kLinesPerChunk[part.compression]);
        chunkBytes = double(w) * kLinesPerChunk[part.compression] * double(part.pixelBytes);
    }
    // The offset table (8 bytes a chunk, the first mip level's alone for tiled files) is in the
    // file; every chunk's decoded bytes come from its compressed bytes in the file.
    if (chunks * 8.0 > double(fileBytes))
        throwReadError(path, "the header's data window needs " + std::to_string(int64_t(chunks)) +
                                 " chunk offsets, more than a file of " +
                                 std::to_string(fileBytes) +
                                 " bytes can hold (corrupt or truncated file)");
    if (chunkBytes > kMaxDecodedBytesPerFileByte * double(fileBytes) + kDecodeSlackBytes)
        throwReadError(path, "the header claims chunks of " + std::to_string(int64_t(chunkBytes)) +
                                 " decoded bytes, more than a file of " +
                                 std::to_string(fileBytes) +
                                 " bytes can hold (corrupt or truncated file)");
}

std::string readFileBytes(const std::string& path) {
    std::string bytes;
    FileReader in(path);
    char buf[65536];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, in.get())) > 0) bytes.append(buf, n);
    return bytes;
}

// The C++ library reads most types by their layout, not by the size field: the two must agree,
// or it reads the attributes after this one from other offsets (a 1.1 GB opaque attribute,
// found by the fuzzer). The attribute's value is bytes[pos, pos + size); a channel list's
// pixel sizes add up in part.pixelBytes.
void checkAttributeLayout(const std::string& path, const std::string& bytes, std::size_t pos,
                          std::uint32_t size, const std::string& what, const std::string& type,
                          ExrPart& part) {
    auto disagree = [&](const std::string& detail) {
        throwReadError(path, "corrupt EXR header: " + what + " is " + std::to_string(size) +
                                 " bytes long, but " + detail);
    };
    const std::size_t end = pos + size;
    if (int fixed = fixedAttributeSize(type); fixed >= 0) {
        if (size != std::uint32_t(fixed))
            disagree("a " + type + " is " + std::to_string(fixed) + " bytes");
    } else if (type == "chlist") {
        std::size_t p = pos;
        while (p < end && bytes[p] != '\0') {
            std::size_t nameEnd = bytes.find('\0', p);
            if (nameEnd == std::string::npos || nameEnd + 17 > end) break;
            // Pixel type (UINT, HALF, FLOAT), pLinear, reserved, x and y sampling.
            const std::uint32_t pixelType = le32At(bytes, nameEnd + 1);
            part.pixelBytes += pixelType == 1 ? 2 : 4;
            p = nameEnd + 1 + 16;
        }
        if (size == 0 || p != end - 1) disagree("the channel list's entries do not end there");
    } else if (type == "stringvector") {
        std::size_t p = pos;
        while (p < end) {
            if (end - p < 4) break;
            p += 4 + std::size_t(le32At(bytes, p));
        }
        if (p != end) disagree("its strings do not end there");
    } else if (type == "floatvector") {
        if (size % 4 != 0) disagree("floats are 4 bytes each");
    } else if (type == "preview") {
        if (size < 8 || std::uint64_t(le32At(bytes, pos)) * le32At(bytes, pos + 4) * 4 != size - 8)
            disagree("a preview image of that width and height is not");
    } else if (type == "idmanifest") {
        if (size < 8) disagree("a manifest has at least 8");
    }
}

// The attributes that size a part's allocations: its data window, compression, tiles, chunk
// count and type.
void readPartAttribute(const std::string& path, const std::string& bytes, std::size_t pos,
                       std::uint32_t size, const std::string& name, const std::string& type,
                       ExrPart& part) {
    if (type == "box2i" && name == "dataWindow") {
        part.hasWindow = true;
        part.x0 = std::int32_t(le32At(bytes, pos));
        part.y0 = std::int32_t(le32At(bytes, pos + 4));
        part.x1 = std::int32_t(le32At(bytes, pos + 8));
        part.y1 = std::int32_t(le32At(bytes, pos + 12));
    } else if (type == "compression" && name == "compression") {
        part.compression = std::uint8_t(bytes[pos]);
        if (part.compression >= int(std::size(kLinesPerChunk)))
            throwReadError(path, "corrupt EXR header: unknown compression " +
                                     std::to_string(part.compression));
    } else if (type == "tiledesc" && name == "tiles") {
        part.tileW = le32At(bytes, pos);
        part.tileH = le32At(bytes, pos + 4);
    } else if (type == "int" && name == "chunkCount") {
        part.chunkCount = std::int32_t(le32At(bytes, pos));
    } else if (type == "string" && name == "type") {
        part.tiled = bytes.compare(pos, size, "tiledimage") == 0;
    }
}

// Walks the header (with multipart, every part's) attribute by attribute from bytes[8]: each
// attribute's size within the file and agreeing with its type, each part's sizes within what
// the file can hold (checkExrPart).
void walkExrHeaders(const std::string& path, const std::string& bytes) {
    const std::uint32_t flags = le32At(bytes, 4) >> 8;
    const bool multipart = (flags & 0x10u) != 0; // bit 12 of the version field
    const bool tiledFile = (flags & 0x02u) != 0; // bit 9: a single-part tiled file
    std::size_t pos = 8;
    auto cString = [&]() {
        std::size_t end = bytes.find('\0', pos);
        if (end == std::string::npos) throwReadError(path, "truncated EXR header");
        std::string text = bytes.substr(pos, end - pos);
        pos = end + 1;
        return text;
    };
    for (;;) { // one header, or with multipart a list of headers closed by an empty one
        if (multipart && pos < bytes.size() && bytes[pos] == '\0') break;
        ExrPart part;
        part.tiled = tiledFile;
        for (;;) {
            std::string name = cString();
            if (name.empty()) break;
            std::string type = cString();
            if (bytes.size() - pos < 4) throwReadError(path, "truncated EXR header");
            const std::uint32_t size = le32At(bytes, pos);
            pos += 4;
            const std::string what =
                "the attribute \"" + printable(name) + "\" (" + printable(type) + ")";
            if (size > bytes.size() - pos)
                throwReadError(path, "corrupt EXR header: " + what + " claims " +
                                         std::to_string(size) + " bytes, but the file has " +
                                         std::to_string(bytes.size() - pos) + " left");
            checkAttributeLayout(path, bytes, pos, size, what, type, part);
            readPartAttribute(path, bytes, pos, size, name, type, part);
            pos += size;
        }
        checkExrPart(path, part, bytes.size());
        if (!multipart) break;
    }
}

// The C++ library does not read every attribute by its size field (a channel list is read up
// to its terminator), so a header can be consistent for walkExrHeaders and still lead it to an
// arbitrary size field (1.9 GB, found by the fuzzer). OpenEXRCore's reader validates each
// attribute against its type and the file and allocates nothing unreasonable: a header it
// refuses is not handed to the C++ library.
void checkWithOpenExrCore(const std::string& path) {
    struct CoreError {
        std::string message;
    } coreError;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.user_data = &coreError;
    init.error_handler_fn = [](exr_const_context_t ctx, exr_result_t, const char* message) {
        void* user = nullptr;
        if (exr_get_user_data(ctx, &user) == EXR_ERR_SUCCESS && user) {
            auto* e = static_cast<CoreError*>(user);
            if (e->message.empty() && message) e->message = message;
        }
    };
    exr_context_t ctx = nullptr;
    exr_result_t r = exr_start_read(&ctx, path.c_str(), &init);
    if (ctx) exr_finish(&ctx);
    if (r != EXR_ERR_SUCCESS)
        throwReadError(path,
                       "corrupt EXR header: " + printable(coreError.message.empty()
                                                              ? exr_get_default_error_message(r)
                                                              : coreError.message,
                                                          160));
}

} // namespace

bool startsAsExr(const std::string& path) {
    FileReader in(path);
    char head[4];
    return std::fread(head, 1, sizeof head, in.get()) == sizeof head &&
           std::memcmp(head, kExrMagic, sizeof head) == 0;
}

void checkExrHeader(const std::string& path) {
    // The magic number first: a texture of another format is not read whole to find it out.
    if (!startsAsExr(path)) return;
    const std::string bytes = readFileBytes(path);
    if (bytes.size() < 8) return;
    walkExrHeaders(path, bytes);
    checkWithOpenExrCore(path);
}

Image readExr(const std::string& path) {
    // Open once ourselves so that a missing or unreadable file is reported with its errno text,
    // and check the header's sizes before OpenEXR allocates them.
    checkExrHeader(path);
    try {
        Imf::InputFile file(path.c_str());
        const Imf::Header& header = file.header();
        for (const char* name : kChannels)
            if (!header.channels().findChannel(name))
                throwReadError(path, std::string("the EXR file has no \"") + name +
                                         "\" channel (it has: " + channelNames(header.channels()) +
                                         ")");

        // The pixels are the data window (usually equal to the display window).
        const Imath::Box2i& window = header.dataWindow();
        std::int64_t w = std::int64_t(window.max.x) - window.min.x + 1;
        std::int64_t h = std::int64_t(window.max.y) - window.min.y + 1;
        if (w <= 0 || h <= 0 || w > INT_MAX || h > INT_MAX)
            throwReadError(path, "invalid EXR data window");
        Image img(static_cast<int>(w), static_cast<int>(h));

        // Any stored pixel type (HALF, FLOAT, UINT) is converted to float by the library.
        Imf::FrameBuffer frameBuffer;
        for (int c = 0; c < 3; ++c)
            frameBuffer.insert(kChannels[c],
                               Imf::Slice::Make(Imf::FLOAT, img.pixels.data() + c, window,
                                                kPixelStride, kPixelStride * img.width));
        file.setFrameBuffer(frameBuffer);
        file.readPixels(window.min.y, window.max.y);
        verifyExrChecksum(path, header, img);
        return img;
    } catch (const ImageIoError&) {
        throw;
    } catch (const std::bad_alloc&) {
        throwReadError(path, "the EXR image is too large to fit in memory");
    } catch (const std::exception& e) {
        throwReadError(path, std::string("not a valid OpenEXR file (OpenEXR: ") + e.what() + ")");
    }
}

} // namespace rayproc::image_detail

namespace rayproc {

void writeExrWithLayers(const std::string& path, const Image& img,
                        const std::vector<ImageLayer>& layers) {
    image_detail::writeExr(path, img, layers);
}

} // namespace rayproc
