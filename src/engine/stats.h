// Statistics as "Category/Counter": counted per thread without synchronisation, merged at the
// end of a render into one table (--stats) or JSON document (--stats-json).
#pragma once

#include "engine/phases.h"

#include <tbb/enumerable_thread_specific.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace rayproc {

// Every named stage of the pipeline. Rays in / rays out / seconds are kept for each.
enum class StageId {
    CameraEmit, // camera emitter: primary rays generated
    Intersect,  // rtcIntersect over radiance rays
    Occlude,    // rtcOccluded over shadow rays
    Surface,    // hit resolution, emission, routing by material
    Shadow,     // light sampling (rays out) and occlusion results (rays in)
    Reflection,
    Refraction,
    Photon,     // gi: photon emission and scattering (rays out), photon hits (rays in)
    Gather,     // gi: final-gather rays spawned (rays out) and resolved (rays in)
    Correction, // gi: the map's correction rays spawned (rays out) and resolved (rays in)
    Count
};
constexpr int kStageCount = int(StageId::Count);
const char* stageName(StageId s);
// The stages as the pipeline runs them (--stats prints them so): the emitters, traversal, the
// retrace stages (surface first, then what it routes to), then gi's; the film comes last.
const std::array<StageId, kStageCount>& pipelineOrder();

struct StageCounters {
    std::uint64_t raysIn = 0;
    std::uint64_t raysOut = 0;
    double seconds = 0;
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
    // gi mode
    std::uint64_t photonsStored = 0;
    std::uint64_t cacheLookups = 0, cacheHits = 0;
    std::uint64_t causticLookups = 0, globalLookups = 0;
    // path mode (and gi's correction paths): by category, see contributionOfLightSample
    std::vector<ContributionMoments> contributions;
    void addContribution(std::size_t category, double luminance) {
        if (contributions.size() <= category) contributions.resize(category + 1);
        contributions[category].add(luminance);
    }
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
    // Where the whole command's time went (engine/phases.h), filled by the render command:
    // empty for renders run by serve and bench. processSeconds is the command's wall time
    // from before the scene load to after the image write; threads the processor's.
    std::vector<PhaseStats> phases;
    double processSeconds = 0;
    int threads = 0;
    std::string toTable() const;
    std::string toJson() const;
};

class Stats {
public:
    ThreadStats& local() { return m_perThread.local(); }
    ThreadStats merged() const;

private:
    tbb::enumerable_thread_specific<ThreadStats> m_perThread;
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
