// Files that are no regular files or absurdly large never reach a reader. Both readers are
// checked: readImage (stb, OpenEXR) and the texture loader (OpenImageIO).
#include "image/image.h"
#include "texture/texture_image.h"

#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

using namespace rayproc;
namespace fs = std::filesystem;

namespace {

struct TempDir {
    fs::path path;
    TempDir() {
        static std::atomic<int> counter{0};
        path = fs::temp_directory_path() / ("rayproc_integrity_test_" + std::to_string(::getpid()) +
                                            "_" + std::to_string(counter++));
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    std::string file(const std::string& name) const { return (path / name).string(); }
};

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
