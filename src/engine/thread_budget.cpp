#include "engine/thread_budget.h"

#include "engine/memory_budget.h"

#include <malloc.h>
#include <sys/resource.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <thread>

namespace rayproc {

namespace {

// A "VmSize:" / "VmData:" line of /proc/self/status in bytes, 0 when absent.
std::uint64_t procStatusBytes(const std::string& key) {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line)) {
        if (line.compare(0, key.size(), key) != 0) continue;
        std::istringstream fields(line.substr(key.size()));
        std::uint64_t kib = 0;
        fields >> kib;
        return kib * 1024;
    }
    return 0;
}

} // namespace

ThreadBudget budgetThreads(int requested, int cores, std::uint64_t roomBytes) {
    ThreadBudget b;
    b.threads = requested;
    if (roomBytes == 0) return b;
    const int wanted = requested > 0 ? requested : std::max(1, cores);
    const std::uint64_t quarter = roomBytes / 4;
    const int affordable = int(std::min<std::uint64_t>(quarter / kThreadReserveBytes, 1 << 20));
    b.mallocArenas = int(std::clamp<std::uint64_t>(quarter / kMallocArenaBytes, 1, 64));
    if (wanted <= affordable) return b;
    b.threads = std::max(1, affordable);
    b.warning = (requested > 0 ? "--threads " + std::to_string(requested)
                               : std::to_string(wanted) + " threads (all cores)") +
                ": the process's address-space limit leaves " + formatBytes(roomBytes) +
                ", room for the stacks of " + std::to_string(affordable) + " threads; using " +
                std::to_string(b.threads) + " (raise ulimit -v or lower --threads)";
    return b;
}

std::uint64_t addressSpaceRoom() {
    std::uint64_t room = 0;
    const std::pair<int, const char*> limits[] = {{RLIMIT_AS, "VmSize:"}, {RLIMIT_DATA, "VmData:"}};
    for (const auto& [resource, key] : limits) {
        rlimit l{};
        if (getrlimit(resource, &l) != 0 || l.rlim_cur == RLIM_INFINITY) continue;
        const std::uint64_t used = procStatusBytes(key);
        const std::uint64_t left = l.rlim_cur > used ? l.rlim_cur - used : 1;
        room = room == 0 ? left : std::min(room, left);
    }
    return room;
}

ThreadBudget applyThreadBudget(int requested) {
    ThreadBudget b = budgetThreads(requested, int(std::thread::hardware_concurrency()),
                                   addressSpaceRoom());
    if (b.mallocArenas > 0) mallopt(M_ARENA_MAX, b.mallocArenas);
    return b;
}

} // namespace rayproc
