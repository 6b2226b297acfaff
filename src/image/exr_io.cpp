// OpenEXR: 32-bit float R, G, B scanlines, ZIP compressed, via Imf::OutputFile / Imf::InputFile.
//
// Writing goes through an Imf::OStream over the AtomicFileWriter rather than a file name.
// OpenEXR writes the line-offset table from ~OutputFile() and swallows any exception there, so
// a by-name write could silently lose a "disk full" at that point; our stream records it in the
// writer instead, and commit() refuses to publish the file. Iex exceptions are rethrown as
// ImageIoError naming the file.
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
#include <cstdint>
#include <new>

namespace rayproc::image_detail {

namespace {

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

void writeExr(const std::string& path, const Image& img) {
    AtomicFileWriter out(path);
    try {
        Imf::Header header(img.width, img.height);
        header.compression() = Imf::ZIP_COMPRESSION;
        Imf::FrameBuffer frameBuffer;
        for (int c = 0; c < 3; ++c) {
            header.channels().insert(kChannels[c], Imf::Channel(Imf::FLOAT));
            frameBuffer.insert(kChannels[c], Imf::Slice::Make(Imf::FLOAT, img.pixels.data() + c,
                                                              header.dataWindow(), kPixelStride,
                                                              kPixelStride * img.width));
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
} // namespace

void checkExrHeader(const std::string& path) {
    std::string bytes;
    {
        FileReader in(path);
        char buf[65536];
        std::size_t n;
        while ((n = std::fread(buf, 1, sizeof buf, in.get())) > 0) bytes.append(buf, n);
    }
    if (bytes.size() < 8 || bytes.compare(0, 4, "\x76\x2f\x31\x01") != 0) return;
    const std::uint32_t flags = std::uint32_t(std::uint8_t(bytes[5])) |
                                std::uint32_t(std::uint8_t(bytes[6])) << 8 |
                                std::uint32_t(std::uint8_t(bytes[7])) << 16;
    const bool multipart = (flags & 0x1000u) != 0; // bit 12 of the version field
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
        for (;;) {
            std::string name = cString();
            if (name.empty()) break;
            std::string type = cString();
            if (bytes.size() - pos < 4) throwReadError(path, "truncated EXR header");
            std::uint32_t size = std::uint32_t(std::uint8_t(bytes[pos])) |
                                 std::uint32_t(std::uint8_t(bytes[pos + 1])) << 8 |
                                 std::uint32_t(std::uint8_t(bytes[pos + 2])) << 16 |
                                 std::uint32_t(std::uint8_t(bytes[pos + 3])) << 24;
            pos += 4;
            if (size > bytes.size() - pos)
                throwReadError(path, "corrupt EXR header: the attribute \"" + printable(name) +
                                         "\" (" + printable(type) + ") claims " +
                                         std::to_string(size) +
                                         " bytes, but the file has " +
                                         std::to_string(bytes.size() - pos) + " left");
            // The C++ library reads a channel list up to its terminating NUL, not by its size:
            // the two must agree, or the library reads the attributes after it from other
            // offsets (a 1.1 GB opaque attribute, found by the fuzzer).
            if (type == "chlist") {
                std::size_t end = pos + size, p = pos;
                while (p < end && bytes[p] != '\0') {
                    std::size_t nameEnd = bytes.find('\0', p);
                    if (nameEnd == std::string::npos || nameEnd >= end) break;
                    p = nameEnd + 1 + 16; // pixel type, pLinear, reserved, x and y sampling
                }
                if (size == 0 || p != end - 1)
                    throwReadError(path, "corrupt EXR header: the channel list's entries do not "
                                         "end where its size (" + std::to_string(size) +
                                         " bytes) says");
            }
            pos += size;
        }
        if (!multipart) break;
    }

    // The C++ library does not read every attribute by its size field (a channel list is read
    // up to its terminator), so a header can be consistent for the walk above and still lead
    // it to an arbitrary size field (1.9 GB, found by the fuzzer). OpenEXRCore's reader
    // validates each attribute against its type and the file and allocates nothing
    // unreasonable: a header it refuses is not handed to the C++ library.
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
        throwReadError(path, "corrupt EXR header: " +
                                 printable(coreError.message.empty()
                                               ? exr_get_default_error_message(r)
                                               : coreError.message,
                                           160));
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
        checkClaimedSize(path, w, h, fileSize(path));
        Image img(static_cast<int>(w), static_cast<int>(h));

        // Any stored pixel type (HALF, FLOAT, UINT) is converted to float by the library.
        Imf::FrameBuffer frameBuffer;
        for (int c = 0; c < 3; ++c)
            frameBuffer.insert(kChannels[c],
                               Imf::Slice::Make(Imf::FLOAT, img.pixels.data() + c, window,
                                                kPixelStride, kPixelStride * img.width));
        file.setFrameBuffer(frameBuffer);
        file.readPixels(window.min.y, window.max.y);
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
