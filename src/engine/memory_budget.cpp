#include "engine/memory_budget.h"

#include <sys/resource.h>

#include <cstdio>
#include <fstream>
#include <sstream>

namespace rayproc {

namespace {

// Film: 128-bit sums (2 x 8 bytes x 3), sample counts (4 + 8), double totals (3 x 8), and the
// resolved float image plus its output copy (2 x 12).
constexpr std::uint64_t kFilmBytesPerPixel = 48 + 12 + 24 + 24;
constexpr std::uint64_t kBytesPerGlobalPhoton = 192;
// Caustic photons are stored only after a specular bounce: most emitted ones store nothing.
constexpr std::uint64_t kBytesPerCausticPhoton = 96;
// gi's caustic radius per pixel (gi/caustic_pixel_radius.h: radius, photon count and three
// 32-bit counters), counted whenever there is a caustic map (also under
// --no-caustic-pixel-radius, where it is not allocated: a small overestimate).
constexpr std::uint64_t kCausticRadiusBytesPerPixel = 4 + 4 + 3 * 4;
constexpr std::uint64_t kProcessBytes = 128ull << 20;

} // namespace

MemoryEstimate estimateRenderMemory(std::uint64_t pixels, std::uint64_t globalPhotons,
                                    std::uint64_t causticPhotons, std::uint64_t sceneBytes) {
    MemoryEstimate e;
    e.filmBytes = pixels * kFilmBytesPerPixel;
    e.photonBytes = globalPhotons * kBytesPerGlobalPhoton + causticPhotons * kBytesPerCausticPhoton;
    if (causticPhotons > 0) e.photonBytes += pixels * kCausticRadiusBytesPerPixel;
    e.baseBytes = kProcessBytes + sceneBytes;
    return e;
}

SystemMemory systemMemory() {
    SystemMemory m;
    std::ifstream in("/proc/meminfo");
    std::string key;
    std::uint64_t value = 0, memTotal = 0, memAvailable = 0, swapTotal = 0, swapFree = 0;
    std::string unit;
    while (in >> key >> value) {
        std::getline(in, unit);
        if (key == "MemTotal:") memTotal = value * 1024;
        else if (key == "MemAvailable:") memAvailable = value * 1024;
        else if (key == "SwapTotal:") swapTotal = value * 1024;
        else if (key == "SwapFree:") swapFree = value * 1024;
    }
    if (memTotal > 0) m.totalBytes = memTotal + swapTotal;
    if (memAvailable > 0) m.availableBytes = memAvailable + swapFree;
    for (int resource : {RLIMIT_AS, RLIMIT_DATA}) {
        rlimit l{};
        if (getrlimit(resource, &l) == 0 && l.rlim_cur != RLIM_INFINITY &&
            (m.limitBytes == 0 || l.rlim_cur < m.limitBytes))
            m.limitBytes = l.rlim_cur;
    }
    return m;
}

std::string formatBytes(std::uint64_t bytes) {
    char buf[32];
    if (bytes >= (1ull << 30)) std::snprintf(buf, sizeof buf, "%.1f GiB", double(bytes) / (1ull << 30));
    else std::snprintf(buf, sizeof buf, "%.1f MiB", double(bytes) / (1ull << 20));
    return buf;
}

std::string memoryProblem(const MemoryEstimate& e, const SystemMemory& m, bool& fatal) {
    fatal = false;
    std::uint64_t need = e.total();
    std::ostringstream what;
    what << "the render needs an estimated " << formatBytes(need) << " (film "
         << formatBytes(e.filmBytes);
    if (e.photonBytes > 0) what << ", photon maps " << formatBytes(e.photonBytes);
    what << ")";
    if (m.limitBytes > 0 && need > m.limitBytes) {
        fatal = true;
        what << ", more than the process may use (ulimit: " << formatBytes(m.limitBytes) << ")";
        return what.str();
    }
    if (m.totalBytes > 0 && need > m.totalBytes) {
        fatal = true;
        what << ", more than this machine has (" << formatBytes(m.totalBytes)
             << " of memory and swap)";
        return what.str();
    }
    if (m.availableBytes > 0 && need > m.availableBytes) {
        what << ", more than is available now (" << formatBytes(m.availableBytes)
             << "); it may fail or swap";
        return what.str();
    }
    return {};
}

} // namespace rayproc
