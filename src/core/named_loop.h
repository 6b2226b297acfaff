// Parallel loops with a name (docs/style.md: every parallel loop is named for the statistics).
// Where the calling thread's phases are timed (the render command installs its PhaseLog as the
// thread's LoopLog, engine/phases.h), a named loop's wall time is recorded as a phase of its
// own that runs on every thread: the serial phase around it (the scene load decoding a
// texture, the light set building a sky's tables) then counts only the time it spends on one
// thread, and `--stats` says where the rest went. A loop run inside another named loop, or on
// a thread without a log (TBB's workers, serve's sessions, tests), records nothing. Not for
// the per-ray path: a loop costs two clock reads.
#pragma once

#include <chrono>

namespace rayproc {

class LoopLog {
public:
    virtual ~LoopLog() = default;
    // A named loop of `seconds` wall time ended on the thread this log is installed on.
    virtual void loopTimed(const char* name, double seconds) = 0;

    // Installs `log` as the calling thread's for the scope's life (null: none).
    class Scope {
    public:
        explicit Scope(LoopLog* log);
        ~Scope();
        Scope(const Scope&) = delete;
        Scope& operator=(const Scope&) = delete;

    private:
        LoopLog* m_previous;
    };

    // The log a loop starting now on this thread records into (null inside another named
    // loop), and the loop's end; used by namedLoop.
    static LoopLog* enter();
    static void leave();
};

// Runs `run` (a TBB loop, or several) as the named parallel loop `name`.
template <typename Run>
void namedLoop(const char* name, Run&& run) {
    struct Guard {
        LoopLog* log = LoopLog::enter();
        std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
        ~Guard() { LoopLog::leave(); }
    } guard;
    run();
    if (guard.log)
        guard.log->loopTimed(
            name,
            std::chrono::duration<double>(std::chrono::steady_clock::now() - guard.start).count());
}

} // namespace rayproc
