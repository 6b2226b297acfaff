#include "engine/phases.h"

#include "engine/stats.h"

#include <algorithm>
#include <utility>

namespace rayproc {

const char* phaseKindName(PhaseKind k) {
    switch (k) {
    case PhaseKind::Serial: return "serial";
    case PhaseKind::Parallel: return "parallel";
    case PhaseKind::Workers: return "workers";
    }
    return "?";
}

double PhaseStats::busyFraction() const {
    if (kind != PhaseKind::Workers || seconds <= 0 || threads <= 0) return -1;
    return busySeconds / (seconds * threads);
}

void PhaseLog::add(const std::string& name, PhaseKind kind, double seconds, double busySeconds,
                   int threads) {
    seconds = std::max(0.0, seconds);
    m_recorded += seconds;
    auto it = std::find_if(m_phases.begin(), m_phases.end(),
                           [&](const PhaseStats& p) { return p.name == name; });
    if (it == m_phases.end()) {
        m_phases.push_back({name, kind, 0, 0, threads, 0});
        it = m_phases.end() - 1;
    }
    it->seconds += seconds;
    it->busySeconds += busySeconds;
    it->threads = std::max(it->threads, threads);
    ++it->count;
}

PhaseTimer::PhaseTimer(PhaseLog* log, std::string name, PhaseKind kind)
    : m_log(log), m_name(std::move(name)), m_kind(kind),
      m_nestedBefore(log ? log->recordedSeconds() : 0), m_start(std::chrono::steady_clock::now()) {}

void PhaseTimer::stop() {
    if (!m_log) return;
    double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    double nested = m_log->recordedSeconds() - m_nestedBefore;
    m_log->add(m_name, m_kind, wall - nested);
    m_log = nullptr;
}

double stageSeconds(const Stats& stats) {
    double s = 0;
    for (const StageCounters& c : stats.merged().stages) s += c.seconds;
    return s;
}

PhaseSummary summarizePhases(const std::vector<PhaseStats>& phases, double processSeconds) {
    PhaseSummary s;
    double capacity = 0, busy = 0;
    for (const PhaseStats& p : phases) {
        s.phaseSeconds += p.seconds;
        if (p.kind == PhaseKind::Serial) s.serialSeconds += p.seconds;
        if (p.kind == PhaseKind::Workers) {
            s.workersSeconds += p.seconds;
            capacity += p.seconds * p.threads;
            busy += p.busySeconds;
        }
    }
    s.workersBusy = capacity > 0 ? busy / capacity : 0;
    s.totalSeconds = processSeconds > 0 ? processSeconds : s.phaseSeconds;
    s.otherSeconds = std::max(0.0, s.totalSeconds - s.phaseSeconds);
    s.serialFraction =
        s.totalSeconds > 0 ? (s.serialSeconds + s.otherSeconds) / s.totalSeconds : 0.0;
    return s;
}

} // namespace rayproc
