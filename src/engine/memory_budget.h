// The memory a render will need, estimated before it starts, and what the machine has: a
// render that cannot fit is refused with the figures, one that may not fit is warned of,
// instead of failing (or being killed) after minutes of work.
#pragma once

#include <cstdint>
#include <string>

namespace rayproc {

struct MemoryEstimate {
    std::uint64_t filmBytes = 0;   // the film's per-pixel sums and the images made from it
    std::uint64_t photonBytes = 0; // gi: photon passes, maps and their kd-tree builds (peak)
    std::uint64_t baseBytes = 0;   // the process, the scene and Embree's BVH, roughly
    std::uint64_t total() const { return filmBytes + photonBytes + baseBytes; }
};

// Calibrated on the Cornell box (peak RSS: 324 MB at 1M photons, 1093 MB at 5M: 192 bytes per
// emitted photon, 1.85 photons stored per emitted one); scenes whose light bounces more store
// more, so the photon figure is a typical value, not a bound.
MemoryEstimate estimateRenderMemory(std::uint64_t pixels, std::uint64_t globalPhotons,
                                    std::uint64_t causticPhotons, std::uint64_t sceneBytes);

struct SystemMemory {
    std::uint64_t totalBytes = 0;     // RAM + swap (MemTotal + SwapTotal); 0 when unknown
    std::uint64_t availableBytes = 0; // MemAvailable + SwapFree; 0 when unknown
    std::uint64_t limitBytes = 0;     // RLIMIT_AS / RLIMIT_DATA when set, else 0
};
SystemMemory systemMemory();

// "" when the estimate fits; otherwise the problem, and `fatal` says whether it cannot fit at
// all (more than RAM + swap or the process's limit) or only may not (more than is available).
std::string memoryProblem(const MemoryEstimate& e, const SystemMemory& m, bool& fatal);

std::string formatBytes(std::uint64_t bytes);

} // namespace rayproc
