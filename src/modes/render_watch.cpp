#include "modes/render_watch.h"

namespace rayproc {

PeriodicReport::PeriodicReport(double intervalSeconds, Report report)
    : m_interval(intervalSeconds), m_report(std::move(report)) {
    m_watcher.begin = [this](std::function<Image()> image, std::function<double()> fraction,
                             std::function<std::uint64_t()> rays) {
        begin(std::move(image), std::move(fraction), std::move(rays));
    };
    m_watcher.end = [this] { end(); };
}

PeriodicReport::~PeriodicReport() { end(); }

void PeriodicReport::begin(std::function<Image()> image, std::function<double()> fraction,
                           std::function<std::uint64_t()> rays) {
    end(); // a watcher serves one render at a time
    m_image = std::move(image);
    m_fraction = std::move(fraction);
    m_rays = std::move(rays);
    m_start = std::chrono::steady_clock::now();
    m_running = true;
    m_thread = std::thread([this] {
        std::unique_lock<std::mutex> lk(m_mutex);
        while (!m_wake.wait_for(lk, m_interval, [this] { return !m_running; })) {
            lk.unlock();
            reportNow();
            lk.lock();
        }
    });
}

void PeriodicReport::end() {
    {
        std::lock_guard<std::mutex> lk(m_mutex);
        if (!m_running) return;
        m_running = false;
    }
    m_wake.notify_all();
    if (m_thread.joinable()) m_thread.join();
    reportNow(); // where the passes ended
    m_image = nullptr;
}

void PeriodicReport::reportNow() {
    if (!m_image || !m_report) return;
    Progress p;
    p.fraction = m_fraction ? m_fraction() : 0.0;
    p.rays = m_rays ? m_rays() : 0;
    p.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    m_report(m_image(), p);
}

} // namespace rayproc
