// File reads a pbrt scene starts and needs only at its end (PLY meshes), run as TBB tasks while
// the parser goes on (issue 35: scene loading was one thread's). What the file says comes out
// as if each read had run where its directive stands:
// - its warnings join the scene's in directive order: before the parser adds a warning of its
//   own, and at the end, the reads started so far are waited for and their warnings merged in
//   the order they were started (Warnings::setBeforeAdd);
// - the first failed read, in directive order, is the load's error, also when the parser has
//   failed later in the file (join() after the parser's exception).
// With one thread (`--threads 1`) the tasks run when they are waited for, on the loading thread.
#pragma once

#include "scene/pbrt/pbrt_warnings.h"

#include <tbb/task_group.h>

#include <deque>
#include <exception>
#include <functional>
#include <memory>

namespace rayproc::pbrt {

class DeferredLoads {
public:
    DeferredLoads() = default;
    DeferredLoads(const DeferredLoads&) = delete;
    DeferredLoads& operator=(const DeferredLoads&) = delete;
    ~DeferredLoads(); // waits: no read outlives the load that started it

    // Starts `read`; what it warns goes to its own list until join() merges it.
    void start(std::function<void(Warnings&)> read);
    // Waits for the reads started so far, merges their warnings into `into` in start order and
    // rethrows the first one's error; a read is merged (and its error thrown) once, and after
    // an error nothing more is merged or thrown.
    void join(Warnings& into);
    bool pending() const { return m_joined < m_reads.size(); }

private:
    struct Read {
        std::function<void(Warnings&)> run;
        Warnings warnings;
        std::exception_ptr error;
    };
    std::unique_ptr<tbb::task_group> m_group; // made by the first start(): a scene without
                                              // PLY files never touches TBB here
    std::deque<Read> m_reads; // a deque: a running task's Read never moves
    std::size_t m_joined = 0;
    bool m_failed = false;
};

} // namespace rayproc::pbrt
