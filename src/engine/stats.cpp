#include "engine/stats.h"

#include <nlohmann/json.hpp>
#include <sys/resource.h>

#include <cstdio>
#include <sstream>

namespace rayproc {

const char* stageName(StageId s) {
    switch (s) {
    case StageId::CameraEmit: return "camera";
    case StageId::Intersect: return "intersect";
    case StageId::Occlude: return "occlude";
    case StageId::Surface: return "surface";
    case StageId::Shadow: return "shadow";
    case StageId::Reflection: return "reflection";
    case StageId::Refraction: return "refraction";
    case StageId::Photon: return "photon";
    case StageId::Gather: return "gather";
    case StageId::Correction: return "correction";
    case StageId::Count: break;
    }
    return "?";
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
        t.photonsStored += s.photonsStored;
        t.cacheLookups += s.cacheLookups;
        t.cacheHits += s.cacheHits;
        t.causticLookups += s.causticLookups;
        t.globalLookups += s.globalLookups;
        if (t.contributions.size() < s.contributions.size()) t.contributions.resize(s.contributions.size());
        for (std::size_t c = 0; c < s.contributions.size(); ++c) t.contributions[c].merge(s.contributions[c]);
    }
    return t;
}

std::size_t peakResidentBytes() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return std::size_t(u.ru_maxrss) * 1024; // Linux reports KiB
}

std::string RenderStats::toTable() const {
    std::ostringstream o;
    char line[160];
    std::snprintf(line, sizeof line, "%-12s %14s %14s %10s %8s\n", "stage", "rays in", "rays out",
                  "seconds", "share");
    o << line;
    double total = 0;
    for (auto& s : totals.stages) total += s.seconds;
    for (int i = 0; i < kStageCount; ++i) {
        const StageCounters& s = totals.stages[i];
        std::snprintf(line, sizeof line, "%-12s %14llu %14llu %10.3f %7.1f%%\n",
                      stageName(StageId(i)), (unsigned long long)s.raysIn,
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
    nlohmann::json stages = nlohmann::json::object();
    for (int i = 0; i < kStageCount; ++i) {
        const StageCounters& s = totals.stages[i];
        stages[stageName(StageId(i))] = {{"rays", s.raysIn}, {"rays_out", s.raysOut},
                                         {"seconds", s.seconds}};
    }
    j["stages"] = stages;
    // "gi/photons_stored" -> j["gi"]["photons_stored"]
    for (auto& [name, value] : extras) {
        auto slash = name.find('/');
        if (slash == std::string::npos) j[name] = value;
        else j[name.substr(0, slash)][name.substr(slash + 1)] = value;
    }
    return j.dump(2);
}

} // namespace rayproc
