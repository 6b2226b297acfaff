// The files a scene reads besides itself, through the real binary: an image that is a device, a
// FIFO or absurdly large is refused with its name, never handed to a reader that would spin or
// block.
#include "test_util.h"

#include "image/image.h"

#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace rayproc;
using namespace rayproc::test;

namespace {

bool contains(const std::string& text, const std::string& what) {
    return text.find(what) != std::string::npos;
}

// A sphere with the image texture `texture` under the environment map `environment`, both
// relative to the scene file; 8x8 pixels.
std::string texturedSkyScene(const std::string& texture, const std::string& environment) {
    return R"({"camera": {"resolution": [8, 8]},
               "textures": {"t": {"type": "image", "file": ")" + texture + R"("}},
               "materials": {"m": {"type": "diffuse", "color": "t"}},
               "lights": [{"type": "environment", "image": ")" + environment + R"("}],
               "nodes": [{"type": "sphere", "material": "m", "radius": 1}]})";
}

void writeGrey(const std::string& path, int size, float value) {
    Image img(size, size);
    std::fill(img.pixels.begin(), img.pixels.end(), value);
    writeImage(path, img);
}

} // namespace

TEST_CASE("A scene image that is a device, a FIFO or absurdly large is refused by name, at once",
          "[cli][bad-input]") {
    TempDir dir, logs;
    writeGrey(dir.file("env.pfm"), 4, 0.5f);
    writeGrey(dir.file("tex.png"), 4, 0.25f);
    // /dev/zero under an image name: OpenImageIO's fallback reader seeked through it forever.
    std::filesystem::create_symlink("/dev/zero", dir.file("zero.png"));
    std::filesystem::create_symlink("/dev/zero", dir.file("zero.pfm"));
    REQUIRE(::mkfifo(dir.file("pipe.exr").c_str(), 0600) == 0); // opening it would block
    {
        std::ofstream big(dir.file("big.png"));
    }
    std::filesystem::resize_file(dir.file("big.png"), std::uintmax_t(5) << 30); // sparse
    const std::vector<std::pair<std::string, std::string>> cases = {
        {texturedSkyScene("zero.png", "env.pfm"), "zero.png\": it is a character device"},
        {texturedSkyScene("tex.png", "zero.pfm"), "zero.pfm\": it is a character device"},
        {texturedSkyScene("pipe.exr", "env.pfm"), "pipe.exr\": it is a FIFO"},
        {texturedSkyScene("tex.png", "pipe.exr"), "pipe.exr\": it is a FIFO"},
        {texturedSkyScene("big.png", "env.pfm"), "more than the 4 GiB an image file may have"},
    };
    for (const auto& [text, message] : cases) {
        const std::string scene = dir.file("scene.json");
        writeText(scene, text);
        RunResult r = runRayproc({"render", scene, "--quiet", "-o", dir.file("out.pfm")}, logs, 30);
        INFO(text << "\n" << r.err);
        CHECK(r.status == 1); // -1: it hung and was killed
        CHECK(contains(r.err, message));
        CHECK(r.seconds < 10.0);
        CHECK_FALSE(std::filesystem::exists(dir.file("out.pfm")));
    }
}
