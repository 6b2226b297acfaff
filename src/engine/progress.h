// Progress on stderr: a live bar (percent, elapsed, ETA, rays/s) when stderr is a terminal,
// a plain line every few seconds when it is not, nothing with --quiet. Updated by a monitor
// thread, so workers never wait on output.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace rayproc {

class Progress {
public:
    // `fraction` and `rays` are polled from the monitor thread.
    Progress(std::string label, bool quiet, std::function<double()> fraction,
             std::function<std::uint64_t()> rays);
    ~Progress();
    // Stops the monitor and prints the final line: 100% when complete, else where it stopped.
    void finish(bool complete = true);

    static bool stderrIsTerminal();
    double elapsedSeconds() const;

private:
    void report(bool final, bool complete);
    void loop();

    std::string m_label;
    bool m_quiet, m_tty;
    std::function<double()> m_fraction;
    std::function<std::uint64_t()> m_rays;
    double m_interval;
    std::chrono::steady_clock::time_point m_start;
    std::mutex m_lock;
    std::condition_variable m_wake;
    bool m_stop = false;
    std::thread m_thread;
};

std::string formatDuration(double seconds);

} // namespace rayproc
