// Helpers shared by the engine, accel, modes, cli and golden tests: paths into the source tree,
// temporary folders, scenes from JSON text, one-call renders, image comparison, and running the
// rayproc binary as a child process with its output captured in files.
#pragma once

#include "accel/embree_scene.h"
#include "cluster/cluster.h"
#include "gi/focus_region.h"
#include "gi/photon_pass.h"
#include "image/image.h"
#include "modes/modes.h"
#include "scene/scene_loader.h"

#include <catch2/catch.hpp>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

extern char** environ;

namespace rayproc::test {

// Paths ----------------------------------------------------------------------------------------

inline std::filesystem::path sourceDir() {
    return RAYPROC_SOURCE_DIR;
}
inline std::string scenePath(const std::string& name) {
    return (sourceDir() / "scenes" / (name + ".json")).string();
}
inline std::string goldenPath(const std::string& name) {
    return (sourceDir() / "tests" / "golden" / name).string();
}
inline std::string rayprocBinary() {
    return RAYPROC_BINARY;
}

// A fresh directory under the system temp directory, removed with its contents at scope exit.
struct TempDir {
    std::filesystem::path path;
    TempDir() {
        static std::atomic<int> counter{0};
        path = std::filesystem::temp_directory_path() /
               ("rayproc_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        std::filesystem::remove_all(path);
        std::filesystem::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    std::string file(const std::string& name) const { return (path / name).string(); }
};

inline std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

inline void writeText(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

// Scenes and renders ---------------------------------------------------------------------------

// A scene from JSON text; `name` only labels messages.
inline std::unique_ptr<Scene> sceneFromJson(const std::string& json,
                                            const std::string& name = "test-scene.json") {
    return loadSceneFromString(json, (sourceDir() / "scenes" / name).string());
}

// A scene file of scenes/ at a reduced resolution.
inline std::unique_ptr<Scene> loadSceneAt(const std::string& name, int width, int height) {
    auto scene = loadScene(scenePath(name));
    scene->camera.width = width;
    scene->camera.height = height;
    return scene;
}

// A render's extra statistic (RenderStats::extras, e.g. "gi/gather_rays"); fails the test when
// the render has none of that name.
inline double extraStat(const RenderResult& r, const std::string& name) {
    for (const auto& [key, value] : r.stats.extras)
        if (key == name) return value;
    FAIL("no extra statistic " << name);
    return 0;
}

// The mean radiance of an image per channel.
inline Vec3 imageMean(const Image& img) {
    Vec3 sum(0.0f);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) sum += Vec3(img.at(x, y)[0], img.at(x, y)[1], img.at(x, y)[2]);
    return sum / float(img.width * img.height);
}

struct RenderOptions {
    std::string mode = "raytrace";
    int spp = 4;
    int lightSamples = 0; // 0: the mode's default
    int threads = 2;
    int packetWidth = 16;
    std::uint64_t seed = 1;
    int maxDepth = 0; // 0: the mode's default
    bool glossyMis = true; // raytrace: EngineSettings::glossyMis
    bool lightChoice = true; // raytrace: EngineSettings::lightChoice
    bool diffuseMis = true; // raytrace: EngineSettings::diffuseMis
};

// The engine of a quiet two-thread render at seed 1, RGB or spectral.
inline EngineSettings quietTwoThreads(bool spectral = false) {
    EngineSettings engine;
    engine.threads = 2;
    engine.seed = 1;
    engine.quiet = true;
    engine.spectral = spectral;
    return engine;
}

// Renders quietly through the library, as `rayproc render` does (without the file output).
// `mode` is "preview", "path", or anything else for raytrace.
inline RenderResult render(const Scene& scene, const EmbreeScene& accel, const RenderOptions& o) {
    EngineSettings engine;
    engine.threads = o.threads;
    engine.packetWidth = o.packetWidth;
    engine.seed = o.seed;
    engine.quiet = true;
    engine.glossyMis = o.glossyMis;
    engine.lightChoice = o.lightChoice;
    engine.diffuseMis = o.diffuseMis;
    ModeOverrides overrides{o.spp, o.maxDepth, o.lightSamples};
    if (o.mode == "preview")
        return renderPreview(scene, accel, previewSettings(scene.render, overrides), engine);
    if (o.mode == "path")
        return renderPath(scene, accel, pathSettings(scene.render, overrides), engine);
    return renderRaytrace(scene, accel, raytraceSettings(scene.render, overrides), engine);
}

// Image comparison -----------------------------------------------------------------------------

// Mean over pixels and channels of (a - b)^2 / (b^2 + 0.01): the relative MSE of `a` against the
// reference `b`, with an offset that keeps dark pixels from dominating.
inline double relMse(const Image& a, const Image& b) {
    REQUIRE(a.width == b.width);
    REQUIRE(a.height == b.height);
    double sum = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        double d = double(a.pixels[i]) - double(b.pixels[i]);
        sum += d * d / (double(b.pixels[i]) * double(b.pixels[i]) + 0.01);
    }
    return a.pixels.empty() ? 0.0 : sum / double(a.pixels.size());
}

// relMSE without the `dropPixels` pixels of largest error (summed over channels): robust to
// a few antialiasing outliers, such as the edge of a bright light that one of 16 samples
// happens to hit and none of 64 did.
inline double relMseTrimmed(const Image& a, const Image& b, std::size_t dropPixels) {
    REQUIRE(a.width == b.width);
    REQUIRE(a.height == b.height);
    std::vector<double> perPixel;
    for (std::size_t p = 0; p + 2 < a.pixels.size(); p += 3) {
        double e = 0;
        for (std::size_t c = p; c < p + 3; ++c) {
            double d = double(a.pixels[c]) - double(b.pixels[c]);
            e += d * d / (double(b.pixels[c]) * double(b.pixels[c]) + 0.01);
        }
        perPixel.push_back(e);
    }
    if (perPixel.size() <= dropPixels) return 0.0;
    std::sort(perPixel.begin(), perPixel.end());
    double sum = 0;
    for (std::size_t i = 0; i + dropPixels < perPixel.size(); ++i) sum += perPixel[i];
    return sum / (3.0 * double(perPixel.size() - dropPixels));
}

inline bool allFinite(const Image& img) {
    for (float v : img.pixels)
        if (!std::isfinite(v)) return false;
    return true;
}

// gi's global photon pass over `scene` (one process, 2 threads, quiet, no focus region): the
// map, and the map the gather reads into `gatherMap`.
inline PhotonRounds traceGlobalMap(const Scene& scene, const EmbreeScene& accel,
                                   const PhotonPassSpec& pass, PhotonMap& map,
                                   PhotonMap* gatherMap) {
    LightSet lights = LightSet::build(scene, accel);
    EngineSettings engine;
    engine.threads = 2;
    engine.quiet = true;
    Cluster alone;
    Stats stats;
    return buildPhotonMap(map, scene, accel, lights, GiSettings{}, engine, alone, nullptr, pass,
                          FocusRegion{}, stats, gatherMap);
}

// The same size and the same bits in every value.
inline bool sameBits(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.pixels.size() == b.pixels.size() &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
}

inline double meanValue(const Image& img) {
    double s = 0;
    for (float v : img.pixels) s += v;
    return img.pixels.empty() ? 0.0 : s / double(img.pixels.size());
}

// Every pixel value multiplied by `factor`.
inline Image scaledImage(const Image& img, float factor) {
    Image out = img;
    for (float& v : out.pixels) v *= factor;
    return out;
}

// The mean over pixels of one channel (0, 1, 2) and its standard error, estimated from the
// spread of the per-pixel values: pixels are independent estimates (their random streams are
// keyed by pixel), so stdError = sample standard deviation / sqrt(pixel count). Analytic tests
// compare the mean with the expected radiance and state stdError. The rectangle [x0, x1) x
// [y0, y1) restricts the pixels (x1, y1 <= 0: the whole image).
struct PixelStats {
    double mean = 0, stdError = 0, stdDev = 0, min = 0, max = 0;
    std::size_t count = 0;
};
inline PixelStats pixelStats(const Image& img, int channel, int x0 = 0, int y0 = 0, int x1 = 0,
                             int y1 = 0) {
    if (x1 <= 0) x1 = img.width;
    if (y1 <= 0) y1 = img.height;
    PixelStats st;
    double sum = 0, sum2 = 0;
    st.min = INFINITY;
    st.max = -INFINITY;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            double v = img.at(x, y)[channel];
            sum += v;
            sum2 += v * v;
            st.min = std::min(st.min, v);
            st.max = std::max(st.max, v);
            ++st.count;
        }
    if (st.count == 0) return st;
    double n = double(st.count);
    st.mean = sum / n;
    double var = st.count > 1 ? std::max(0.0, (sum2 - n * st.mean * st.mean) / (n - 1)) : 0.0;
    st.stdDev = std::sqrt(var);
    st.stdError = st.stdDev / std::sqrt(n);
    return st;
}

// Child processes ------------------------------------------------------------------------------

// A rayproc process started with its stdout and stderr redirected to files.
class Child {
public:
    // Starts RAYPROC_BINARY (or `program`, a path) with `args`; SIGINT is unblocked and at its
    // default disposition in the child whatever the test process (Catch2's signal handlers)
    // has set.
    Child(const std::vector<std::string>& args, const std::string& outFile,
          const std::string& errFile, const std::string& program = rayprocBinary())
        : m_out(outFile), m_err(errFile) {
        std::vector<std::string> all{program};
        all.insert(all.end(), args.begin(), args.end());
        std::vector<char*> argv;
        for (auto& a : all) argv.push_back(a.data());
        argv.push_back(nullptr);

        posix_spawn_file_actions_t fa;
        posix_spawn_file_actions_init(&fa);
        posix_spawn_file_actions_addopen(&fa, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
        posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, m_out.c_str(),
                                         O_WRONLY | O_CREAT | O_TRUNC, 0644);
        posix_spawn_file_actions_addopen(&fa, STDERR_FILENO, m_err.c_str(),
                                         O_WRONLY | O_CREAT | O_TRUNC, 0644);
        posix_spawnattr_t attr;
        posix_spawnattr_init(&attr);
        sigset_t none, defaults;
        sigemptyset(&none);
        sigemptyset(&defaults);
        sigaddset(&defaults, SIGINT);
        sigaddset(&defaults, SIGPIPE);
        posix_spawnattr_setsigmask(&attr, &none);
        posix_spawnattr_setsigdefault(&attr, &defaults);
        posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
        int rc = posix_spawn(&m_pid, argv[0], &fa, &attr, argv.data(), environ);
        posix_spawn_file_actions_destroy(&fa);
        posix_spawnattr_destroy(&attr);
        if (rc != 0) m_pid = -1;
    }
    ~Child() {
        if (m_pid > 0 && !m_done) {
            ::kill(m_pid, SIGKILL);
            int st = 0;
            ::waitpid(m_pid, &st, 0);
        }
    }
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;

    bool started() const { return m_pid > 0; }
    pid_t pid() const { return m_pid; }
    void signal(int sig) const {
        if (m_pid > 0 && !m_done) ::kill(m_pid, sig);
    }

    // Waits up to `timeoutSeconds`; returns false (and kills the child) on timeout.
    bool wait(double timeoutSeconds) {
        if (m_pid <= 0) return false;
        if (m_done) return true;
        auto deadline =
            std::chrono::steady_clock::now() + std::chrono::duration<double>(timeoutSeconds);
        for (;;) {
            int st = 0;
            pid_t r = ::waitpid(m_pid, &st, WNOHANG);
            if (r == m_pid) {
                m_done = true;
                m_status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
                return true;
            }
            if (std::chrono::steady_clock::now() > deadline) {
                ::kill(m_pid, SIGKILL);
                ::waitpid(m_pid, &st, 0);
                m_done = true;
                m_status = -1;
                return false;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
    }
    // Exit status, or 128 + signal number when a signal ended the child; -1 after a timeout.
    int status() const { return m_status; }
    std::string out() const { return readText(m_out); }
    std::string err() const { return readText(m_err); }
    // Waits up to `timeoutSeconds` until the child's stderr holds `text`; false if it does not.
    // Tests that signal a render wait for its settings line (printed once the scene is loaded
    // and the signal handlers are in place) rather than a fixed time, which a loaded machine
    // can outlast.
    bool waitForErr(const std::string& text, double timeoutSeconds) const {
        auto deadline =
            std::chrono::steady_clock::now() + std::chrono::duration<double>(timeoutSeconds);
        while (err().find(text) == std::string::npos) {
            if (std::chrono::steady_clock::now() > deadline) return false;
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        return true;
    }

private:
    std::string m_out, m_err;
    pid_t m_pid = -1;
    bool m_done = false;
    int m_status = -1;
};

struct RunResult {
    int status = -1; // exit status; 128 + signal; -1 on timeout or spawn failure
    std::string out, err;
    double seconds = 0;
};

// Runs rayproc (or `program`, e.g. mpirun) to completion (at most `timeoutSeconds`) with its
// output captured under `dir`.
inline RunResult runRayproc(const std::vector<std::string>& args, const TempDir& dir,
                            double timeoutSeconds = 60,
                            const std::string& program = rayprocBinary()) {
    static std::atomic<int> counter{0};
    int n = counter++;
    auto start = std::chrono::steady_clock::now();
    Child child(args, dir.file("stdout" + std::to_string(n) + ".txt"),
                dir.file("stderr" + std::to_string(n) + ".txt"), program);
    RunResult r;
    if (!child.started()) return r;
    child.wait(timeoutSeconds);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.status = child.status();
    r.out = child.out();
    r.err = child.err();
    return r;
}

} // namespace rayproc::test
