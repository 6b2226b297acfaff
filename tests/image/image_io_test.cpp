// Image I/O: round trips per format, the display transform, PFM row order, format detection,
// atomic writes that leave nothing behind on failure, and corrupt inputs that must not crash.
#include "image/image.h"
#include "skip.h"

#include <catch2/catch.hpp>
#include <zlib.h>

#include <ImfBoxAttribute.h>
#include <ImfChannelList.h>
#include <ImfFloatVectorAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfKeyCodeAttribute.h>
#include <ImfMatrixAttribute.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfPartType.h>
#include <ImfPreviewImageAttribute.h>
#include <ImfRationalAttribute.h>
#include <ImfStandardAttributes.h>
#include <ImfStringVectorAttribute.h>
#include <ImfTiledOutputFile.h>
#include <ImfTimeCodeAttribute.h>
#include <ImfVecAttribute.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <csignal>
#include <fcntl.h>
#include <pwd.h>
#include <sys/resource.h>
#include <unistd.h>

using namespace rayproc;
namespace fs = std::filesystem;

namespace {

// The effective user and group of `nobody` for the scope when the process is root, so that
// file permissions apply; the real and saved ids stay root and the destructor takes root back.
// ok() is false when root cannot change its effective ids (no CAP_SETUID or CAP_SETGID). A
// process that is not root is unprivileged already.
class Unprivileged {
public:
    Unprivileged() : m_gid(::getegid()) {
        if (::geteuid() != 0) {
            m_ok = true;
            return;
        }
        const passwd* pw = ::getpwnam("nobody");
        const uid_t uid = pw ? pw->pw_uid : 65534;
        const gid_t gid = pw ? pw->pw_gid : 65534;
        if (::setegid(gid) != 0) return;
        if (::seteuid(uid) != 0) {
            (void)::setegid(m_gid);
            return;
        }
        m_dropped = m_ok = true;
    }
    ~Unprivileged() {
        if (!m_dropped) return;
        (void)::seteuid(0);
        (void)::setegid(m_gid);
    }
    Unprivileged(const Unprivileged&) = delete;
    Unprivileged& operator=(const Unprivileged&) = delete;
    bool ok() const { return m_ok; }

private:
    gid_t m_gid;
    bool m_ok = false, m_dropped = false;
};

// A fresh directory under the system temp directory, removed (with everything in it) at scope
// exit, even if a test made it read-only.
struct TempDir {
    fs::path path;
    TempDir() {
        static std::atomic<int> counter{0};
        path = fs::temp_directory_path() / ("rayproc_image_test_" + std::to_string(::getpid()) +
                                            "_" + std::to_string(counter++));
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::permissions(path, fs::perms::owner_all, fs::perm_options::add, ec);
        fs::remove_all(path, ec);
    }
    std::string file(const std::string& name) const { return (path / name).string(); }
    std::vector<std::string> entries() const {
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(path)) names.push_back(e.path().filename());
        std::sort(names.begin(), names.end());
        return names;
    }
};

// A non-symmetric image mixing ordinary, bright (> 1) and tiny values.
Image makeTestImage(int w, int h) {
    Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float* p = img.at(x, y);
            p[0] = 0.1f * float(x + 1) + 0.01f * float(y);
            p[1] = float(y * w + x) * 3.75f + 0.5f; // up to well above 1
            p[2] = 1e-7f * float(x + 2 * y + 1);    // tiny
        }
    img.at(0, 0)[0] = 65504.5f;
    img.at(w - 1, h - 1)[2] = 1.17549435e-38f; // smallest normal float
    return img;
}

// The ImageIoError message thrown by `f`; fails the test if `f` throws nothing or another type.
std::string ioErrorMessage(const std::function<void()>& f) {
    try {
        f();
    } catch (const ImageIoError& e) {
        return e.what();
    } catch (const std::exception& e) {
        FAIL("expected ImageIoError, got another exception: " << e.what());
    }
    FAIL("expected ImageIoError, nothing was thrown");
    return {};
}

void writeBytes(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
}

std::string floatBytes(const std::vector<float>& values, bool bigEndian) {
    std::string bytes(values.size() * 4, '\0');
    std::memcpy(bytes.data(), values.data(), bytes.size());
    if (bigEndian)
        for (std::size_t i = 0; i < bytes.size(); i += 4) std::reverse(&bytes[i], &bytes[i + 4]);
    return bytes;
}

} // namespace

TEST_CASE("EXR and PFM round trips are bit-exact", "[image]") {
    TempDir dir;
    Image img = makeTestImage(7, 5);
    img.at(3, 2)[1] = -0.25f; // float formats keep negatives too
    for (const char* name : {"round.exr", "round.pfm"}) {
        INFO(name);
        writeImage(dir.file(name), img);
        Image back = readImage(dir.file(name));
        REQUIRE(back.width == img.width);
        REQUIRE(back.height == img.height);
        REQUIRE(back.pixels.size() == img.pixels.size());
        CHECK(std::memcmp(back.pixels.data(), img.pixels.data(), img.pixels.size() * 4) == 0);
    }
    CHECK(dir.entries() == std::vector<std::string>{"round.exr", "round.pfm"});
}

TEST_CASE("HDR round trip is within RGBE precision", "[image]") {
    TempDir dir;
    // Width 9 is written with run-length encoded scanlines, width 5 with flat ones.
    for (int width : {9, 5}) {
        Image img = makeTestImage(width, 4);
        writeImage(dir.file("round.hdr"), img);
        Image back = readImage(dir.file("round.hdr"));
        REQUIRE(back.width == img.width);
        REQUIRE(back.height == img.height);
        // RGBE shares one exponent per pixel with an 8-bit mantissa: every channel is exact to
        // about 1% of the pixel's largest channel.
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                const float* a = img.at(x, y);
                const float* b = back.at(x, y);
                float largest = std::max({a[0], a[1], a[2]});
                for (int c = 0; c < 3; ++c) CHECK(std::abs(b[c] - a[c]) <= 0.01f * largest);
            }
    }
}

TEST_CASE("PNG round trip matches the 8-bit sRGB quantisation", "[image]") {
    TempDir dir;
    Image img = makeTestImage(6, 6);
    for (ToneMapSettings tm : {ToneMapSettings{}, ToneMapSettings{-2.0f, ToneMap::Reinhard},
                               ToneMapSettings{1.0f, ToneMap::Aces}}) {
        writeImage(dir.file("round.png"), img, tm);
        Image back = readImage(dir.file("round.png"));
        REQUIRE(back.width == img.width);
        REQUIRE(back.height == img.height);
        for (std::size_t i = 0; i < img.pixels.size(); ++i) {
            float expected = srgbToLinear(float(toSrgb8(img.pixels[i], tm)) / 255.0f);
            CHECK(back.pixels[i] == Approx(expected).margin(1e-6));
            // And the stored byte is within one quantisation step of the exact encoding.
            CHECK(std::abs(srgbOetf(back.pixels[i]) * 255.0f - float(toSrgb8(img.pixels[i], tm))) <
                  0.01f);
        }
    }
    CHECK(dir.entries() == std::vector<std::string>{"round.png"});
}

TEST_CASE("PFM keeps the top-left pixel top-left and stores the bottom row first", "[image]") {
    TempDir dir;
    Image img(2, 3); // pixel (x, y) holds (x, y, 10 * y + x): no symmetry to hide a flip
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 2; ++x) {
            float* p = img.at(x, y);
            p[0] = float(x), p[1] = float(y), p[2] = float(10 * y + x);
        }
    writeImage(dir.file("orient.pfm"), img);
    Image back = readImage(dir.file("orient.pfm"));
    CHECK(back.pixels == img.pixels);
    CHECK(back.at(0, 0)[2] == 0.0f);
    CHECK(back.at(1, 2)[2] == 21.0f);

    // On disk: header, then the bottom row (y = 2) first, little-endian.
    std::ifstream in(dir.file("orient.pfm"), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string header = "PF\n2 3\n-1.0\n";
    REQUIRE(bytes.size() == header.size() + 2 * 3 * 3 * 4);
    CHECK(bytes.substr(0, header.size()) == header);
    CHECK(bytes.substr(header.size(), 12) == floatBytes({0.0f, 2.0f, 20.0f}, false));
}

TEST_CASE("PFM reader accepts big-endian and greyscale files", "[image]") {
    TempDir dir;
    // 2x1 big-endian colour file (positive scale).
    writeBytes(dir.file("be.pfm"), "PF\n2 1\n1.0\n" + floatBytes({1, 2, 3, 4, 5, 6}, true));
    Image be = readImage(dir.file("be.pfm"));
    CHECK(be.pixels == std::vector<float>{1, 2, 3, 4, 5, 6});
    // 1x2 little-endian greyscale, bottom row first: replicated to RGB.
    writeBytes(dir.file("grey.PFM"), "Pf\n1 2\n-1\n" + floatBytes({0.25f, 0.75f}, false));
    Image grey = readImage(dir.file("grey.PFM"));
    CHECK(grey.pixels == std::vector<float>{0.75f, 0.75f, 0.75f, 0.25f, 0.25f, 0.25f});
}

TEST_CASE("toSrgb8 applies exposure, the tone map and the sRGB curve", "[image]") {
    ToneMapSettings clamp;
    CHECK(toSrgb8(0.0f, clamp) == 0);
    CHECK(toSrgb8(1.0f, clamp) == 255);
    CHECK(toSrgb8(0.5f, clamp) == 188);
    CHECK(toSrgb8(7.0f, clamp) == 255);
    CHECK(toSrgb8(-1.0f, clamp) == 0);
    CHECK(toSrgb8(std::nanf(""), clamp) == 0);

    ToneMapSettings plusOne{1.0f, ToneMap::Clamp};
    for (float v : {0.01f, 0.1f, 0.25f, 0.4f})
        CHECK(toSrgb8(v, plusOne) == toSrgb8(2.0f * v, clamp));

    ToneMapSettings reinhard{0.0f, ToneMap::Reinhard};
    CHECK(toSrgb8(1.0f, reinhard) == toSrgb8(0.5f, clamp));
    CHECK(toSrgb8(1e30f, reinhard) == 255);
    CHECK(toSrgb8(INFINITY, reinhard) == 255);

    ToneMapSettings aces{0.0f, ToneMap::Aces};
    CHECK(toSrgb8(0.0f, aces) == 0);
    CHECK(toSrgb8(100.0f, aces) == 255);
    CHECK(toSrgb8(INFINITY, aces) == 255);
    // Narkowicz's fit is pre-exposed: 1 maps to 2.54 / 3.16 (about 0.8).
    CHECK(toSrgb8(1.0f, aces) == toSrgb8(2.54f / 3.16f, clamp));
    for (float v = 0.0f; v < 16.0f; v += 0.125f)
        CHECK(toSrgb8(v, aces) <= toSrgb8(v + 0.125f, aces));
}

TEST_CASE("Image format is detected from the extension", "[image]") {
    CHECK(imageFormatFromPath("out.png") == ImageFormat::Png);
    CHECK(imageFormatFromPath("dir.v2/OUT.PNG") == ImageFormat::Png);
    CHECK(imageFormatFromPath("a.Exr") == ImageFormat::Exr);
    CHECK(imageFormatFromPath("a.HDR") == ImageFormat::Hdr);
    CHECK(imageFormatFromPath("a.pfm") == ImageFormat::Pfm);
    std::string jpg = ioErrorMessage([] { imageFormatFromPath("photo.jpg"); });
    CHECK_THAT(jpg,
               Catch::Contains(".png") && Catch::Contains(".jpg") && Catch::Contains("photo.jpg"));
    CHECK_THAT(ioErrorMessage([] { imageFormatFromPath("dir.v2/noext"); }),
               Catch::Contains("no file extension"));
}

TEST_CASE("Writing into a missing directory fails cleanly", "[image]") {
    TempDir dir;
    Image img = makeTestImage(3, 2);
    for (const char* name : {"out.png", "out.exr", "out.hdr", "out.pfm"}) {
        std::string path = dir.file(std::string("missing/") + name);
        std::string message = ioErrorMessage([&] { writeImage(path, img); });
        CHECK_THAT(message, Catch::Contains(path) && Catch::Contains("No such file"));
        CHECK_FALSE(fs::exists(path));
    }
    CHECK(dir.entries().empty());
}

TEST_CASE("Writing into a read-only directory leaves no temporary files", "[image]") {
    TempDir dir;
    Image img = makeTestImage(3, 2);
    fs::permissions(dir.path, fs::perms::owner_read | fs::perms::owner_exec |
                                  fs::perms::group_read | fs::perms::group_exec |
                                  fs::perms::others_read | fs::perms::others_exec);
    // Root ignores directory permissions (CI runs as root): write as nobody instead.
    std::vector<std::string> messages;
    {
        Unprivileged nobody;
        if (!nobody.ok()) RAYPROC_SKIP("running as root and cannot take nobody's user id");
        if (::faccessat(AT_FDCWD, dir.path.c_str(), W_OK, AT_EACCESS) == 0)
            RAYPROC_SKIP("the read-only directory is writable to user " << ::geteuid());
        for (const char* name : {"out.png", "out.exr", "out.hdr", "out.pfm"})
            messages.push_back(ioErrorMessage([&] { writeImage(dir.file(name), img); }));
    }
    int i = 0;
    for (const char* name : {"out.png", "out.exr", "out.hdr", "out.pfm"}) {
        CHECK_THAT(messages[i++],
                   Catch::Contains(dir.file(name)) && Catch::Contains("Permission denied"));
    }
    CHECK(dir.entries().empty());
}

TEST_CASE("A failed rename removes the temporary file and keeps the destination", "[image]") {
    TempDir dir;
    Image img = makeTestImage(4, 4);
    // The encoder succeeds, then rename() onto a directory fails: the complete temporary file
    // must be removed.
    for (const char* name : {"blocked.png", "blocked.exr", "blocked.hdr", "blocked.pfm"}) {
        fs::create_directory(dir.path / name);
        fs::path inside = dir.path / name / "keep";
        writeBytes(inside.string(), "x");
        std::string message = ioErrorMessage([&] { writeImage(dir.file(name), img); });
        CHECK_THAT(message, Catch::Contains(dir.file(name)) && Catch::Contains("renaming"));
        CHECK(fs::is_directory(dir.path / name));
        CHECK(fs::exists(inside));
    }
    CHECK(dir.entries() ==
          std::vector<std::string>{"blocked.exr", "blocked.hdr", "blocked.pfm", "blocked.png"});
}

TEST_CASE("Running out of space mid-write leaves no partial file", "[image]") {
    TempDir dir;
    // Incompressible noise, so every format needs far more than the 4 KiB allowed below.
    Image img(64, 64);
    std::uint32_t state = 12345;
    for (float& v : img.pixels) {
        state = state * 1664525u + 1013904223u;
        v = float(state >> 8) / float(1 << 24) * 4.0f;
    }
    // RLIMIT_FSIZE makes writes past 4 KiB fail with EFBIG (SIGXFSZ ignored), like a full disk.
    rlimit saved{};
    REQUIRE(::getrlimit(RLIMIT_FSIZE, &saved) == 0);
    auto savedHandler = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limited = saved;
    limited.rlim_cur = 4096;
    REQUIRE(::setrlimit(RLIMIT_FSIZE, &limited) == 0);
    std::vector<std::string> messages;
    for (const char* name : {"full.png", "full.exr", "full.hdr", "full.pfm"}) {
        try {
            writeImage(dir.file(name), img);
            messages.push_back("");
        } catch (const ImageIoError& e) {
            messages.push_back(e.what());
        }
    }
    ::setrlimit(RLIMIT_FSIZE, &saved);
    std::signal(SIGXFSZ, savedHandler);
    for (const std::string& message : messages) {
        CHECK_THAT(message, Catch::Contains(dir.path.string()) && Catch::Contains("too large"));
    }
    CHECK(dir.entries().empty());
}

TEST_CASE("Overwriting an image replaces it completely", "[image]") {
    TempDir dir;
    writeImage(dir.file("a.pfm"), makeTestImage(8, 8));
    Image small = makeTestImage(2, 1);
    writeImage(dir.file("a.pfm"), small);
    Image back = readImage(dir.file("a.pfm"));
    CHECK(back.pixels == small.pixels);
    CHECK(dir.entries() == std::vector<std::string>{"a.pfm"});
}

TEST_CASE("Invalid images are rejected before any file is created", "[image]") {
    TempDir dir;
    Image empty;
    CHECK_THAT(ioErrorMessage([&] { writeImage(dir.file("e.png"), empty); }),
               Catch::Contains("e.png") && Catch::Contains("0x0"));
    Image wrong(4, 4);
    wrong.pixels.pop_back();
    CHECK_THAT(ioErrorMessage([&] { writeImage(dir.file("w.exr"), wrong); }),
               Catch::Contains("w.exr") && Catch::Contains("47"));
    CHECK(dir.entries().empty());
}

TEST_CASE("Corrupt or missing inputs throw ImageIoError", "[image]") {
    TempDir dir;
    Image img = makeTestImage(16, 16);
    for (const char* name : {"t.pfm", "t.exr", "t.png", "t.hdr"}) {
        writeImage(dir.file(name), img);
        fs::resize_file(dir.path / name, fs::file_size(dir.path / name) / 2);
        CHECK_THAT(ioErrorMessage([&] { readImage(dir.file(name)); }), Catch::Contains(name));
    }
    CHECK_THAT(ioErrorMessage([&] { readImage(dir.file("t.pfm")); }), Catch::Contains("truncated"));

    writeBytes(dir.file("text.exr"), "this is not an image\n");
    CHECK_THAT(ioErrorMessage([&] { readImage(dir.file("text.exr")); }),
               Catch::Contains("text.exr"));
    writeBytes(dir.file("text.png"), "this is not an image\n");
    CHECK_THAT(ioErrorMessage([&] { readImage(dir.file("text.png")); }),
               Catch::Contains("not a PNG"));
    writeBytes(dir.file("text.hdr"), "this is not an image\n");
    CHECK_THAT(ioErrorMessage([&] { readImage(dir.file("text.hdr")); }),
               Catch::Contains("not a Radiance HDR"));
    // A scanline whose run-length count is 0 (what zero bytes past a truncation look like).
    writeBytes(dir.file("zero.hdr"), "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 8\n" +
                                         std::string("\x02\x02\x00\x08\x00", 5));
    CHECK_THAT(ioErrorMessage([&] { readImage(dir.file("zero.hdr")); }),
               Catch::Contains("bad run-length encoding"));
    writeBytes(dir.file("xyze.hdr"), "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n1234");
    CHECK_THAT(ioErrorMessage([&] { readImage(dir.file("xyze.hdr")); }),
               Catch::Contains("32-bit_rle_xyze"));
    writeBytes(dir.file("header.pfm"), "PF\n-3 2\n-1.0\n");
    CHECK_THAT(ioErrorMessage([&] { readImage(dir.file("header.pfm")); }),
               Catch::Contains("expected a positive integer width"));
    writeBytes(dir.file("magic.pfm"), "P6\n3 2\n255\n");
    CHECK_THAT(ioErrorMessage([&] { readImage(dir.file("magic.pfm")); }),
               Catch::Contains("expected \"PF\""));

    CHECK_THAT(ioErrorMessage([&] { readImage(dir.file("absent.exr")); }),
               Catch::Contains("absent.exr") && Catch::Contains("No such file"));
    CHECK_THAT(ioErrorMessage([&] { readImage(dir.file("absent.png")); }),
               Catch::Contains("absent.png") && Catch::Contains("No such file"));
}

TEST_CASE("Reading an EXR without an RGB channel names the missing channel", "[image]") {
    TempDir dir;
    std::string path = dir.file("luma.exr");
    {
        std::vector<float> luma(4 * 2, 0.5f);
        Imf::Header header(4, 2);
        header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
        Imf::FrameBuffer frameBuffer;
        frameBuffer.insert("Y", Imf::Slice::Make(Imf::FLOAT, luma.data(), header.dataWindow()));
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(frameBuffer);
        file.writePixels(2);
    }
    CHECK_THAT(ioErrorMessage([&] { readImage(path); }), Catch::Contains("luma.exr") &&
                                                             Catch::Contains("no \"R\" channel") &&
                                                             Catch::Contains("Y"));
}

TEST_CASE("Headers that claim more than their file holds are refused before allocating",
          "[image]") {
    TempDir dir;
    auto writeBytes = [&](const std::string& name, const std::string& bytes) {
        std::string path = dir.file(name);
        std::FILE* f = std::fopen(path.c_str(), "wb");
        REQUIRE(f);
        std::fwrite(bytes.data(), 1, bytes.size(), f);
        std::fclose(f);
        return path;
    };
    auto le32 = [](std::uint32_t v) {
        std::string s(4, '\0');
        for (int i = 0; i < 4; ++i) s[i] = char((v >> (8 * i)) & 0xff);
        return s;
    };
    // EXR: an attribute whose size field says 1.2 GB, in a file of a few dozen bytes (OpenEXR
    // allocated the 1.2 GB before it found the file too short; found by the image fuzzer).
    std::string exr = std::string("\x76\x2f\x31\x01\x02\x00\x00\x00", 8) +
                      std::string("channels\0chlist\0", 16) + le32(1212747008u) + "xx";
    std::string exrPath = writeBytes("huge-attribute.exr", exr);
    CHECK_THROWS_WITH(readImage(exrPath),
                      Catch::Matchers::Contains("the attribute \"channels\" (chlist) claims "
                                                "1212747008 bytes, but the file has 2 left"));
    CHECK_THROWS_WITH(checkImageHeader(exrPath), Catch::Matchers::Contains("claims"));
    // A header cut short.
    std::string cut =
        writeBytes("cut.exr", std::string("\x76\x2f\x31\x01\x02\x00\x00\x00", 8) + "channels");
    CHECK_THROWS_WITH(readImage(cut), Catch::Matchers::Contains("truncated EXR header"));

    // PNG: an IHDR of 15000 x 15000 pixels (within stb_image's own 2^30-byte limit; it would
    // allocate 1.35 GB) in a 57-byte file.
    std::string ihdr = "IHDR";
    auto be32 = [](std::uint32_t v) {
        std::string s(4, '\0');
        for (int i = 0; i < 4; ++i) s[i] = char((v >> (8 * (3 - i))) & 0xff);
        return s;
    };
    // Each chunk with its right CRC: the readers check them before the sizes.
    auto crc = [&](const std::string& typeAndData) {
        return be32(std::uint32_t(crc32(0, reinterpret_cast<const Bytef*>(typeAndData.data()),
                                        uInt(typeAndData.size()))));
    };
    ihdr += be32(15000) + be32(15000) + std::string("\x08\x02\x00\x00\x00", 5);
    std::string png = std::string("\x89PNG\r\n\x1a\n", 8) + be32(13) + ihdr + crc(ihdr) +
                      be32(0) + "IEND" + crc("IEND");
    std::string pngPath = writeBytes("huge.png", png);
    CHECK_THROWS_WITH(readImage(pngPath),
                      Catch::Matchers::Contains("claims 15000x15000 pixels, more than a file of"));
    CHECK_THROWS_AS(checkImageDimensions(pngPath, 15000, 15000), ImageIoError);
    CHECK_NOTHROW(checkImageDimensions(pngPath, 64, 64)); // small claims always pass
    // PNG: a 4x3 header, then an IDAT chunk whose length says 1.2 GB (stb_image reallocated
    // its buffer to that; found by the image fuzzer).
    std::string small = "IHDR" + be32(4) + be32(3) + std::string("\x08\x02\x00\x00\x00", 5);
    std::string idat = std::string("\x89PNG\r\n\x1a\n", 8) + be32(13) + small + crc(small) +
                       be32(1229539657u) + "IDAT" + "xyz";
    CHECK_THROWS_WITH(readImage(writeBytes("huge-idat.png", idat)),
                      Catch::Matchers::Contains("the IDAT chunk claims 1229539657 bytes, but "
                                                "the file has 3 left"));

    // The fuzzer's own findings, as found (tests/image/corrupt/): each refused with a clear
    // message, without the allocation (the sanitizer build's fuzz run would catch one).
    const std::string corrupt = std::string(RAYPROC_SOURCE_DIR) + "/tests/image/corrupt/";
    CHECK_THROWS_WITH(readImage(corrupt + "attribute-claims-1.2gb.exr"),
                      Catch::Matchers::Contains("claims 1212747008 bytes"));
    CHECK_THROWS_WITH(readImage(corrupt + "channel-list-then-1.9gb-attribute.exr"),
                      Catch::Matchers::Contains("corrupt EXR header: Invalid pixel type"));
    CHECK_THROWS_WITH(readImage(corrupt + "channel-list-size-disagrees.exr"),
                      Catch::Matchers::Contains("the channel list's entries do not end"));
    CHECK_THROWS_WITH(readImage(corrupt + "idat-claims-1.2gb.png"),
                      Catch::Matchers::Contains("the IDAT chunk claims 1229539657 bytes"));

    // A real EXR passes the header walk.
    std::string good = dir.file("good.exr");
    writeImage(good, makeTestImage(5, 3));
    CHECK_NOTHROW(checkImageHeader(good));
    CHECK(readImage(good).width == 5);
}

namespace {

// An EXR of w x h pixels (float R, G, B; value (x + 2y) / 64 in every channel) written by
// OpenEXR itself with `compression` and, besides the standard ones, attributes of every kind
// the library reads by their layout rather than by their size field.
void writeExrWith(const std::string& path, int w, int h, Imf::Compression compression, bool tiled) {
    Imf::Header header(w, h);
    header.compression() = compression;
    header.insert("names", Imf::StringVectorAttribute({"key", "", "fill light"}));
    header.insert("weights", Imf::FloatVectorAttribute({0.5f, 2.0f}));
    header.insert("box", Imf::Box2iAttribute(Imath::Box2i({1, 2}, {3, 4})));
    header.insert("toWorld", Imf::M44dAttribute(Imath::M44d()));
    header.insert("origin", Imf::V3dAttribute(Imath::V3d(1, 2, 3)));
    header.insert("rate", Imf::RationalAttribute(Imf::Rational(24000, 1001)));
    header.insert("frame", Imf::TimeCodeAttribute(Imf::TimeCode(1, 2, 3, 4)));
    header.insert("film", Imf::KeyCodeAttribute(Imf::KeyCode()));
    Imf::addChromaticities(header, Imf::Chromaticities());
    Imf::PreviewImage preview(3, 2);
    header.insert("preview", Imf::PreviewImageAttribute(preview));
    std::vector<float> values(std::size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
                values[(std::size_t(y) * w + x) * 3 + c] = (x + 2 * y) / 64.f;
    const char* const names[3] = {"R", "G", "B"};
    Imf::FrameBuffer frameBuffer;
    for (int c = 0; c < 3; ++c) {
        header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
        frameBuffer.insert(names[c],
                           Imf::Slice::Make(Imf::FLOAT, values.data() + c, header.dataWindow(),
                                            3 * sizeof(float), 3 * sizeof(float) * w));
    }
    if (tiled) {
        // Mip-mapped 16 x 16 tiles; every level is written from the same buffer's top-left.
        header.setTileDescription(Imf::TileDescription(16, 16, Imf::MIPMAP_LEVELS));
        Imf::TiledOutputFile file(path.c_str(), header);
        for (int level = 0; level < file.numLevels(); ++level) {
            Imf::FrameBuffer levelBuffer;
            const std::size_t rowBytes = 3 * sizeof(float) * file.levelWidth(level);
            for (int c = 0; c < 3; ++c)
                levelBuffer.insert(names[c], Imf::Slice(Imf::FLOAT,
                                                        reinterpret_cast<char*>(values.data() + c),
                                                        3 * sizeof(float), rowBytes));
            file.setFrameBuffer(levelBuffer);
            file.writeTiles(0, file.numXTiles(level) - 1, 0, file.numYTiles(level) - 1, level);
        }
        return;
    }
    Imf::OutputFile file(path.c_str(), header);
    file.setFrameBuffer(frameBuffer);
    file.writePixels(h);
}

std::string readAll(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void writeAll(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
}

// The offset of the value of the header attribute `name` of type `type` (its size field is the
// four bytes before it).
std::size_t attributeValue(const std::string& bytes, const std::string& name,
                           const std::string& type) {
    std::size_t at = bytes.find(name + std::string(1, '\0') + type + std::string(1, '\0'));
    REQUIRE(at != std::string::npos);
    return at + name.size() + type.size() + 2 + 4;
}

void putLe32(std::string& bytes, std::size_t at, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes[at + i] = char((v >> (8 * i)) & 0xff);
}

} // namespace

TEST_CASE("EXR files of every compression, tiled or not, with attributes of every kind read back",
          "[image]") {
    // The header walk in front of OpenEXR (exr_io.cpp) must refuse nothing OpenEXR writes.
    TempDir dir;
    const Imf::Compression compressions[] = {
        Imf::NO_COMPRESSION,   Imf::RLE_COMPRESSION,   Imf::ZIPS_COMPRESSION, Imf::ZIP_COMPRESSION,
        Imf::PIZ_COMPRESSION,  Imf::PXR24_COMPRESSION, Imf::B44_COMPRESSION,  Imf::B44A_COMPRESSION,
        Imf::DWAA_COMPRESSION, Imf::DWAB_COMPRESSION};
    for (Imf::Compression compression : compressions)
        for (bool tiled : {false, true}) {
            const bool lossy =
                compression == Imf::PXR24_COMPRESSION || compression == Imf::B44_COMPRESSION ||
                compression == Imf::B44A_COMPRESSION || compression == Imf::DWAA_COMPRESSION ||
                compression == Imf::DWAB_COMPRESSION;
            CAPTURE(int(compression), tiled);
            std::string path =
                dir.file("c" + std::to_string(int(compression)) + (tiled ? "-tiled.exr" : ".exr"));
            writeExrWith(path, 37, 21, compression, tiled);
            REQUIRE_NOTHROW(checkImageHeader(path));
            Image img = readImage(path);
            REQUIRE(img.width == 37);
            REQUIRE(img.height == 21);
            float worst = 0.f;
            for (int y = 0; y < 21; ++y)
                for (int x = 0; x < 37; ++x)
                    worst = std::max(worst, std::abs(img.at(x, y)[0] - (x + 2 * y) / 64.f));
            CHECK(worst <= (lossy ? 0.05f : 0.f));
        }
}

TEST_CASE("EXR headers whose fields disagree with what OpenEXR would allocate are refused",
          "[image]") {
    TempDir dir;
    std::string base = dir.file("base.exr");
    writeExrWith(base, 6, 1, Imf::ZIP_COMPRESSION, false);
    const std::string good = readAll(base);
    REQUIRE_NOTHROW(readImage(base));
    auto refused = [&](const std::string& name, const std::string& bytes) {
        std::string path = dir.file(name);
        writeAll(path, bytes);
        return ioErrorMessage([&] { readImage(path); });
    };

    // A one-row ZIP image 4,194,305 pixels wide in a file of a few hundred bytes: OpenEXR's
    // 16-row decoding buffer would be 805 MB (found by the image fuzzer).
    std::string wide = good;
    putLe32(wide, attributeValue(wide, "dataWindow", "box2i") + 8, 4194304);
    CHECK_THAT(refused("wide.exr", wide),
               Catch::Contains("the header claims chunks of 805306560 decoded bytes"));

    // A 1-pixel-wide image of 100,000 rows: its offset table alone would be 800 kB.
    std::string tall = good;
    putLe32(tall, attributeValue(tall, "dataWindow", "box2i") + 8, 0);
    putLe32(tall, attributeValue(tall, "dataWindow", "box2i") + 12, 99999);
    CHECK_THAT(refused("tall.exr", tall),
               Catch::Contains("needs 6250 chunk offsets, more than a file of"));

    // Size fields that disagree with the layout the library reads by: it would go on reading
    // the attributes after them from other offsets.
    std::string box = good;
    putLe32(box, attributeValue(box, "box", "box2i") - 4, 12);
    CHECK_THAT(refused("box.exr", box),
               Catch::Contains("the attribute \"box\" (box2i) is 12 bytes long, but a box2i is "
                               "16 bytes"));
    std::string strings = good;
    putLe32(strings, attributeValue(strings, "names", "stringvector"), 9); // "key" is 3 long
    CHECK_THAT(refused("strings.exr", strings),
               Catch::Contains("\"names\" (stringvector)") &&
                   Catch::Contains("its strings do not end there"));
    std::string floats = good;
    putLe32(floats, attributeValue(floats, "weights", "floatvector") - 4, 7);
    CHECK_THAT(refused("floats.exr", floats), Catch::Contains("floats are 4 bytes each"));
    // A two-part file reads (its first part); a chunkCount of 10 million in a small one does not
    // (OpenEXR allocates the offset tables the parts' chunkCounts state).
    std::string multi = dir.file("multi.exr");
    {
        std::vector<Imf::Header> headers(2, Imf::Header(6, 1));
        std::vector<float> pixels(6 * 3, 0.25f);
        Imf::FrameBuffer frameBuffer;
        for (int c = 0; c < 3; ++c) {
            const char* name = c == 0 ? "R" : c == 1 ? "G" : "B";
            for (Imf::Header& h : headers) h.channels().insert(name, Imf::Channel(Imf::FLOAT));
            frameBuffer.insert(name, Imf::Slice::Make(Imf::FLOAT, pixels.data() + c,
                                                      headers[0].dataWindow(), 3 * sizeof(float),
                                                      6 * 3 * sizeof(float)));
        }
        headers[0].setName("left");
        headers[1].setName("right");
        headers[0].setType(Imf::SCANLINEIMAGE);
        headers[1].setType(Imf::SCANLINEIMAGE);
        Imf::MultiPartOutputFile file(multi.c_str(), headers.data(), 2);
        for (int part = 0; part < 2; ++part) {
            Imf::OutputPart out(file, part);
            out.setFrameBuffer(frameBuffer);
            out.writePixels(1);
        }
    }
    REQUIRE(readImage(multi).at(5, 0)[1] == 0.25f);
    std::string chunks = readAll(multi);
    putLe32(chunks, attributeValue(chunks, "chunkCount", "int"), 10000000);
    CHECK_THAT(refused("chunks.exr", chunks),
               Catch::Contains("the header's chunkCount 10000000 does not fit a file of"));
    std::string preview = good;
    putLe32(preview, attributeValue(preview, "preview", "preview"), 3000); // width
    CHECK_THAT(refused("preview.exr", preview),
               Catch::Contains("a preview image of that width and height is not"));
}
