// --threads under an address-space limit, through the real binary: TBB threw "pthread_create has
// failed" from a worker thread, which nothing can catch (status 134); now the render falls back
// to the threads that fit, says so, and writes its image.
#include "cli/limited_run.h"
#include "skip.h"

#include "image/image.h"

#include <catch2/catch.hpp>

using namespace rayproc;
using namespace rayproc::test;

TEST_CASE("More --threads than an address-space limit holds fall back to fewer, with a warning",
          "[cli][bad-input]") {
    if (!kAddressSpaceLimitWorks)
        RAYPROC_SKIP("AddressSanitizer build: an address-space limit cannot apply");
    struct Case {
        int threads;
        rlim_t limit;
    };
    // The two: ulimit -v 1000000 (KiB) with 1024 threads, 600 MB with 64.
    const Case cases[] = {{1024, rlim_t(1000000) * 1024}, {64, rlim_t(600) * 1000 * 1000}};
    for (const Case& c : cases) {
        TempDir dir;
        Limits limits;
        limits.addressSpace = c.limit;
        const std::string out = dir.file("out.pfm");
        RunResult r = runLimited({"render", scenePath("cornell-box"), "--mode", "path", "--spp",
                                  "4", "--width", "32", "--height", "32", "--threads",
                                  std::to_string(c.threads), "-o", out},
                                 dir, limits, 120);
        INFO(c.threads << " threads under " << c.limit << " bytes\n" << r.err);
        CHECK(r.status == 0); // was 134: "terminate called ... pthread_create has failed"
        CHECK(r.err.find("--threads " + std::to_string(c.threads) +
                         ": the process's address-space limit") != std::string::npos);
        REQUIRE(std::filesystem::exists(out));
        CHECK(readImage(out).width == 32);
    }
}
