// The files a scene reads besides itself, through the real binary: an output may not replace an
// image the scene reads (environment map, texture), whatever the spelling; an image that is a
// device, a FIFO or absurdly large is refused with its name, never handed to a reader that
// would spin or block; and temporary files a killed run left next to its output are removed.
#include "test_util.h"

#include "image/image.h"

#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <sys/wait.h>
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

// A process id that no process has now: a child that has exited and been reaped.
pid_t deadPid() {
    pid_t pid = ::fork();
    if (pid == 0) ::_exit(0);
    int st = 0;
    ::waitpid(pid, &st, 0);
    return pid;
}

} // namespace

TEST_CASE("No output may replace an image the scene reads - environment map or texture, any "
          "spelling",
          "[cli][bad-input]") {
    TempDir dir, logs;
    const std::string env = dir.file("env.pfm"), tex = dir.file("tex.png");
    writeGrey(env, 4, 0.5f);
    writeGrey(tex, 4, 0.25f);
    const std::string scene = dir.file("scene.json");
    writeText(scene, texturedSkyScene("tex.png", "env.pfm"));
    const std::string envBytes = readText(env), texBytes = readText(tex);
    std::filesystem::create_hard_link(env, dir.file("env-hard-link.pfm"));
    std::filesystem::create_symlink(tex, dir.file("tex-link.png"));

    // The scene itself renders: the refusals below are for the outputs alone.
    RunResult ok = runRayproc({"render", scene, "--mode", "preview", "--quiet", "-o",
                               dir.file("out.pfm")},
                              logs);
    INFO(ok.err);
    REQUIRE(ok.status == 0);

    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"-o", env}, "-o " + env + " is the same file as the scene's image " + env},
        {{"-o", dir.path.string() + "/./tex.png"}, "is the same file as the scene's image " + tex},
        {{"-o", dir.file("env-hard-link.pfm")}, "the scene's image " + env},
        {{"-o", dir.file("tex-link.png")}, "the scene's image " + tex},
        {{"-o", dir.file("b.pfm"), "--stats-json", env}, "--stats-json " + env},
    };
    for (const auto& [options, message] : cases) {
        std::vector<std::string> args{"render", scene, "--mode", "preview", "--quiet"};
        args.insert(args.end(), options.begin(), options.end());
        RunResult r = runRayproc(args, logs);
        INFO(options[1] << "\n" << r.err);
        CHECK(r.status == 1);
        CHECK(contains(r.err, message));
        CHECK(contains(r.err, "(an input): writing it would destroy the input"));
        CHECK(readText(env) == envBytes);
        CHECK(readText(tex) == texBytes);
    }
}

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
        CHECK(r.status == 1); // -1: it hung and was killed (30 s)
        CHECK(contains(r.err, message));
        CHECK_FALSE(std::filesystem::exists(dir.file("out.pfm")));
    }
}

TEST_CASE("A render removes the temporary files of its output that a killed run left behind",
          "[cli]") {
    TempDir dir, logs;
    const std::string scene = dir.file("scene.json");
    writeGrey(dir.file("env.pfm"), 4, 0.5f);
    writeGrey(dir.file("tex.png"), 4, 0.25f);
    writeText(scene, texturedSkyScene("tex.png", "env.pfm"));
    const std::string dead = std::to_string(deadPid()), live = std::to_string(::getpid());
    const std::string stale = dir.file("out.pfm.tmp." + dead + ".3");
    const std::string alive = dir.file("out.pfm.tmp." + live + ".0");
    const std::string other = dir.file("other.pfm.tmp." + dead + ".0");
    const std::string notOurs = dir.file("out.pfm.tmp." + dead + ".x");
    for (const std::string& f : {stale, alive, other, notOurs}) writeText(f, "partial");
    RunResult r = runRayproc({"render", scene, "--mode", "preview", "-o", dir.file("out.pfm")},
                             logs);
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(contains(r.err, "removed 1 temporary file(s) of " + dir.file("out.pfm")));
    CHECK_FALSE(std::filesystem::exists(stale));
    CHECK(std::filesystem::exists(alive));   // a live process may still be writing it
    CHECK(std::filesystem::exists(other));   // another output's
    CHECK(std::filesystem::exists(notOurs)); // not a name AtomicFileWriter makes
    CHECK(readImage(dir.file("out.pfm")).width == 8);
}
