// Distributed renders (docs/distributed.md): rayproc under mpirun with 1, 2 and 4 ranks on this
// machine (oversubscribed loopback ranks), against one process without mpirun.
#include "test_util.h"

#include "image/image.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <thread>

#if defined(RAYPROC_MPIEXEC)

using namespace rayproc;
using namespace rayproc::test;

namespace {

// mpirun with what a test machine needs: more ranks than cores, root allowed (CI runs as
// root), shared-memory transport without ptrace-based single copy (containers forbid it).
std::vector<std::string> mpirunArgs(int ranks, const std::vector<std::string>& rayprocArgs) {
    std::vector<std::string> a{"--oversubscribe", "--allow-run-as-root", "--mca",
                               "btl_vader_single_copy_mechanism", "none", "-np",
                               std::to_string(ranks), rayprocBinary()};
    a.insert(a.end(), rayprocArgs.begin(), rayprocArgs.end());
    return a;
}

RunResult runMpi(int ranks, const std::vector<std::string>& rayprocArgs, const TempDir& dir) {
    return runRayproc(mpirunArgs(ranks, rayprocArgs), dir, 120, RAYPROC_MPIEXEC);
}

bool contains(const std::string& text, const std::string& what) {
    return text.find(what) != std::string::npos;
}

std::size_t lineCount(const std::string& text) {
    return std::size_t(std::count(text.begin(), text.end(), '\n'));
}

// Bit-for-bit: every float of every pixel.
bool samePixels(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.pixels == b.pixels;
}

// The children of a process (mpirun's ranks), from /proc.
std::vector<pid_t> childrenOf(pid_t parent) {
    std::vector<pid_t> out;
    for (auto& e : std::filesystem::directory_iterator("/proc")) {
        std::string name = e.path().filename().string();
        if (name.find_first_not_of("0123456789") != std::string::npos) continue;
        std::ifstream status(e.path() / "status");
        std::string line;
        while (std::getline(status, line))
            if (line.rfind("PPid:", 0) == 0) {
                if (std::stoi(line.substr(5)) == parent) out.push_back(pid_t(std::stoi(name)));
                break;
            }
    }
    return out;
}

} // namespace

TEST_CASE("A render over 1, 2 and 4 MPI ranks is bit-identical to one process, in every mode",
          "[cli][mpi]") {
    // 40x24: tiles cut at the edges, 6 tiles shared unevenly among 4 ranks. cornell-spheres has
    // a mirror and glass, so gi builds both photon maps, the cache and its gradients.
    auto [mode, extra] = GENERATE(table<std::string, std::vector<std::string>>({
        {"preview", {}},
        {"raytrace", {"--spp", "4"}},
        {"path", {"--spp", "8"}},
        {"gi", {"--spp", "2", "--photons", "20000", "--caustic-photons", "20000"}},
        // Each rank corrects its share of the cache's records; the sums are added.
        {"gi", {"--spp", "3", "--photons", "20000", "--caustic-photons", "20000",
                "--ic-correction-rays", "2"}},
        // Stop decisions made together: the same pass ends the render on every rank.
        {"path", {"--target-relmse", "0.05", "--spp", "64"}},
        // Adaptive sampling: the needs come from every rank's tiles, summed in tile order.
        {"path", {"--adaptive", "--spp", "16", "--adaptive-min-spp", "4"}},
        {"path", {"--target-relmse", "0.02", "--spp", "256", "--adaptive-min-spp", "4"}},
        // Spectral: each path's wavelengths are a pure function of its pixel and sample.
        {"path", {"--spp", "8", "--spectral"}},
        {"raytrace", {"--spp", "4", "--spectral"}},
        // Spectral gi: each photon's wavelengths are a pure function of the pass and its
        // index, a record's gather rays' of the record; the corrections sum in record order.
        {"gi", {"--spp", "3", "--photons", "20000", "--caustic-photons", "20000",
                "--ic-correction-rays", "2", "--spectral"}},
    }));
    INFO("mode " << mode);
    TempDir dir;
    std::vector<std::string> args{"render", scenePath("cornell-spheres"), "--mode", mode,
                                  "--width", "40", "--height", "24", "--threads", "1", "-q"};
    args.insert(args.end(), extra.begin(), extra.end());
    auto withOutput = [&](const std::string& out) {
        std::vector<std::string> a = args;
        a.push_back("-o");
        a.push_back(out);
        return a;
    };
    RunResult one = runRayproc(withOutput(dir.file("one.pfm")), dir);
    INFO(one.err);
    REQUIRE(one.status == 0);
    Image expected = readImage(dir.file("one.pfm"));
    REQUIRE(meanValue(expected) > 0.01);
    for (int ranks : {1, 2, 4}) {
        INFO(ranks << " ranks");
        std::string out = dir.file("ranks" + std::to_string(ranks) + ".pfm");
        RunResult r = runMpi(ranks, withOutput(out), dir);
        INFO(r.err);
        REQUIRE(r.status == 0);
        CHECK(samePixels(readImage(out), expected));
        // One writer: stdout names the image once.
        CHECK(lineCount(r.out) == 1);
    }
}

TEST_CASE("Statistics of a distributed render count every rank's work", "[cli][mpi]") {
    TempDir dir;
    std::vector<std::string> args{"render", scenePath("cornell-box"), "--mode", "path", "--spp",
                                  "4", "--width", "32", "--height", "32", "--threads", "1", "-q"};
    auto run = [&](int ranks, const std::string& name) {
        std::vector<std::string> a = args;
        a.insert(a.end(), {"-o", dir.file(name + ".pfm"), "--stats-json", dir.file(name + ".json")});
        return ranks == 0 ? runRayproc(a, dir) : runMpi(ranks, a, dir);
    };
    REQUIRE(run(0, "one").status == 0);
    REQUIRE(run(2, "two").status == 0);
    nlohmann::json one = nlohmann::json::parse(std::ifstream(dir.file("one.json")));
    nlohmann::json two = nlohmann::json::parse(std::ifstream(dir.file("two.json")));
    CHECK(one["samples"] == 32 * 32 * 4);
    CHECK(two["samples"] == 32 * 32 * 4);
    CHECK(two["rays"] == one["rays"]);
    CHECK(two["cluster"]["ranks"] == 2);
    CHECK(two["cluster"]["bytes_sent"].get<double>() > 0);
    CHECK_FALSE(one.contains("cluster"));
}

TEST_CASE("SIGTERM to mpirun writes the partial image gathered from every rank", "[cli][mpi]") {
    TempDir dir;
    std::string out = dir.file("partial.pfm");
    Child child(mpirunArgs(2, {"render", scenePath("cornell-box"), "--mode", "path", "--spp",
                               "100000", "--width", "48", "--height", "48", "--threads", "1",
                               "-o", out}),
                dir.file("stdout.txt"), dir.file("stderr.txt"), RAYPROC_MPIEXEC);
    REQUIRE(child.started());
    REQUIRE(child.waitForErr("mode=path", 60.0));
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    child.signal(SIGTERM);
    bool finished = child.wait(30.0);
    INFO(child.err());
    REQUIRE(finished);
    CHECK(child.status() != 0);
    // Every rank's tiles are in it: no pixel without samples.
    CHECK(contains(child.err(), "interrupted: wrote the partial image (0 pixels had no sample)"));
    REQUIRE(std::filesystem::exists(out));
    Image img = readImage(out);
    CHECK(allFinite(img));
    CHECK(meanValue(img) > 0.01);
    // Both halves of the image (tiles alternate between the two ranks) have light.
    double left = 0, right = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) (x < 16 ? left : right) += img.at(x, y)[1];
    CHECK(left > 0);
    CHECK(right > 0);
}

// Each rank runs under a shell that records the rank's pid and exit status, so that one rank can
// be signalled and rank 0's own status seen (mpirun reports one status for all of them).
TEST_CASE("SIGTERM to one rank during gi's photon pass keeps the old image and every rank exits 143",
          "[cli][mpi]") {
    TempDir dir;
    const std::string out = dir.file("old.pfm");
    Image old(24, 24);
    std::fill(old.pixels.begin(), old.pixels.end(), 0.5f);
    writeImage(out, old);
    const std::string before = readText(out);
    const std::string d = dir.path.string();
    const std::string script = "\"$0\" \"$@\" & echo $! > " + d + "/pid.$OMPI_COMM_WORLD_RANK; " +
                               "wait $!; echo $? > " + d + "/status.$OMPI_COMM_WORLD_RANK";
    const std::vector<std::string> render{
        "render", scenePath("cornell-box"), "--mode", "gi", "--photons", "4000000", "--spp", "1",
        "--width", "24", "--height", "24", "--threads", "1", "-o", out};
    std::vector<std::string> args = mpirunArgs(2, {});
    args.back() = "sh"; // in place of the rayproc binary, which the shell runs as "$0"
    args.insert(args.end(), {"-c", script, rayprocBinary()});
    args.insert(args.end(), render.begin(), render.end());
    Child child(args, dir.file("stdout.txt"), dir.file("stderr.txt"), RAYPROC_MPIEXEC);
    REQUIRE(child.started());
    REQUIRE(child.waitForErr("mode=gi", 60.0));
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    const std::string rank1 = readText(d + "/pid.1");
    REQUIRE_FALSE(rank1.empty());
    ::kill(pid_t(std::stoi(rank1)), SIGTERM); // not rank 0: it learns of it from rank 1
    bool finished = child.wait(90.0);
    INFO(child.err());
    REQUIRE(finished);
    CHECK(readText(d + "/status.1") == "143\n");
    CHECK(readText(d + "/status.0") == "143\n"); // was 130, as if Ctrl-C had been pressed
    CHECK(contains(child.err(), "interrupted before any pixel had a sample: nothing was written"));
    CHECK(readText(out) == before); // was replaced by a black image
}

TEST_CASE("A rank that dies ends the job with a clear error, not a hang", "[cli][mpi]") {
    TempDir dir;
    Child child(mpirunArgs(2, {"render", scenePath("cornell-box"), "--mode", "path", "--spp",
                               "100000", "--width", "48", "--height", "48", "--threads", "1",
                               "-q", "-o", dir.file("never.pfm")}),
                dir.file("stdout.txt"), dir.file("stderr.txt"), RAYPROC_MPIEXEC);
    REQUIRE(child.started());
    std::vector<pid_t> ranks;
    for (int i = 0; i < 100 && ranks.size() < 2; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        ranks = childrenOf(child.pid());
    }
    REQUIRE(ranks.size() == 2);
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));
    ::kill(ranks.back(), SIGKILL);
    auto killed = std::chrono::steady_clock::now();
    bool finished = child.wait(30.0);
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - killed).count();
    INFO(child.err());
    REQUIRE(finished);
    CHECK(seconds < 20);
    CHECK(child.status() != 0);
    CHECK(contains(child.err(), "exited on signal 9"));
}

TEST_CASE("Commands other than render refuse to run across MPI ranks", "[cli][mpi]") {
    TempDir dir;
    RunResult r = runMpi(2, {"info", scenePath("cornell-box")}, dir);
    INFO(r.err);
    CHECK(r.status != 0);
    CHECK(contains(r.err, "only 'render' runs across MPI ranks"));
}

#else

#include "skip.h"

// Without RAYPROC_MPIEXEC (configured with RAYPROC_MPI=OFF, as the sanitizer build is, or no
// MPI found) the cases above are not compiled; this one says so in ctest's summary.
TEST_CASE("MPI renders are not tested in this build", "[cli][mpi]") {
    RAYPROC_SKIP("built without RAYPROC_MPIEXEC (RAYPROC_MPI=OFF or no MPI); the MPI tests are "
                 "compiled out");
}

#endif
