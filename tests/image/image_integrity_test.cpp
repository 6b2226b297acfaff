// Corrupt inputs are errors, not images with changed pixels: every single-bit flip of a PNG
// fails its chunk CRC (or the signature), a zlib stream whose Adler-32 is wrong is refused even
// with a matching CRC, and no single-bit flip of an EXR rayproc wrote reads as other pixels (its
// pixel checksum); files that are no regular files or absurdly large never reach a reader. Both readers are checked: readImage
// (stb, OpenEXR) and the texture loader (OpenImageIO).
#include "image/image.h"
#include "texture/texture_image.h"

#include "test_util.h"

#include <catch2/catch.hpp>
#include <zlib.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

using namespace rayproc;
namespace fs = std::filesystem;

namespace {

using test::TempDir;

std::string readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

// A small image with a different value in every channel of every pixel.
Image ramp(int w, int h) {
    Image img(w, h);
    for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = float(i % 97) / 97.0f;
    return img;
}

std::uint32_t be32(const std::string& b, std::size_t at) {
    return std::uint32_t(std::uint8_t(b[at])) << 24 | std::uint32_t(std::uint8_t(b[at + 1])) << 16 |
           std::uint32_t(std::uint8_t(b[at + 2])) << 8 | std::uint32_t(std::uint8_t(b[at + 3]));
}

// Outcome of reading a file: "" when it read, else the error message.
template <typename Read> std::string readError(Read read) {
    try {
        read();
    } catch (const ImageIoError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST_CASE("Every single-bit flip of a PNG is refused by readImage and the texture loader",
          "[image][corrupt]") {
    TempDir dir;
    const std::string good = dir.file("good.png");
    writeImage(good, ramp(6, 5));
    const std::string bytes = readBytes(good);
    REQUIRE(readError([&] { readImage(good); }).empty());
    const std::string bad = dir.file("bad.png");
    std::size_t accepted = 0, flips = 0;
    for (std::size_t byte = 0; byte < bytes.size(); ++byte)
        for (int bit = 0; bit < 8; ++bit) {
            std::string b = bytes;
            b[byte] = char(b[byte] ^ (1 << bit));
            writeBytes(bad, b);
            ++flips;
            if (readError([&] { readImage(bad); }).empty()) {
                ++accepted;
                UNSCOPED_INFO("accepted: byte " << byte << " bit " << bit);
            }
            // OpenImageIO's libpng, on a sample (it is slower to open).
            if ((byte * 8 + bit) % 29 == 0 &&
                readError([&] { loadTextureImage(bad, TextureEncoding{}); }).empty()) {
                ++accepted;
                UNSCOPED_INFO("texture accepted: byte " << byte << " bit " << bit);
            }
        }
    INFO(flips << " flips");
    CHECK(accepted == 0);
}

TEST_CASE("A PNG whose zlib checksum is wrong is refused even when its chunk CRC matches",
          "[image][corrupt]") {
    TempDir dir;
    const std::string path = dir.file("adler.png");
    writeImage(path, ramp(6, 5));
    const std::string good = readBytes(path);
    std::string b = good;
    // The first IDAT chunk: its data ends with the zlib stream's Adler-32.
    const std::size_t idat = b.find("IDAT");
    REQUIRE(idat != std::string::npos);
    const std::size_t length = be32(b, idat - 4), end = idat + 4 + length;
    b[end - 1] = char(b[end - 1] ^ 0x10);
    std::uint32_t crc = std::uint32_t(crc32(0, reinterpret_cast<const Bytef*>(&b[idat]),
                                            uInt(length + 4)));
    for (int i = 0; i < 4; ++i) b[end + std::size_t(i)] = char(crc >> (24 - 8 * i));
    writeBytes(path, b);
    CHECK_THAT(readError([&] { readImage(path); }),
               Catch::Contains("zlib stream is damaged") && Catch::Contains(path));
    CHECK_THAT(readError([&] { loadTextureImage(path, TextureEncoding{}); }),
               Catch::Contains("zlib stream is damaged"));
    // Cut after the (intact) IDAT chunk, the file ends early: refused too.
    writeBytes(path, good.substr(0, end + 4));
    CHECK_THAT(readError([&] { readImage(path); }), Catch::Contains("no IEND chunk"));
}

TEST_CASE("Devices, FIFOs and files over 4 GiB are refused before a reader opens them",
          "[image][corrupt]") {
    TempDir dir;
    fs::create_symlink("/dev/zero", dir.file("zero.png"));
    fs::create_symlink("/dev/zero", dir.file("zero.exr"));
    REQUIRE(::mkfifo(dir.file("pipe.pfm").c_str(), 0600) == 0);
    {
        std::ofstream big(dir.file("big.png"));
    }
    fs::resize_file(dir.file("big.png"), std::uintmax_t(5) << 30); // sparse
    for (const char* name : {"zero.png", "zero.exr"}) {
        INFO(name);
        const std::string path = dir.file(name);
        CHECK_THAT(readError([&] { readImage(path); }),
                   Catch::Contains(path) && Catch::Contains("it is a character device"));
        CHECK_THAT(readError([&] { loadTextureImage(path, TextureEncoding{}); }),
                   Catch::Contains(path) && Catch::Contains("it is a character device"));
    }
    // Without the check, opening the FIFO would wait forever for a writer.
    CHECK_THAT(readError([&] { readImage(dir.file("pipe.pfm")); }),
               Catch::Contains("it is a FIFO (named pipe)"));
    CHECK_THAT(readError([&] { loadTextureImage(dir.file("pipe.pfm"), TextureEncoding{}); }),
               Catch::Contains("it is a FIFO (named pipe)"));
    CHECK_THAT(readError([&] { readImage(dir.file("big.png")); }),
               Catch::Contains("more than the 4 GiB an image file may have"));
}

namespace {

// Finite floats of random bits: ZIP cannot shrink them, so OpenEXR stores every chunk raw,
// without zlib's checksum.
Image noise(int w, int h) {
    Image img(w, h);
    std::uint64_t state = 12345;
    for (float& v : img.pixels) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        const std::uint32_t bits = std::uint32_t(state >> 32) & 0xbfffffffu; // exponent < 128
        std::memcpy(&v, &bits, sizeof v);
    }
    return img;
}

// Single-bit flips of `bytes` at every bit of the first `headerBytes` bytes and every
// `stride`-th bit after: how many read as an image other than `original`.
std::size_t flipsReadChanged(const std::string& bytes, const Image& original,
                             const std::string& path, std::size_t headerBytes, std::size_t stride) {
    std::size_t changed = 0;
    for (std::size_t bitIndex = 0; bitIndex < bytes.size() * 8; ++bitIndex) {
        if (bitIndex >= headerBytes * 8 && bitIndex % stride != 0) continue;
        std::string b = bytes;
        b[bitIndex / 8] = char(b[bitIndex / 8] ^ (1 << (bitIndex % 8)));
        writeBytes(path, b);
        Image img;
        if (!readError([&] { img = readImage(path); }).empty()) continue;
        if (img.width != original.width || img.height != original.height ||
            img.pixels != original.pixels) {
            ++changed;
            UNSCOPED_INFO("read with changed pixels: byte " << bitIndex / 8 << " bit "
                                                            << bitIndex % 8);
        }
    }
    return changed;
}

} // namespace

TEST_CASE("rayproc's EXR files carry a pixel checksum: no flipped bit reads as other pixels",
          "[image][corrupt]") {
    TempDir dir;
    const std::string bad = dir.file("bad.exr");
    // Both kinds of chunk: ZIP-compressed (zlib's Adler-32 guards them) and stored raw (only
    // the checksum does). Without it, 19 header flips of the ramp read as other pixels (a
    // channel's FLOAT read as UINT, the data window) and most flips of the noise did.
    // Every bit of the ramp's header and channel list (where those 19 flips are), a sample of
    // the rest: each read takes milliseconds.
    struct Case {
        Image original;
        std::size_t headerBytes, stride;
    };
    for (const Case& c : {Case{ramp(8, 40), 160, 17}, Case{noise(8, 40), 0, 13}}) {
        const std::string good = dir.file("good.exr");
        writeImage(good, c.original);
        const std::string bytes = readBytes(good);
        CHECK(readImage(good).pixels == c.original.pixels);
        CHECK(flipsReadChanged(bytes, c.original, bad, c.headerBytes, c.stride) == 0);
    }
}

TEST_CASE("A corrupt rayproc EXR is refused by the texture loader too - EXRs of other writers "
          "still read",
          "[image][corrupt]") {
    TempDir dir;
    const std::string path = dir.file("noise.exr");
    const Image original = noise(8, 40);
    writeImage(path, original);
    std::string b = readBytes(path);
    b[b.size() - 100] = char(b[b.size() - 100] ^ 4); // in the last chunk's raw pixels
    writeBytes(path, b);
    CHECK_THAT(readError([&] { readImage(path); }),
               Catch::Contains("do not match the checksum rayproc wrote"));
    CHECK_THAT(readError([&] { loadTextureImage(path, TextureEncoding{}); }),
               Catch::Contains("do not match the checksum rayproc wrote"));

    // Without the attribute (another writer's file) nothing is compared: it reads as it is.
    const std::string plain = dir.file("plain.exr");
    {
        Imf::Header header(original.width, original.height);
        Imf::FrameBuffer frameBuffer;
        const char* names[3] = {"R", "G", "B"};
        for (int c = 0; c < 3; ++c) {
            header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
            frameBuffer.insert(names[c],
                               Imf::Slice::Make(Imf::FLOAT, original.pixels.data() + c,
                                                header.dataWindow(), 12, 12 * original.width));
        }
        Imf::OutputFile file(plain.c_str(), header);
        file.setFrameBuffer(frameBuffer);
        file.writePixels(original.height);
    }
    CHECK(readImage(plain).pixels == original.pixels);
    CHECK(loadTextureImage(plain, TextureEncoding{})->width() == original.width);
}
