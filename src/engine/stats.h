// Statistics as "Category/Counter": counted per thread without synchronisation, merged at the
// end of a render into one table (--stats) or JSON document (--stats-json).
#pragma once

#include "engine/phases.h"
#include "engine/ray_batch.h"

#include <tbb/enumerable_thread_specific.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace rayproc {

// Every named stage of the pipeline. Rays in / rays out / seconds are kept for each. The engine
// names its own; a mode's stages take the ids from kFirstModeStage on, named by the mode
// (gi: gi/gi_pipeline.h) in the render's pipeline (RenderStats::pipeline).
enum class StageId {
    CameraEmit, // camera emitter: primary rays generated
    Intersect,  // rtcIntersect over radiance rays
    Occlude,    // rtcOccluded over shadow rays
    Surface,    // hit resolution, emission, routing by material
    Shadow,     // light sampling (rays out) and occlusion results (rays in)
    Reflection,
    Refraction,
};
constexpr int kFirstModeStage = 7;
constexpr int kModeStageCount = 3; // a mode's stages at most
constexpr int kStageCount = kFirstModeStage + kModeStageCount;
// A mode's i-th own stage.
constexpr StageId modeStage(int i) { return StageId(kFirstModeStage + i); }

// A stage as --stats names it.
struct StageLabel {
    StageId id;
    const char* name;
};
// The engine's stages as the pipeline runs them (--stats prints them so): the camera emitter,
// traversal, then the retrace stages (surface first, then what it routes to); a mode's own
// stages follow them, the film comes last.
const std::vector<StageLabel>& enginePipeline();

struct StageCounters {
    std::uint64_t raysIn = 0;
    std::uint64_t raysOut = 0;
    double seconds = 0;
};

// What one queue (the rays of one kind) carried to its stage: batches and rays.
struct QueueCounters {
    std::uint64_t batches = 0;
    std::uint64_t rays = 0;
};

// A pipeline's shape (engine/pipeline.h): its emitter, then its stages in order, each with the
// queues that feed it.
struct QueueLayout {
    RayKind kind;
    std::string name;
    bool occlusion = false; // traced as occlusion rays
};
struct StageLayout {
    std::string name;
    std::vector<QueueLayout> queues;
};
struct PipelineLayout {
    std::string name;    // "render", "photons", "cache prepass", ...
    std::string emitter; // "camera", "photon", "record"
    int packetWidth = 0;
    std::vector<StageLayout> stages;
    // Adds the stages and queues of `other` (the same pipeline built again with more stages)
    // that this one lacks.
    void merge(const PipelineLayout& other);
};

// Path mode's contributions to the film by how they were sampled (--stats, "path/..."): their
// count, the sum and the sum of squares of their luminance, and the largest. The sums of squares
// say which strategy's samples the noise comes from: a firefly is one huge square.
struct ContributionMoments {
    std::uint64_t count = 0;
    double sum = 0, sumSquares = 0, largest = 0;
    void add(double v) {
        ++count;
        sum += v;
        sumSquares += v * v;
        largest = v > largest ? v : largest;
    }
    void merge(const ContributionMoments& o) {
        count += o.count;
        sum += o.sum;
        sumSquares += o.sumSquares;
        largest = o.largest > largest ? o.largest : largest;
    }
};

// The categories: 0, emission or sky reached from the camera through delta lobes only; for
// light k (k = the number of lights: the sky), 1 + 2k its light samples and 2 + 2k BSDF rays
// that found it.
inline std::size_t contributionOfLightSample(std::size_t k) { return 1 + 2 * k; }
inline std::size_t contributionOfBsdfHit(std::size_t k) { return 2 + 2 * k; }

struct ThreadStats {
    std::array<StageCounters, kStageCount> stages{};
    std::uint64_t raysTraced = 0;     // every ray handed to Embree
    std::uint64_t samples = 0;        // camera samples emitted
    std::uint64_t invalidSamples = 0; // NaN/Inf contributions discarded before the film
    std::uint64_t clampedSamples = 0; // contributions beyond the film's fixed-point range
    std::uint64_t batches = 0;
    std::array<QueueCounters, kRayKindCount> queues{}; // by ray kind
    // A mode's own counts, indexed by the mode's names for them (gi: gi/gi_pipeline.h).
    static constexpr int kModeCounterCount = 6;
    std::array<std::uint64_t, kModeCounterCount> modeCounters{};
    // path mode (and gi's correction paths): by category, see contributionOfLightSample
    std::vector<ContributionMoments> contributions;
    void addContribution(std::size_t category, double luminance) {
        if (contributions.size() <= category) contributions.resize(category + 1);
        contributions[category].add(luminance);
    }
};

// One line: "camera emitter -> queue -> intersect (packets of 16) -> surface [camera,
// reflection] -> shadow [shadow: occlusion]".
std::string pipelineShape(const PipelineLayout& layout);

// A pipeline as it ran: its shape and what its queues carried over all its runs.
struct PipelineRun {
    PipelineLayout layout;
    std::array<QueueCounters, kRayKindCount> queues{};
};

struct RenderStats {
    ThreadStats totals;
    double wallSeconds = 0;
    std::size_t peakMemoryBytes = 0;
    std::size_t batchesAllocated = 0;
    std::size_t pixelsWithoutSamples = 0;
    // Mode-specific figures ("gi/photons stored", ...), printed after the table and written
    // to the JSON as an object under their category.
    std::vector<std::pair<std::string, double>> extras;
    // The stages of the render's pipeline in order, named (--stats' rows, the JSON's "stages"
    // and "pipeline"); empty: the engine's (enginePipeline()).
    std::vector<StageLabel> pipeline;
    // Every pipeline the render ran, in the order they ran (gi: photons, the cache's prepass
    // and refinement, then the render), with their queues' batches and rays (--stats).
    std::vector<PipelineRun> pipelines;
    // Where the whole command's time went (engine/phases.h), filled by the render command:
    // empty for renders run by serve and bench. processSeconds is the command's wall time
    // from before the scene load to after the image write; threads the processor's.
    std::vector<PhaseStats> phases;
    double processSeconds = 0;
    int threads = 0;
    const std::vector<StageLabel>& stages() const {
        return pipeline.empty() ? enginePipeline() : pipeline;
    }
    std::string toTable() const;
    std::string toJson() const;
};

class Stats {
public:
    ThreadStats& local() { return m_perThread.local(); }
    ThreadStats merged() const;
    // The pipelines counted here (engine/pipeline.h records its own on its first run); one
    // of a name built again is merged into the first.
    void addPipeline(const PipelineLayout& layout);
    const std::vector<PipelineLayout>& pipelines() const { return m_pipelines; }
    // The pipelines with their queues' counts from `totals` (merged, and summed over ranks).
    std::vector<PipelineRun> pipelineRuns(const ThreadStats& totals) const;

private:
    tbb::enumerable_thread_specific<ThreadStats> m_perThread;
    std::vector<PipelineLayout> m_pipelines;
};

// Adds the seconds of a scope to a stage's counter.
class StageTimer {
public:
    StageTimer(ThreadStats& s, StageId id)
        : m_counters(s.stages[int(id)]), m_start(std::chrono::steady_clock::now()) {}
    ~StageTimer() {
        m_counters.seconds +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    }

private:
    StageCounters& m_counters;
    std::chrono::steady_clock::time_point m_start;
};

std::size_t peakResidentBytes();

} // namespace rayproc
