// Bad input through the real binary: every malformed scene, absurd size and impossible output
// ends in one clear message naming the file and the place (JSON pointer, line and column, or
// pbrt file:line:column), a non-zero status, quickly, without allocating for the absurd size
// (runs under a 1 GiB address-space cap where the build allows it), and with no output file.
// Failed writes (a missing or unwritable directory, a full disk simulated with RLIMIT_FSIZE)
// leave no partial or temporary file and an existing image untouched.
#include "cli/limited_run.h"
#include "skip.h"

#include <sys/stat.h>

using namespace rayproc;
using namespace rayproc::test;

namespace {

bool contains(const std::string& text, const std::string& what) {
    return text.find(what) != std::string::npos;
}

// 1 GiB: far more than any of these loads needs, far less than the sizes they ask for.
constexpr rlim_t kAddressCap = rlim_t(1) << 30;

Limits memoryCap() {
    Limits l;
    if (kAddressSpaceLimitWorks) l.addressSpace = kAddressCap;
    return l;
}

std::vector<std::string> fileNames(const std::filesystem::path& dir) {
    std::vector<std::string> names;
    for (auto& e : std::filesystem::directory_iterator(dir))
        names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

struct BadScene {
    const char* name;     // file name; the extension picks the reader
    std::string text;     // contents
    std::string location; // expected in the message after the file name
    std::string problem;  // expected in the message
};

std::string sphereScene(const std::string& sections) {
    return "{" + sections + (sections.empty() ? "" : ", ") +
           R"("materials": {"m": {"type": "diffuse"}},
               "nodes": [{"type": "sphere", "material": "m", "radius": 1}]})";
}

// A unit sphere lit by a point light, seen at res x res pixels.
std::string litSphereScene(int res) {
    std::string r = std::to_string(res);
    return sphereScene(R"("camera": {"resolution": [)" + r + ", " + r + R"(]},
                          "lights": [{"type": "point", "position": [0, 0, 4],
                                      "intensity": [1, 1, 1]}])");
}

std::string meshScene(const std::string& indices) {
    return R"({"materials": {"m": {"type": "diffuse"}},
               "nodes": [{"type": "mesh", "material": "m",
                          "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": )" +
           indices + "}]}";
}

std::string gridScene(const std::string& segments) {
    return R"({"materials": {"m": {"type": "diffuse"}},
               "nodes": [{"type": "grid", "material": "m", "size": [1, 1], "segments": )" +
           segments + "}]}";
}

// Prototypes p0 .. p(n-1), each placing the next twice: 2^n placements in a few lines.
std::string instanceExplosion(int n) {
    std::string protos;
    for (int i = 0; i + 1 < n; ++i) {
        protos += "\"p" + std::to_string(i) + "\": {\"children\": [" +
                  "{\"type\": \"instance\", \"prototype\": \"p" + std::to_string(i + 1) +
                  "\", \"transform\": {\"translate\": [1, 0, 0]}}, " +
                  "{\"type\": \"instance\", \"prototype\": \"p" + std::to_string(i + 1) +
                  "\"}]}, ";
    }
    protos += "\"p" + std::to_string(n - 1) +
              "\": {\"children\": [{\"type\": \"sphere\", \"radius\": 1, \"emission\": [1, 1, 1]}]}";
    return "{\"prototypes\": {" + protos +
           "}, \"nodes\": [{\"type\": \"instance\", \"prototype\": \"p0\"}]}";
}

const char* const kPbrtHead = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\n";

// Runs `render <scene> -o <dir>/out.pfm` under the memory cap and checks the failure.
void checkRejected(const TempDir& dir, const BadScene& c) {
    std::string scene = dir.file(c.name);
    writeText(scene, c.text);
    std::string out = dir.file("out.pfm");
    RunResult r = runLimited({"render", scene, "-o", out, "--quiet"}, dir, memoryCap(), 60);
    INFO("scene " << c.name << "\nstderr: " << r.err);
    CHECK(r.status == 1);
    // One message: "rayproc: <file>: <location>: <problem>" (pbrt: "<file>:<line>:<col>: ...").
    CHECK(contains(r.err, "rayproc: " + scene));
    CHECK(contains(r.err, c.location));
    CHECK(contains(r.err, c.problem));
    CHECK_FALSE(contains(r.err, "out of memory"));
    // A generous bound for a busy CI machine, not a performance claim: these fail in
    // milliseconds; what it catches is work (or allocation) proportional to the absurd size.
    CHECK(r.seconds < 5.0);
    CHECK_FALSE(std::filesystem::exists(out));
}

} // namespace

TEST_CASE("A valid scene renders under the address-space cap the bad-input tests use",
          "[cli][bad-input]") {
    // The control: without it, a test below could pass because the cap itself broke rayproc.
    TempDir dir;
    std::string scene = dir.file("ok.json");
    writeText(scene, litSphereScene(16));
    std::string out = dir.file("ok.pfm");
    RunResult r = runLimited({"render", scene, "--mode", "preview", "-o", out, "--quiet",
                              "--threads", "2"},
                             dir, memoryCap());
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK(std::filesystem::exists(out));
    if (!kAddressSpaceLimitWorks) WARN("AddressSanitizer build: no address-space cap applied");
}

TEST_CASE("Malformed JSON scenes fail with file, JSON pointer or line, and status 1",
          "[cli][bad-input]") {
    TempDir dir;
    std::string deepGroups;
    for (int i = 0; i < 20000; ++i) deepGroups += R"({"type": "group", "children": [)";
    deepGroups += R"({"type": "sphere", "material": "m", "radius": 1})";
    for (int i = 0; i < 20000; ++i) deepGroups += "]}";
    const BadScene cases[] = {
        {"syntax.json", "{\n  \"nodes\": [\n    {\"type\": \"sphere\",, }\n", "line 3, column",
         "syntax error"},
        {"empty.json", "", "line 1, column 1", "syntax error"},
        {"binary.json", std::string("\x00\xff\xfe{\x01", 5), "line 1, column 1", "syntax error"},
        {"truncated.json", sphereScene("").substr(0, 60), "line 2", "syntax error"},
        {"wrong-type.json",
         R"({"materials": {"m": {"type": "diffuse"}},
             "nodes": [{"type": "sphere", "material": "m", "radius": "one"}]})",
         "/nodes/0/radius", "expected a number"},
        {"wrong-type-vector.json", sphereScene(R"("camera": {"position": [0, "0", 5]})"),
         "/camera/position/1", "expected a number"},
        {"nan.json", sphereScene(R"("camera": {"fov": NaN})"), "line 1, column", "syntax error"},
        {"infinity.json", sphereScene(R"("camera": {"fov": Infinity})"), "line 1, column",
         "syntax error"},
        {"overflow-float.json", sphereScene(R"("camera": {"aperture": 1e39})"),
         "/camera/aperture", "32-bit float"},
        {"overflow-double.json", sphereScene(R"("camera": {"aperture": 1e999})"),
         "/camera/aperture", "overflows"},
        {"missing-obj.json",
         R"({"materials": {"m": {"type": "diffuse"}},
             "nodes": [{"type": "obj", "material": "m", "file": "no-such-mesh.obj"}]})",
         "/nodes/0/file", "OBJ file not found"},
        {"obj-is-device.json",
         R"({"materials": {"m": {"type": "diffuse"}},
             "nodes": [{"type": "obj", "material": "m", "file": "/dev/zero"}]})",
         "/nodes/0/file", "OBJ file not found"},
        {"index-range.json", meshScene("[[0, 1, 3]]"), "/nodes/0/indices/0/2", "out of range"},
        {"index-huge.json", meshScene("[[0, 1, 1099511627776]]"), "/nodes/0/indices/0/2",
         "out of range"},
        {"index-negative.json", meshScene("[0, 1, -1]"), "/nodes/0/indices/2", "out of range"},
        {"index-fraction.json", meshScene("[0, 1, 1.5]"), "/nodes/0/indices/2",
         "expected an integer"},
        {"index-count.json", meshScene("[0, 1]"), "/nodes/0/indices", "not a multiple of 3"},
        {"image-1e9.json", sphereScene(R"("camera": {"resolution": [1000000000, 1000000000]})"),
         "/camera/resolution/0", "out of range"},
        {"image-1e12-float.json", sphereScene(R"("camera": {"resolution": [1e12, 1e12]})"),
         "/camera/resolution/0", "out of range"},
        {"image-pixels.json", sphereScene(R"("camera": {"resolution": [16384, 16384]})"),
         "/camera/resolution", "image too large"},
        {"spp-1e12.json", sphereScene(R"("render": {"spp": 1000000000000})"), "/render/spp",
         "out of range"},
        {"spp-2e6.json", sphereScene(R"("render": {"spp": 2000000})"), "/render/spp",
         "out of range"},
        {"depth-1e12.json", sphereScene(R"("render": {"max_depth": 1e12})"), "/render/max_depth",
         "out of range"},
        {"light-samples.json", sphereScene(R"("render": {"light_samples": 4294967296})"),
         "/render/light_samples", "out of range"},
        // Photon counts are a command-line setting only; a scene cannot ask for 1e12 of them.
        {"photons-1e12.json", sphereScene(R"("render": {"photons": 1000000000000})"),
         "/render/photons", "unknown key"},
        {"grid-1e9.json", gridScene("[1000000000, 1000000000]"), "/nodes/0/segments/0",
         "out of range"},
        {"grid-cells.json", gridScene("[8192, 8192]"), "/nodes/0/segments", "too many cells"},
        {"deep-groups.json",
         R"({"materials": {"m": {"type": "diffuse"}}, "nodes": [)" + deepGroups + "]}",
         "/children/0/children/0/...", "nested more than 1024 levels"},
        {"deep-arrays.json",
         R"({"nodes": )" + std::string(200000, '[') + std::string(200000, ']') + "}",
         "/nodes/0/0/0/0", "nested more than 1024 levels"},
        {"instance-explosion.json", instanceExplosion(40), "/nodes", "the limit is 4194304"},
        {"cycle.json",
         R"({"prototypes": {"a": {"children": [{"type": "instance", "prototype": "a"}]}},
             "nodes": [{"type": "instance", "prototype": "a"}]})",
         "/prototypes/a/children/0/prototype", "instance cycle"},
    };
    for (const BadScene& c : cases) checkRejected(dir, c);
}

TEST_CASE("Malformed pbrt scenes and PLY meshes fail with file, line and column, and status 1",
          "[cli][bad-input]") {
    TempDir dir;
    // Binary PLY headers that promise billions of rows the file does not hold.
    writeText(dir.file("huge-vertices.ply"),
              "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
              "property float x\nproperty float y\nproperty float z\nelement face 1\n"
              "property list uchar int vertex_indices\nend_header\n" +
                  std::string(64, '\0'));
    writeText(dir.file("huge-faces.ply"),
              "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
              "property float x\nproperty float y\nproperty float z\nelement face 4000000000\n"
              "property list uchar int vertex_indices\nend_header\n" +
                  std::string(36 + 13, '\0'));
    writeText(dir.file("huge-list.ply"),
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
              "property float z\nelement face 1\nproperty list uint int vertex_indices\n"
              "end_header\n0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n");
    writeText(dir.file("huge-empty-element.ply"),
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
              "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
              "element nothing 1000000000000000000\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    writeText(dir.file("nan-vertex.ply"),
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
              "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
              "end_header\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n");
    auto world = [](const std::string& body) {
        return std::string(kPbrtHead) + "WorldBegin\n" + body;
    };
    auto ply = [&](const std::string& name) {
        return world("AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\n"
                     "Shape \"plymesh\" \"string filename\" \"" +
                     dir.file(name) + "\"\nAttributeEnd\n");
    };
    const BadScene cases[] = {
        {"syntax.pbrt", world("Shape \"sphere\" \"float radius\" [1\n"), ":4:", "never closed"},
        {"unknown-directive.pbrt", world("Sphere 1\n"), ":4:1", "unknown directive \"Sphere\""},
        {"nan.pbrt", world("Shape \"sphere\" \"float radius\" [nan]\n"), ":4:", "expects numbers"},
        {"overflow.pbrt", world("Shape \"sphere\" \"float radius\" [1e39]\n"), ":4:",
         "expects numbers"},
        {"wrong-type.pbrt", world("Shape \"sphere\" \"float radius\" [\"one\"]\n"), ":4:",
         "expects numbers"},
        {"film-1e9.pbrt",
         std::string(kPbrtHead) + "Film \"rgb\" \"integer xresolution\" [1000000000] "
                                  "\"integer yresolution\" [1000000000]\nWorldBegin\n"
                                  "Shape \"sphere\"\n",
         ":3:", "outside 1..16384"},
        {"film-pixels.pbrt",
         std::string(kPbrtHead) + "Film \"rgb\" \"integer xresolution\" [16384] "
                                  "\"integer yresolution\" [16384]\nWorldBegin\n"
                                  "Shape \"sphere\"\n",
         ":3:", "exceeds the limit"},
        {"index.pbrt",
         world("Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] "
               "\"integer indices\" [0 1 7]\n"),
         ":4:", "index 7 out of range"},
        {"index-huge.pbrt",
         world("Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] "
               "\"integer indices\" [0 1 4294967296]\n"),
         ":4:", "expects integers"},
        {"missing-include.pbrt", world("Include \"no-such-file.pbrt\"\n"), ":4:",
         "cannot open the included file"},
        {"missing-ply.pbrt", world("Shape \"plymesh\" \"string filename\" \"no-such.ply\"\n"),
         ":4:", "PLY file not found"},
        {"huge-vertices.pbrt", ply("huge-vertices.ply"), ":6:", "more than the file holds"},
        {"huge-faces.pbrt", ply("huge-faces.ply"), ":6:", "more than the file holds"},
        {"huge-list.pbrt", ply("huge-list.ply"), ":6:", "face 0"},
        {"huge-empty-element.pbrt", ply("huge-empty-element.ply"), ":6:", "nothing"},
        {"nan-vertex.pbrt", ply("nan-vertex.ply"), ":6:", "not a number"},
    };
    for (const BadScene& c : cases) checkRejected(dir, c);
}

TEST_CASE("Absurd sizes on the command line are refused before rendering", "[cli][bad-input]") {
    TempDir dir;
    std::string scene = dir.file("small.json");
    writeText(scene, sphereScene(R"("camera": {"resolution": [8, 8]})"));
    std::string out = dir.file("out.pfm");
    struct CliCase {
        std::vector<std::string> args;
        std::string mention;
    };
    const CliCase cases[] = {
        {{"--width", "1000000000"}, "--width"},
        {{"--width", "1e9", "--height", "1e9"}, "--width"},
        {{"--height", "-5"}, "--height"},
        // Each side is allowed; their product is not (the scene-file limit of 2^26 pixels).
        {{"--width", "16384", "--height", "16384"}, "too large"},
        {{"--width", "16384"}, "too large"}, // 16384 x the scene's 8: fine...
        {{"--spp", "1000000000000"}, "--spp"},
        {{"--spp", "2000000"}, "--spp"},
        {{"--photons", "1000000000000", "--mode", "gi"}, "--photons"},
        {{"--caustic-photons", "1e12", "--mode", "gi"}, "--caustic-photons"},
        {{"--gather-rays", "100000000", "--mode", "gi"}, "--gather-rays"},
        {{"--global-k", "0", "--mode", "gi"}, "--global-k"},
        {{"--global-k", "100000", "--mode", "gi"}, "--global-k"},
        {{"--caustic-radius", "0", "--mode", "gi"}, "--caustic-radius"},
        {{"--caustic-radius", "-0.5", "--mode", "gi"}, "--caustic-radius"},
        {{"--caustic-radius", "1e39", "--mode", "gi"}, "--caustic-radius"},
        {{"--max-depth", "1000000"}, "--max-depth"},
        {{"--threads", "1000000"}, "--threads"},
    };
    for (const CliCase& c : cases) {
        std::vector<std::string> args = {"render", scene, "-o", out, "--quiet"};
        args.insert(args.end(), c.args.begin(), c.args.end());
        if (c.mention == "too large" && c.args.size() == 2) {
            // 16384 x 8 = 131072 pixels is within the limit: this one must render.
            RunResult ok = runLimited(args, dir, memoryCap());
            INFO(ok.err);
            CHECK(ok.status == 0);
            std::filesystem::remove(out);
            continue;
        }
        RunResult r = runLimited(args, dir, memoryCap());
        INFO("args " << c.args[0] << " " << c.args[1] << "\nstderr: " << r.err);
        CHECK(r.status != 0);
        CHECK(r.status != -1);
        CHECK(r.status < 128); // an error exit, not a signal
        CHECK(contains(r.err, c.mention));
        CHECK_FALSE(contains(r.err, "out of memory"));
        CHECK(r.seconds < 5.0);
        CHECK_FALSE(std::filesystem::exists(out));
    }
}

TEST_CASE("A device is not a scene file, however long it is", "[cli][bad-input]") {
    // /dev/zero never ends: reading it whole would allocate without bound.
    TempDir dir;
    std::string out = dir.file("x.pfm");
    RunResult r = runLimited({"render", "/dev/zero", "-o", out}, dir, memoryCap(), 60);
    INFO(r.err);
    CHECK(r.status == 1);
    CHECK(contains(r.err, "rayproc: /dev/zero: not a regular file"));
    CHECK(r.seconds < 5.0);
    CHECK_FALSE(std::filesystem::exists(out));
}

TEST_CASE("A missing scene file is a clear error", "[cli][bad-input]") {
    TempDir dir;
    std::string missing = dir.file("no-such-scene.json");
    RunResult r = runRayproc({"render", missing, "-o", dir.file("x.pfm")}, dir);
    INFO(r.err);
    CHECK(r.status != 0);
    CHECK(r.status < 128);
    CHECK(contains(r.err, missing));
}

TEST_CASE("A failed final write is a clear error and leaves nothing behind",
          "[cli][bad-input]") {
    TempDir dir, logs;
    std::string scene = dir.file("scene.json");
    writeText(scene, litSphereScene(64));
    std::vector<std::string> render = {"render", scene, "--mode", "preview", "--quiet",
                                       "--threads", "2"};

    SECTION("a full disk: the old image stays as it was") {
        // 64 x 64 PFM is 49 KiB; files may not grow past 4 KiB, so the write fails with EFBIG.
        std::string out = dir.file("old.pfm");
        const std::string oldBytes = "an older image, which must survive a failed write\n";
        writeText(out, oldBytes);
        auto before = fileNames(dir.path);
        Limits l;
        l.fileSize = 4096;
        auto args = render;
        args.insert(args.end(), {"-o", out, "--stats-json", dir.file("stats.json")});
        RunResult r = runLimited(args, logs, l);
        INFO(r.err);
        CHECK(r.status == 1);
        CHECK(contains(r.err, "cannot write image \"" + out + "\""));
        CHECK(contains(r.err, "File too large"));
        CHECK(readText(out) == oldBytes);
        CHECK(fileNames(dir.path) == before); // no temporary file, no stats file
    }
    SECTION("failed progressive writes warn once; the render goes on to its own error") {
        std::string out = dir.file("progressive.pfm");
        Limits l;
        l.fileSize = 4096;
        RunResult r = runLimited({"render", scene, "--mode", "raytrace", "--spp", "64",
                                  "--threads", "2", "--quiet", "--progressive-output",
                                  "--progressive-interval", "0.001", "-o", out},
                                 logs, l);
        INFO(r.err);
        CHECK(r.status == 1);
        std::size_t warnings = 0;
        for (std::size_t p = r.err.find("warning: cannot write image"); p != std::string::npos;
             p = r.err.find("warning: cannot write image", p + 1))
            ++warnings;
        CHECK(warnings == 1);
        CHECK(contains(r.err, "rendering goes on"));
        CHECK(contains(r.err, "rayproc: cannot write image \"" + out + "\""));
        CHECK(fileNames(dir.path) == std::vector<std::string>{"scene.json"});
    }
    SECTION("an unwritable statistics file: refused before the render") {
        std::string out = dir.file("image.pfm");
        std::string stats = "/proc/rayproc-bad-input-test-stats.json";
        auto args = render;
        args.insert(args.end(), {"-o", out, "--stats-json", stats});
        RunResult r = runRayproc(args, logs);
        INFO(r.err);
        CHECK(r.status == 1);
        CHECK(contains(r.err, "--stats-json " + stats + ": the directory /proc does not accept "
                              "new files"));
        CHECK(fileNames(dir.path) == std::vector<std::string>{"scene.json"});
    }
    SECTION("a directory that cannot take files: refused before the render") {
        // /proc refuses new files even to root, so this holds however the tests run.
        std::string out = "/proc/rayproc-bad-input-test.pfm";
        auto args = render;
        args.insert(args.end(), {"-o", out});
        RunResult r = runRayproc(args, logs);
        INFO(r.err);
        CHECK(r.status == 1);
        CHECK(contains(r.err, "-o " + out + ": the directory /proc does not accept new files"));
        CHECK_FALSE(std::filesystem::exists(out));
    }
    SECTION("an output path under a regular file") {
        std::string out = dir.file("scene.json/out.pfm");
        auto args = render;
        args.insert(args.end(), {"-o", out});
        RunResult r = runRayproc(args, logs);
        INFO(r.err);
        CHECK(r.status == 1);
        CHECK(contains(r.err, out));
        CHECK(fileNames(dir.path) == std::vector<std::string>{"scene.json"});
    }
}

// CLI11 reads "nan" and "inf" as numbers and its range checks let NaN through; a NaN exposure
// or time limit rendered silently. Usage errors exit 1, as --help says (diff: 2), not CLI11's
// own 105, 106, 109.
TEST_CASE("Non-finite numbers and usage errors exit with the documented status", "[cli]") {
    TempDir dir;
    std::string scene = std::string(RAYPROC_SOURCE_DIR) + "/scenes/cornell-box.json";
    std::vector<std::string> render = {"render", scene, "--mode", "gi", "--width", "8",
                                       "--height", "8", "--spp", "1", "--quiet",
                                       "-o", dir.file("out.pfm")};
    const std::vector<std::vector<std::string>> nonFinite = {
        {"--exposure", "nan"}, {"--ic-accuracy", "nan"}, {"--time-limit", "nan"},
        {"--exposure", "inf"}, {"--progressive-interval", "-nan"}};
    for (const auto& extra : nonFinite) {
        auto args = render;
        args.insert(args.end(), extra.begin(), extra.end());
        RunResult r = runRayproc(args, dir);
        INFO(extra[0] << " " << extra[1] << "\nstderr: " << r.err);
        CHECK(r.status == 1);
        CHECK(contains(r.err, extra[0] + ": must be a finite number"));
        CHECK_FALSE(std::filesystem::exists(dir.file("out.pfm")));
    }
    RunResult unknown = runRayproc({"render", scene, "--no-such-option"}, dir);
    CHECK(unknown.status == 1);
    RunResult missing = runRayproc({"render"}, dir);
    CHECK(missing.status == 1);
    RunResult bench = runRayproc({"bench", "--time-cap", "nan"}, dir);
    CHECK(bench.status == 1);
    RunResult diff = runRayproc({"diff", scene, scene, "--max-rmse", "nan"}, dir);
    CHECK(diff.status == 2);
    CHECK(contains(diff.err, "--max-rmse: must be a finite number"));
}

TEST_CASE("No output may overwrite an input or another output - all refused before any work",
          "[cli][bad-input]") {
    TempDir dir, logs;
    std::string scene = dir.file("scene.json");
    std::string sceneText = litSphereScene(16);
    writeText(scene, sceneText);
    std::string ref = dir.file("ref.pfm");
    std::string image = dir.file("image.pfm");
    RunResult made = runRayproc({"render", scene, "--mode", "preview", "--quiet", "-o", ref}, logs);
    REQUIRE(made.status == 0);
    REQUIRE(runRayproc({"render", scene, "--mode", "preview", "--quiet", "-o", image}, logs).status == 0);
    std::string refBytes = readText(ref), imageBytes = readText(image);
    // Another spelling of the same file counts too.
    std::string sceneAgain = (std::filesystem::path(dir.path) / "." / "scene.json").string();

    struct Case {
        std::vector<std::string> args;
        std::string message;
        int status;
    };
    const std::vector<Case> cases = {
        {{"render", scene, "--stats-json", sceneAgain, "-o", dir.file("a.pfm")},
         "--stats-json " + sceneAgain + " is the same file as scene " + scene + " (an input)", 1},
        {{"render", scene, "--reference", ref, "--error-log", scene, "-o", dir.file("a.pfm")},
         "--error-log " + scene + " is the same file as scene", 1},
        {{"render", scene, "--reference", ref, "--error-log", dir.file("log.csv"), "-o", ref},
         "-o " + ref + " is the same file as --reference " + ref + " (an input)", 1},
        {{"render", scene, "--stats-json", dir.file("same.pfm"), "-o", dir.file("same.pfm")},
         "--stats-json " + dir.file("same.pfm") + " is the same file as -o " +
             dir.file("same.pfm") + " (another output)",
         1},
        {{"render", scene, "-o", scene}, "", 1}, // refused (.json is no image format either)
        {{"diff", image, ref, "-o", ref}, "-o " + ref + " is the same file as reference", 2},
        {{"diff", image, ref, "--heatmap", image}, "--heatmap " + image + " is the same file as test", 2},
        {{"diff", image, ref, "-o", dir.file("d.pfm"), "--heatmap", dir.file("d.pfm")},
         "(another output)", 2},
    };
    for (const Case& c : cases) {
        std::string shown;
        for (const std::string& a : c.args) shown += a + " ";
        INFO(shown);
        RunResult r = runRayproc(c.args, logs);
        INFO(r.err);
        CHECK(r.status == c.status);
        if (!c.message.empty()) CHECK(contains(r.err, c.message));
        // Nothing was touched, nothing was added.
        CHECK(readText(scene) == sceneText);
        CHECK(readText(ref) == refBytes);
        CHECK(readText(image) == imageBytes);
        CHECK(fileNames(dir.path) ==
              std::vector<std::string>{"image.pfm", "ref.pfm", "scene.json"});
    }
}

TEST_CASE("An output path that is a directory or a device is refused before the render",
          "[cli][bad-input]") {
    TempDir dir, logs;
    std::string scene = dir.file("scene.json");
    writeText(scene, sphereScene(R"("camera": {"resolution": [16, 16]})"));
    std::filesystem::create_directory(dir.file("folder.pfm"));
    RunResult r = runRayproc({"render", scene, "-o", dir.file("folder.pfm")}, logs);
    INFO(r.err);
    CHECK(r.status == 1);
    CHECK(contains(r.err, "-o " + dir.file("folder.pfm") + ": is a directory"));
    CHECK(std::filesystem::is_directory(dir.file("folder.pfm")));

    RunResult s = runRayproc({"render", scene, "-o", dir.file("x.pfm"), "--stats-json", "/dev/full"},
                             logs);
    INFO(s.err);
    CHECK(s.status == 1);
    CHECK(contains(s.err, "--stats-json /dev/full: is not a regular file"));
    CHECK_FALSE(std::filesystem::exists(dir.file("x.pfm")));
}

TEST_CASE("A full disk while writing the error log is an error - the image is still written",
          "[cli][bad-input]") {
    TempDir dir, logs;
    std::string scene = dir.file("scene.json");
    writeText(scene, litSphereScene(8));
    std::string ref = dir.file("ref.pfm");
    REQUIRE(runRayproc({"render", scene, "--mode", "raytrace", "--quiet", "-o", ref}, logs).status == 0);
    // 8 x 8 PFM images are 787 bytes; the log grows by a row per pass (64 passes of 1 spp under
    // --time-limit: some 2 KiB), so a 1 KiB file cap fills the "disk" in the middle of the log.
    std::string out = dir.file("out.pfm"), log = dir.file("log.csv");
    Limits l;
    l.fileSize = 1024;
    RunResult r = runLimited({"render", scene, "--mode", "raytrace", "--quiet", "--spp", "64",
                              "--time-limit", "1000", "--reference", ref, "--error-log", log,
                              "-o", out},
                             logs, l);
    INFO(r.err);
    CHECK(r.status == 1);
    CHECK(contains(r.err, "cannot write the error log " + log + ": File too large"));
    CHECK(contains(r.err, "(the image was written)"));
    CHECK(readImage(out).width == 8);
    std::string text = readText(log);
    CHECK(text.size() <= 1024);
    CHECK(text.rfind("spp,seconds,relmse,rmse,relmse_estimate\n", 0) == 0);
}

TEST_CASE("bench refuses outputs that are inputs and keeps an old results.csv until it has a row",
          "[cli][bad-input]") {
    TempDir dir, logs;
    std::string out = dir.file("results");
    std::filesystem::create_directory(out);
    std::string results = out + "/results.csv";
    const std::string old = "scene,mode,settings,seconds,rays,relmse,rmse\nold,path,spp=1,1,1,1,1\n";
    writeText(results, old);
    // The results file named as a peer: it would be emptied, then read.
    RunResult r = runRayproc({"bench", "--quick", "-q", "-o", out, "--peer-csv", results}, logs);
    INFO(r.err);
    CHECK(r.status == 1);
    CHECK(contains(r.err, "is the same file as --peer-csv"));
    CHECK(readText(results) == old);
    // A scene file that does not parse is only found when the ladders load it, after the
    // options were checked: the old results survive it.
    std::string scene = dir.file("broken.json");
    writeText(scene, "{\"materials\": ");
    RunResult s = runRayproc({"bench", "--quick", "-q", "-o", out, "--scene", scene}, logs);
    INFO(s.err);
    CHECK(s.status == 1);
    CHECK(contains(s.err, scene + ": line 1"));
    CHECK(readText(results) == old);
}

TEST_CASE("Scenes whose rays would leave Embree's range are refused before Embree sees them",
          "[cli][bad-input]") {
    // Each of these aborted inside Embree (an assertion on the ray's range, status 134). A far
    // camera is refused by the loader already (camera_range_test.cpp).
    TempDir dir, logs;
    auto scene = [](const std::string& scale, const std::string& cameraZ) {
        return R"({"camera": {"position": [0, 0, )" + cameraZ + R"(], "look_at": [0, 0, 0],
                              "resolution": [16, 16]},
                   "materials": {"m": {"type": "diffuse"}},
                   "lights": [{"type": "point", "position": [0, 0, 4], "intensity": [1, 1, 1]}],
                   "nodes": [{"type": "group", "name": "thin", "transform": {"scale": )" +
               scale + R"(}, "children": [{"type": "sphere", "material": "m", "radius": 1}]}]})";
    };
    struct Case {
        const char* name;
        std::string text;
        std::string message;
    };
    const std::vector<Case> cases = {
        {"squashed.json", scene("[1, 1e-20, 1]", "5"),
         "node 'thin' (root/0): its transform, composed with its parents', shrinks an axis"},
        {"pbrt-scale.pbrt",
         "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\n"
         "Film \"rgb\" \"integer xresolution\" [16] \"integer yresolution\" [16]\nWorldBegin\n"
         "LightSource \"point\" \"point3 from\" [0 0 4]\nAttributeBegin\nScale 1 1e-30 1\n"
         "Shape \"sphere\"\nAttributeEnd\n",
         "grows vectors by up to 1e+30"},
    };
    for (const Case& c : cases) {
        INFO(c.name);
        std::string path = dir.file(c.name);
        writeText(path, c.text);
        for (const char* mode : {"preview", "path"}) {
            INFO(mode);
            RunResult r = runRayproc({"render", path, "--mode", mode, "--spp", "2", "--quiet",
                                      "-o", dir.file("out.pfm")},
                                     logs);
            INFO(r.err);
            CHECK(r.status == 1);
            CHECK(contains(r.err, path + ": the scene cannot be rendered: " ));
            CHECK(contains(r.err, c.message));
            CHECK_FALSE(std::filesystem::exists(dir.file("out.pfm")));
        }
    }
    // The control: a thin but sane squash (1e-6) renders.
    std::string fine = dir.file("thin-but-fine.json");
    writeText(fine, scene("[1, 1e-6, 1]", "5"));
    RunResult ok = runRayproc({"render", fine, "--mode", "path", "--spp", "2", "--quiet", "-o",
                               dir.file("fine.pfm")},
                              logs);
    INFO(ok.err);
    CHECK(ok.status == 0);
}

TEST_CASE("Renders that cannot fit in memory are refused up front - running out is a clear error",
          "[cli][bad-input]") {
    if (!kAddressSpaceLimitWorks)
        RAYPROC_SKIP("AddressSanitizer build: address-space limits do not apply");
    TempDir dir, logs;
    std::string out = dir.file("out.pfm");
    // 20M photons need an estimated 3.8 GiB (with a progressive caustic pass of 16 x 50,000
    // photons); under a 1 GiB cap that is refused before any work (it used to trace photons
    // until an allocation failed).
    Limits l = memoryCap();
    RunResult r = runLimited({"render", scenePath("cornell-box"), "--mode", "gi", "--photons",
                              "20000000", "--width", "32", "--height", "32", "--quiet", "-o", out},
                             logs, l);
    INFO(r.err);
    CHECK(r.status == 1);
    CHECK(contains(r.err, "the render needs an estimated 3.8 GiB"));
    CHECK(contains(r.err, "more than the process may use (ulimit: 1.0 GiB)"));
    CHECK(r.seconds < 5.0);
    CHECK_FALSE(std::filesystem::exists(out));

    // 6M photons are estimated within a 1.4 GiB cap but do not fit in it: the allocation that
    // fails mid-pass ends in "out of memory", status 1 (it was "internal check failed" and an
    // abort, 134, when the exception unwound the ray processor with batches in flight).
    Limits tight;
    tight.addressSpace = rlim_t(1500000) * 1024;
    RunResult oom = runLimited({"render", scenePath("cornell-box"), "--mode", "gi", "--photons",
                                "6000000", "--width", "32", "--height", "32", "--quiet", "-o",
                                out},
                               logs, tight, 120);
    INFO(oom.err);
    CHECK(oom.status == 1);
    CHECK(contains(oom.err, "rayproc: out of memory"));
    CHECK_FALSE(contains(oom.err, "internal check failed"));
}
