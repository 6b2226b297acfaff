#include "engine/stats.h"

#include <nlohmann/json.hpp>
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace rayproc {

const std::vector<StageLabel>& enginePipeline() {
    static const std::vector<StageLabel> order{
        {StageId::CameraEmit, "camera"},     {StageId::Intersect, "intersect"},
        {StageId::Surface, "surface"},       {StageId::Reflection, "reflection"},
        {StageId::Refraction, "refraction"}, {StageId::Shadow, "shadow"},
        {StageId::Occlude, "occlude"}};
    return order;
}

ThreadStats Stats::merged() const {
    ThreadStats t;
    for (const ThreadStats& s : m_perThread) {
        for (int i = 0; i < kStageCount; ++i) {
            t.stages[i].raysIn += s.stages[i].raysIn;
            t.stages[i].raysOut += s.stages[i].raysOut;
            t.stages[i].seconds += s.stages[i].seconds;
        }
        t.raysTraced += s.raysTraced;
        t.samples += s.samples;
        t.invalidSamples += s.invalidSamples;
        t.clampedSamples += s.clampedSamples;
        t.batches += s.batches;
        for (int k = 0; k < kRayKindCount; ++k) {
            t.queues[k].batches += s.queues[k].batches;
            t.queues[k].rays += s.queues[k].rays;
        }
        for (int c = 0; c < ThreadStats::kModeCounterCount; ++c) t.modeCounters[c] += s.modeCounters[c];
        if (t.contributions.size() < s.contributions.size()) t.contributions.resize(s.contributions.size());
        for (std::size_t c = 0; c < s.contributions.size(); ++c) t.contributions[c].merge(s.contributions[c]);
    }
    return t;
}

void PipelineLayout::merge(const PipelineLayout& other) {
    for (const StageLayout& o : other.stages) {
        auto same = std::find_if(stages.begin(), stages.end(),
                                 [&](const StageLayout& s) { return s.name == o.name; });
        if (same == stages.end()) {
            stages.push_back(o);
            continue;
        }
        for (const QueueLayout& q : o.queues)
            if (std::none_of(same->queues.begin(), same->queues.end(),
                             [&](const QueueLayout& m) { return m.kind == q.kind; }))
                same->queues.push_back(q);
    }
}

void Stats::addPipeline(const PipelineLayout& layout) {
    for (PipelineLayout& p : m_pipelines)
        if (p.name == layout.name) {
            p.merge(layout);
            return;
        }
    m_pipelines.push_back(layout);
}

std::vector<PipelineRun> Stats::pipelineRuns(const ThreadStats& totals) const {
    std::vector<PipelineRun> runs;
    for (const PipelineLayout& p : m_pipelines) runs.push_back({p, totals.queues});
    return runs;
}

std::size_t peakResidentBytes() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return std::size_t(u.ru_maxrss) * 1024; // Linux reports KiB
}

namespace {

const PhaseStats* findPhase(const std::vector<PhaseStats>& phases, const char* name) {
    for (const PhaseStats& p : phases)
        if (p.name == name) return &p;
    return nullptr;
}

// The phases' table: wall seconds, share of the command's wall time, how each ran, and the
// workers' busy fraction where the stage timers measure it; then the summary.
void phaseTable(std::ostringstream& o, const RenderStats& r) {
    char line[200];
    const PhaseSummary sum = summarizePhases(r.phases, r.processSeconds);
    const double total = sum.totalSeconds;
    std::snprintf(line, sizeof line, "%-22s %10s %8s %-9s %6s %6s\n", "phase", "seconds", "share",
                  "runs on", "busy", "count");
    o << line;
    auto row = [&](const std::string& name, const char* kind, double seconds, double busy,
                   int count) {
        char busyText[16] = "-";
        if (busy >= 0) std::snprintf(busyText, sizeof busyText, "%.0f%%", 100.0 * busy);
        std::snprintf(line, sizeof line, "%-22s %10.3f %7.1f%% %-9s %6s %6d\n", name.c_str(),
                      seconds, total > 0 ? 100.0 * seconds / total : 0.0, kind, busyText, count);
        o << line;
    };
    for (const PhaseStats& p : r.phases)
        row(p.name, phaseKindName(p.kind), p.seconds, p.busyFraction(), p.count);
    if (r.processSeconds > 0) row("other", "serial", sum.otherSeconds, -1, 1);
    std::snprintf(line, sizeof line,
                  "process %.3f s wall, %d threads: serial fraction %.1f%% (serial phases and "
                  "other), workers busy %.1f%% of %.3f s in the ray processor\n",
                  total, r.threads, 100.0 * sum.serialFraction,
                  100.0 * sum.workersBusy, sum.workersSeconds);
    o << line;
}

// Each pipeline the render ran: a line of its shape (emitter -> queue -> intersect -> stages in
// order), then a row per stage and queue with the batches and rays that queue carried.
void pipelineTable(std::ostringstream& o, const std::vector<PipelineRun>& runs) {
    char line[200];
    for (const PipelineRun& run : runs) {
        o << "pipeline " << run.layout.name << ": " << pipelineShape(run.layout) << "\n";
        std::snprintf(line, sizeof line, "  %-16s %-16s %-10s %12s %14s\n", "stage", "queue",
                      "traced as", "batches", "rays");
        o << line;
        for (const StageLayout& stage : run.layout.stages)
            for (const QueueLayout& q : stage.queues) {
                const QueueCounters& c = run.queues[int(q.kind)];
                std::snprintf(line, sizeof line, "  %-16s %-16s %-10s %12llu %14llu\n",
                              stage.name.c_str(), q.name.c_str(),
                              q.occlusion ? "occlusion" : "closest", (unsigned long long)c.batches,
                              (unsigned long long)c.rays);
                o << line;
            }
    }
}

nlohmann::json pipelineJson(const PipelineRun& run) {
    nlohmann::json stages = nlohmann::json::array();
    for (const StageLayout& stage : run.layout.stages) {
        nlohmann::json queues = nlohmann::json::array();
        std::uint64_t batches = 0, rays = 0;
        for (const QueueLayout& q : stage.queues) {
            const QueueCounters& c = run.queues[int(q.kind)];
            queues.push_back({{"kind", q.name},
                              {"query", q.occlusion ? "occlusion" : "closest"},
                              {"batches", c.batches},
                              {"rays", c.rays}});
            batches += c.batches;
            rays += c.rays;
        }
        stages.push_back(
            {{"name", stage.name}, {"queues", queues}, {"batches", batches}, {"rays", rays}});
    }
    return {{"name", run.layout.name},
            {"emitter", run.layout.emitter},
            {"packet_width", run.layout.packetWidth},
            {"shape", pipelineShape(run.layout)},
            {"stages", stages}};
}

} // namespace

std::string pipelineShape(const PipelineLayout& p) {
    std::string s = p.emitter + " emitter -> queue -> intersect (" +
                    (p.packetWidth > 1 ? "packets of " + std::to_string(p.packetWidth)
                                       : std::string("single rays")) +
                    ")";
    for (const StageLayout& stage : p.stages) {
        s += " -> " + stage.name + " [";
        for (std::size_t i = 0; i < stage.queues.size(); ++i) {
            if (i > 0) s += ", ";
            s += stage.queues[i].name;
            if (stage.queues[i].occlusion) s += ": occlusion";
        }
        s += "]";
    }
    return s;
}

std::string RenderStats::toTable() const {
    std::ostringstream o;
    char line[160];
    std::snprintf(line, sizeof line, "%-12s %14s %14s %10s %8s\n", "stage", "rays in", "rays out",
                  "seconds", "share");
    o << line;
    double total = 0;
    for (auto& s : totals.stages) total += s.seconds;
    for (const StageLabel& stage : stages()) {
        const StageCounters& s = totals.stages[int(stage.id)];
        std::snprintf(line, sizeof line, "%-12s %14llu %14llu %10.3f %7.1f%%\n",
                      stage.name, (unsigned long long)s.raysIn,
                      (unsigned long long)s.raysOut, s.seconds,
                      total > 0 ? 100.0 * s.seconds / total : 0.0);
        o << line;
    }
    std::snprintf(line, sizeof line,
                  "rays traced %llu in %.3f s wall: %.2f Mrays/s; samples %llu; invalid samples "
                  "%llu; clamped %llu; peak memory %.1f MiB\n",
                  (unsigned long long)totals.raysTraced, wallSeconds,
                  wallSeconds > 0 ? totals.raysTraced / wallSeconds * 1e-6 : 0.0,
                  (unsigned long long)totals.samples, (unsigned long long)totals.invalidSamples,
                  (unsigned long long)totals.clampedSamples, peakMemoryBytes / 1048576.0);
    o << line;
    // The film: the stages add to it; it folds each pass in between passes (in parallel) and
    // resolves the image at the end (on one thread).
    const PhaseStats* commits = findPhase(phases, "film_commit");
    const PhaseStats* resolve = findPhase(phases, "film_resolve");
    if (commits || resolve) {
        std::snprintf(line, sizeof line,
                      "%-12s pass commits %.3f s (parallel), resolve %.3f s (one thread), wall\n",
                      "film",
                      commits ? commits->seconds : 0.0, resolve ? resolve->seconds : 0.0);
        o << line;
    }
    pipelineTable(o, pipelines);
    if (!phases.empty()) phaseTable(o, *this);
    for (auto& [name, value] : extras) {
        std::snprintf(line, sizeof line, "%-40s %.6g\n", name.c_str(), value);
        o << line;
    }
    return o.str();
}

std::string RenderStats::toJson() const {
    nlohmann::json j;
    j["wall_seconds"] = wallSeconds;
    j["rays"] = totals.raysTraced;
    j["rays_per_second"] = wallSeconds > 0 ? totals.raysTraced / wallSeconds : 0.0;
    j["samples"] = totals.samples;
    j["invalid_samples"] = totals.invalidSamples;
    j["clamped_samples"] = totals.clampedSamples;
    j["peak_memory_bytes"] = peakMemoryBytes;
    j["batches_allocated"] = batchesAllocated;
    j["pixels_without_samples"] = pixelsWithoutSamples;
    nlohmann::json stageTable = nlohmann::json::object();
    nlohmann::json order = nlohmann::json::array();
    for (const StageLabel& stage : stages()) {
        const StageCounters& s = totals.stages[int(stage.id)];
        stageTable[stage.name] = {{"rays", s.raysIn}, {"rays_out", s.raysOut},
                                  {"seconds", s.seconds}};
        order.push_back(stage.name);
    }
    j["stages"] = stageTable;
    j["pipeline"] = order;
    nlohmann::json runs = nlohmann::json::array();
    for (const PipelineRun& run : pipelines) runs.push_back(pipelineJson(run));
    j["pipelines"] = runs;
    if (!phases.empty()) {
        const PhaseSummary sum = summarizePhases(phases, processSeconds);
        nlohmann::json list = nlohmann::json::array();
        auto add = [&](const std::string& name, PhaseKind kind, double seconds, double busy,
                       int threads, int count) {
            nlohmann::json p = {{"name", name},     {"kind", phaseKindName(kind)},
                                {"seconds", seconds}, {"threads", threads},
                                {"count", count}};
            p["busy_fraction"] = busy >= 0 ? nlohmann::json(busy) : nlohmann::json(nullptr);
            list.push_back(p);
        };
        for (const PhaseStats& p : phases)
            add(p.name, p.kind, p.seconds, p.busyFraction(), p.threads, p.count);
        add("other", PhaseKind::Serial, sum.otherSeconds, -1, 1, 1);
        j["phases"] = list;
        j["process_seconds"] = sum.totalSeconds;
        j["threads"] = threads;
        j["serial_fraction"] = sum.serialFraction;
        j["workers_busy_fraction"] = sum.workersBusy;
        j["workers_seconds"] = sum.workersSeconds;
    }
    // "gi/photons_stored" -> j["gi"]["photons_stored"]
    for (auto& [name, value] : extras) {
        auto slash = name.find('/');
        if (slash == std::string::npos) j[name] = value;
        else j[name.substr(0, slash)][name.substr(slash + 1)] = value;
    }
    return j.dump(2);
}

} // namespace rayproc
