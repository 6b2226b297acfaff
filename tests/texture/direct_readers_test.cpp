// Texture files read without OpenImageIO (texture/direct_readers.h) must give exactly the floats
// OpenImageIO's readers give for the same file, so that which reader read a texture never shows
// in an image: every byte value of top-down and bottom-up TGAs, grey and colour, and PFMs; what
// is left to OpenImageIO (an alpha channel, run-length encoding, a short file, other formats) is
// left to it.
#include "test_util.h"

#include "image/image.h"
#include "texture/direct_readers.h"
#include "texture/oiio_module.h"

#include <catch2/catch.hpp>

#include <cstdint>
#include <fstream>
#include <memory>
#include <vector>

using namespace rayproc;
using namespace rayproc::test;

namespace {

// A TGA of `depth` bits (8 grey, 24 or 32 colour), `width` x `height` pixels with values
// value(x, y, channel) (BGR(A) order in the file), raw or run-length encoded (each pixel its
// own raw packet, the last row one run), top-down or bottom-up.
void writeTga(const std::string& path, int width, int height, int depth, bool rle, bool topDown,
              int (*value)(int, int, int)) {
    const int n = depth / 8;
    std::vector<unsigned char> bytes(18, 0);
    bytes[2] = std::uint8_t(n == 1 ? (rle ? 11 : 3) : (rle ? 10 : 2));
    bytes[12] = std::uint8_t(width & 0xff), bytes[13] = std::uint8_t(width >> 8);
    bytes[14] = std::uint8_t(height & 0xff), bytes[15] = std::uint8_t(height >> 8);
    bytes[16] = std::uint8_t(depth);
    bytes[17] = std::uint8_t((topDown ? 0x20 : 0) | (n == 4 ? 8 : 0));
    for (int row = 0; row < height; ++row) {
        int y = topDown ? row : height - 1 - row;
        bool runRow = rle && row == height - 1 && width <= 128;
        if (runRow) bytes.push_back(std::uint8_t(0x80 | (width - 1)));
        for (int x = 0; x < (runRow ? 1 : width); ++x) {
            if (rle && !runRow) bytes.push_back(0); // a raw packet of one pixel
            for (int c = 0; c < n; ++c) {
                int ch = n >= 3 && c < 3 ? 2 - c : c; // the file stores blue first
                bytes.push_back(std::uint8_t(value(x, y, ch)));
            }
        }
    }
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                                std::streamsize(bytes.size()));
}

RawPixels throughOiio(const std::string& path) {
    const OiioModule& m = OiioModule::get();
    char error[256] = "";
    RayprocOiioInfo info{};
    std::unique_ptr<void, RayprocOiioCloseFn> in(m.open(path.c_str(), &info, error, sizeof error),
                                                 m.close);
    INFO(error);
    REQUIRE(in);
    RawPixels raw;
    raw.width = info.width;
    raw.height = info.height;
    raw.channels = info.channels;
    raw.alphaChannel = info.alphaChannel;
    raw.isFloat = info.isFloat != 0;
    raw.pixels.resize(std::size_t(raw.width) * raw.height * raw.channels);
    REQUIRE(m.read(in.get(), raw.pixels.data(), error, sizeof error));
    return raw;
}

void requireSameAsOiio(const std::string& path) {
    RawPixels direct;
    REQUIRE(readWithoutOiio(path, direct));
    RawPixels oiio = throughOiio(path);
    REQUIRE(direct.width == oiio.width);
    REQUIRE(direct.height == oiio.height);
    REQUIRE(direct.isFloat == oiio.isFloat);
    REQUIRE(oiio.alphaChannel < 0);
    // A grey PFM comes back as three equal channels where OpenImageIO gives one: the texture
    // loader repeats a grey file's channel, so both give the same texels.
    const std::size_t pixels = std::size_t(direct.width) * direct.height;
    for (std::size_t i = 0; i < pixels; ++i)
        for (int c = 0; c < direct.channels; ++c) {
            int oc = oiio.channels >= 3 ? c : 0;
            INFO("pixel " << i << " channel " << c);
            const std::size_t at = i * direct.channels + c;
            // The TGA reader keeps its bytes: each stands for byteSample(b).
            const float value = direct.bytes ? byteSample(direct.bytes.get()[at])
                                             : direct.pixels[at];
            REQUIRE(value == oiio.pixels[i * oiio.channels + oc]);
        }
}

int byteRamp(int x, int y, int c) { return (x + 16 * y + 85 * c) & 0xff; }

} // namespace

TEST_CASE("direct texture readers: raw TGAs read as OpenImageIO reads them to every byte value",
          "[texture][oiio]") {
    TempDir dir;
    int k = 0;
    for (int depth : {8, 24})
        for (bool rle : {false, true})
            for (bool topDown : {false, true}) {
                std::string path = (dir.path / ("t" + std::to_string(k++) + ".tga")).string();
                writeTga(path, 16, 16, depth, rle, topDown, byteRamp);
                INFO(depth << " bits, rle " << rle << ", top-down " << topDown);
                if (!rle) {
                    requireSameAsOiio(path);
                    continue;
                }
                RawPixels raw;
                CHECK_FALSE(readWithoutOiio(path, raw));
                RawPixels oiio = throughOiio(path); // which reads it
                CHECK(oiio.width == 16);
            }
}

TEST_CASE("direct texture readers: PFMs read as OpenImageIO reads them and other files are left "
          "to it", "[texture][oiio]") {
    TempDir dir;
    Image img(5, 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x)
            for (int c = 0; c < 3; ++c) img.at(x, y)[c] = float(x) * 0.37f - float(y) + 1e-3f * float(c);
    std::string pfm = (dir.path / "ramp.pfm").string();
    writeImage(pfm, img);
    requireSameAsOiio(pfm);

    // Left to OpenImageIO: a TGA with alpha (which it premultiplies), any other format.
    RawPixels raw;
    std::string alpha = (dir.path / "alpha.tga").string();
    writeTga(alpha, 4, 4, 32, false, true, byteRamp);
    CHECK_FALSE(readWithoutOiio(alpha, raw));
    std::string png = (dir.path / "ramp.png").string();
    writeImage(png, img);
    CHECK_FALSE(readWithoutOiio(png, raw));
    // A truncated TGA: refused here, for OpenImageIO to say what is wrong.
    std::string cut = (dir.path / "cut.tga").string();
    writeTga(cut, 16, 16, 24, false, true, byteRamp);
    std::filesystem::resize_file(cut, 100);
    CHECK_FALSE(readWithoutOiio(cut, raw));
}
