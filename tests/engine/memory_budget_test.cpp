// The memory estimate made before a render, and the verdict against what the machine has.
#include "engine/memory_budget.h"

#include <catch2/catch.hpp>

using namespace rayproc;

TEST_CASE("The memory estimate grows with pixels and photons and is judged against the machine",
          "[engine]") {
    MemoryEstimate small = estimateRenderMemory(512 * 512, 0, 0, 0);
    MemoryEstimate gi = estimateRenderMemory(512 * 512, 5000000, 200000, 0);
    CHECK(small.photonBytes == 0);
    CHECK(gi.total() > small.total());
    // The calibration point: 5M photons of the Cornell box peaked at 1093 MB (RSS).
    MemoryEstimate box = estimateRenderMemory(64 * 64, 5000000, 0, 0);
    CHECK(double(box.total()) == Approx(1093e6).epsilon(0.15));
    // A caustic map brings gi's caustic radius per pixel (20 bytes each) beside its photons.
    MemoryEstimate noCaustic = estimateRenderMemory(4096 * 4096, 0, 0, 0);
    MemoryEstimate caustic = estimateRenderMemory(4096 * 4096, 0, 1, 0);
    CHECK(caustic.photonBytes - noCaustic.photonBytes == 96 + 4096ull * 4096 * 20);

    SystemMemory machine;
    machine.totalBytes = 24ull << 30;
    machine.availableBytes = 20ull << 30;
    bool fatal = true;
    CHECK(memoryProblem(small, machine, fatal).empty());
    CHECK_FALSE(fatal);

    // 22 GiB: fits the machine, not what is free now: a warning.
    MemoryEstimate tight;
    tight.photonBytes = 22ull << 30;
    std::string warn = memoryProblem(tight, machine, fatal);
    CHECK_FALSE(fatal);
    CHECK(warn.find("more than is available now (20.0 GiB)") != std::string::npos);

    // Beyond RAM + swap, or beyond the process's limit: refused.
    MemoryEstimate huge;
    huge.photonBytes = 30ull << 30;
    std::string refuse = memoryProblem(huge, machine, fatal);
    CHECK(fatal);
    CHECK(refuse.find("estimated 30.0 GiB") != std::string::npos);
    CHECK(refuse.find("more than this machine has (24.0 GiB") != std::string::npos);
    machine.limitBytes = 1ull << 30;
    refuse = memoryProblem(gi, machine, fatal);
    CHECK(fatal);
    CHECK(refuse.find("ulimit: 1.0 GiB") != std::string::npos);
    // Unknown figures (0) judge nothing.
    CHECK(memoryProblem(huge, SystemMemory{}, fatal).empty());
    CHECK_FALSE(fatal);
}
