// A report at a fixed interval while a render's passes run, from a thread of its own, and
// once more when they end: rayproc serve's page and `render --display-server` show the image
// filling in with it (RenderControl::Watcher: the film so far, through the film's sensor).
#pragma once

#include "modes/render_job.h"

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>

namespace rayproc {

class PeriodicReport {
public:
    struct Progress {
        double fraction = 0;    // of the passes' work
        std::uint64_t rays = 0; // traced so far
        double seconds = 0;     // since the passes began
    };
    using Report = std::function<void(Image image, const Progress& progress)>;

    PeriodicReport(double intervalSeconds, Report report);
    ~PeriodicReport(); // stops a report still running
    PeriodicReport(const PeriodicReport&) = delete;
    PeriodicReport& operator=(const PeriodicReport&) = delete;
    // For RenderControl::watcher; valid while this object lives.
    const RenderControl::Watcher* watcher() const { return &m_watcher; }

private:
    void begin(std::function<Image()> image, std::function<double()> fraction,
               std::function<std::uint64_t()> rays);
    void end();
    void reportNow();

    std::chrono::duration<double> m_interval;
    Report m_report;
    RenderControl::Watcher m_watcher;
    std::mutex m_mutex;
    std::condition_variable m_wake;
    bool m_running = false;
    std::thread m_thread;
    std::function<Image()> m_image; // set while a render runs
    std::function<double()> m_fraction;
    std::function<std::uint64_t()> m_rays;
    std::chrono::steady_clock::time_point m_start;
};

} // namespace rayproc
