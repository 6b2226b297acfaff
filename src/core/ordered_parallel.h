// tbb::parallel_for and parallel_invoke with their ordering made visible to ThreadSanitizer.
// TBB hands tasks to other threads and joins them inside libtbb, which Debian builds without
// instrumentation: what the calling thread wrote before the loop and what the bodies wrote
// for it to read after are ordered by TBB, but ThreadSanitizer cannot see that order and
// reports the accesses as races (docs/testing.md, "ThreadSanitizer"). Here a flag released
// before the loop is acquired by every body, and a count every body releases is acquired after
// it: the same order, stated with atomics the sanitizer instruments. Two atomic operations per
// chunk; use these where loops hand data to or from the calling thread.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <atomic>
#include <cstddef>

namespace rayproc {

template <typename Body>
void orderedParallelFor(std::size_t begin, std::size_t end, std::size_t grain, const Body& body) {
    std::atomic<bool> started{false};
    std::atomic<std::size_t> finished{0};
    started.store(true, std::memory_order_release);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, grain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          (void)started.load(std::memory_order_acquire);
                          body(r);
                          finished.fetch_add(1, std::memory_order_release);
                      });
    (void)finished.load(std::memory_order_acquire);
}

// One body call per index of [begin, end).
template <typename Body>
void orderedParallelForEach(std::size_t begin, std::size_t end, const Body& body) {
    orderedParallelFor(begin, end, 1, [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) body(i);
    });
}

template <typename F, typename G>
void orderedParallelInvoke(const F& f, const G& g) {
    std::atomic<bool> started{false};
    std::atomic<int> finished{0};
    started.store(true, std::memory_order_release);
    auto ordered = [&](const auto& task) {
        return [&] {
            (void)started.load(std::memory_order_acquire);
            task();
            finished.fetch_add(1, std::memory_order_release);
        };
    };
    tbb::parallel_invoke(ordered(f), ordered(g));
    (void)finished.load(std::memory_order_acquire);
}

} // namespace rayproc
