// Worker threads under an address-space limit (ulimit -v, RLIMIT_DATA).
//
// Every thread reserves its stack (TBB's workers: 4 MiB) and glibc gives busy threads their own
// malloc arena (64 MiB of address space each). TBB creates its workers lazily, from its own
// threads, and throws when pthread_create fails there: nothing can catch it and the process
// aborts ("pthread_create has failed" with --threads 1024 under ulimit -v 1000000, issue 36).
// So the thread count is bounded before TBB sees it, and the arenas are capped.
#pragma once

#include <cstdint>
#include <string>

namespace rayproc {

// The stack size rayproc asks TBB to give its workers (tbb::global_control::thread_stack_size).
constexpr std::uint64_t kWorkerStackBytes = std::uint64_t(4) << 20;
// What one thread costs in address space besides its arena: the stack, its guard page, TLS.
constexpr std::uint64_t kThreadReserveBytes = kWorkerStackBytes + (std::uint64_t(256) << 10);
// glibc's per-thread arena reservation on 64-bit (HEAP_MAX_SIZE).
constexpr std::uint64_t kMallocArenaBytes = std::uint64_t(64) << 20;

struct ThreadBudget {
    int threads = 0;      // what to use: the request, or fewer; 0: no limit (all cores)
    int mallocArenas = 0; // glibc's M_ARENA_MAX to set; 0: leave it
    std::string warning;  // why fewer threads than asked for, "" when none
};

// Threads may take a quarter of `roomBytes` (the limit less what the process already maps;
// 0: no limit) for their stacks and another quarter for malloc arenas; the rest is the render's.
// `requested` 0 means every one of `cores`.
ThreadBudget budgetThreads(int requested, int cores, std::uint64_t roomBytes);

// The address space the process may still map under RLIMIT_AS and RLIMIT_DATA (the smaller
// room), 0 when neither is set.
std::uint64_t addressSpaceRoom();

// budgetThreads for this process, with M_ARENA_MAX set when it says so.
ThreadBudget applyThreadBudget(int requested);

} // namespace rayproc
