// Where a render's wall time goes, phase by phase (--stats "phases", --stats-json "phases"):
// scene load, BVH build, light set, photon passes, photon map builds, the cache prepass, render
// passes, film resolve, image write. Each phase says how it runs: on one thread (serial), in
// parallel library code (TBB loops, Embree's builder: no busy figure), or on the ray
// processor's workers, whose stage timers give their busy fraction:
//   busy = thread-seconds inside stage timers / (wall x threads).
// The serial fraction of a render is the wall time of its serial phases over the whole.
// Phases are timed by the thread that drives the render, between processor runs: nothing here
// is on the per-ray path.
#pragma once

#include "core/named_loop.h"

#include <chrono>
#include <string>
#include <vector>

namespace rayproc {

class Stats;

enum class PhaseKind {
    Serial,   // one thread
    Parallel, // TBB loops or Embree's builder; no stage timers, so no busy figure
    Workers,  // RayProcessor::run: the workers' stage timers measure how busy they were
};
const char* phaseKindName(PhaseKind k);

struct PhaseStats {
    std::string name; // snake_case, stable: the JSON's and the scaling script's key
    PhaseKind kind = PhaseKind::Serial;
    double seconds = 0;     // wall
    double busySeconds = 0; // Workers: thread-seconds in stage timers
    int threads = 1;        // Workers: the processor's threads
    int count = 0;          // how many times the phase ran (rounds, levels, passes)
    // Workers only; negative otherwise.
    double busyFraction() const;
};

// The phases in the order they first ran; a phase entered again adds to its entry. Installed
// as a thread's LoopLog, it records that thread's named loops as Parallel phases.
class PhaseLog : public LoopLog {
public:
    void loopTimed(const char* name, double seconds) override {
        add(name, PhaseKind::Parallel, seconds);
    }
    void add(const std::string& name, PhaseKind kind, double seconds, double busySeconds = 0,
             int threads = 1);
    const std::vector<PhaseStats>& phases() const { return m_phases; }
    // Every phase's seconds so far: what a timer around nested timers subtracts.
    double recordedSeconds() const { return m_recorded; }

private:
    std::vector<PhaseStats> m_phases;
    double m_recorded = 0;
};

// Times a scope as one entry of a phase, less the time nested timers recorded meanwhile (so
// phases never count a second twice and add up to the wall time they cover). A null log
// records nothing (serve, bench).
class PhaseTimer {
public:
    PhaseTimer(PhaseLog* log, std::string name, PhaseKind kind = PhaseKind::Serial);
    ~PhaseTimer() { stop(); }
    PhaseTimer(const PhaseTimer&) = delete;
    PhaseTimer& operator=(const PhaseTimer&) = delete;
    void stop(); // records now; later calls do nothing

private:
    PhaseLog* m_log;
    std::string m_name;
    PhaseKind m_kind;
    double m_nestedBefore = 0;
    std::chrono::steady_clock::time_point m_start;
};

// The seconds of every stage timer in `stats` (all threads).
double stageSeconds(const Stats& stats);

// Runs `run` (one RayProcessor::run) as an entry of a Workers phase: its wall time, and the
// stage thread-seconds `stats` gained meanwhile.
template <typename Run>
void timeWorkers(PhaseLog* log, const std::string& name, const Stats& stats, int threads,
                 Run&& run) {
    if (!log) {
        run();
        return;
    }
    const double busyBefore = stageSeconds(stats);
    const auto start = std::chrono::steady_clock::now();
    run();
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    log->add(name, PhaseKind::Workers, wall, stageSeconds(stats) - busyBefore, threads);
}

// Summary figures of a list of phases (RenderStats::toTable / toJson).
struct PhaseSummary {
    double phaseSeconds = 0;   // the phases' seconds added up
    double serialSeconds = 0;  // of Serial phases
    double workersSeconds = 0; // of Workers phases (wall)
    double workersBusy = 0;    // busy thread-seconds / (wall x threads) over Workers phases
    // Against the whole command's wall time (processSeconds, or the phases' sum without it):
    double totalSeconds = 0;   // that wall time
    double otherSeconds = 0;   // what no phase timed (counted as serial)
    double serialFraction = 0; // (serial phases + other) / total
};
PhaseSummary summarizePhases(const std::vector<PhaseStats>& phases, double processSeconds = 0);

} // namespace rayproc
