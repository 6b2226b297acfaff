#include "cluster/cluster.h"

#include "engine/cancel.h"
#include "engine/stats.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#if RAYPROC_HAVE_MPI
#include <mpi.h>
#endif

namespace rayproc {

namespace {

Cluster g_world;
[[maybe_unused]] bool g_mpiStarted = false;

#if RAYPROC_HAVE_MPI
// MPI counts are ints: large buffers go in chunks of at most this many elements.
constexpr std::size_t kChunkBytes = std::size_t(1) << 30;

// Launchers set these in each rank's environment; without one, rayproc runs as one process
// and does not start MPI (a singleton MPI_Init would only add start-up time).
bool launchedByMpi() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"})
        if (std::getenv(v)) return true;
    return false;
}

void check(int rc, const char* what) {
    if (rc != MPI_SUCCESS) throw std::runtime_error(std::string("MPI ") + what + " failed");
}

template <typename T>
void reduceChunks(std::vector<T>& values, MPI_Datatype type, bool all, std::uint64_t& sent) {
    std::size_t per = kChunkBytes / sizeof(T);
    for (std::size_t at = 0; at < values.size(); at += per) {
        int n = int(std::min(per, values.size() - at));
        if (all)
            check(MPI_Allreduce(MPI_IN_PLACE, values.data() + at, n, type, MPI_SUM, MPI_COMM_WORLD),
                  "Allreduce");
        else if (g_world.root())
            check(MPI_Reduce(MPI_IN_PLACE, values.data() + at, n, type, MPI_SUM, 0, MPI_COMM_WORLD),
                  "Reduce");
        else
            check(MPI_Reduce(values.data() + at, nullptr, n, type, MPI_SUM, 0, MPI_COMM_WORLD),
                  "Reduce");
        sent += std::uint64_t(n) * sizeof(T);
    }
}
#endif

} // namespace

void Cluster::start(int& argc, char**& argv) {
#if RAYPROC_HAVE_MPI
    if (!launchedByMpi()) return;
    int provided = 0;
    // Only the main thread calls MPI; TBB's workers never do.
    if (MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
        std::fprintf(stderr, "rayproc: MPI_Init failed; running as one process\n");
        return;
    }
    g_mpiStarted = true;
    MPI_Comm_rank(MPI_COMM_WORLD, &g_world.m_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &g_world.m_size);
#else
    (void)argc;
    (void)argv;
#endif
}

void Cluster::finish() {
#if RAYPROC_HAVE_MPI
    if (g_mpiStarted) MPI_Finalize();
    g_mpiStarted = false;
#endif
}

void Cluster::abort(int status) {
#if RAYPROC_HAVE_MPI
    if (g_mpiStarted && g_world.m_size > 1) MPI_Abort(MPI_COMM_WORLD, status);
#endif
    std::exit(status);
}

const Cluster& Cluster::world() { return g_world; }

bool Cluster::builtWithMpi() {
#if RAYPROC_HAVE_MPI
    return true;
#else
    return false;
#endif
}

std::string Cluster::name() const {
    if (m_size <= 1) return {};
    return "rank " + std::to_string(m_rank) + " of " + std::to_string(m_size);
}

void Cluster::sumToRoot(std::vector<double>& values) const {
#if RAYPROC_HAVE_MPI
    if (m_size > 1) reduceChunks(values, MPI_DOUBLE, false, m_bytesSent);
#else
    (void)values;
#endif
}

void Cluster::sumToRoot(std::vector<std::uint64_t>& values) const {
#if RAYPROC_HAVE_MPI
    if (m_size > 1) reduceChunks(values, MPI_UINT64_T, false, m_bytesSent);
#else
    (void)values;
#endif
}

void Cluster::sumAll(std::vector<double>& values) const {
#if RAYPROC_HAVE_MPI
    if (m_size > 1) reduceChunks(values, MPI_DOUBLE, true, m_bytesSent);
#else
    (void)values;
#endif
}

void Cluster::sumAll(std::vector<std::uint64_t>& values) const {
#if RAYPROC_HAVE_MPI
    if (m_size > 1) reduceChunks(values, MPI_UINT64_T, true, m_bytesSent);
#else
    (void)values;
#endif
}

std::uint32_t Cluster::orAll(std::uint32_t bits) const {
#if RAYPROC_HAVE_MPI
    if (m_size > 1) {
        check(MPI_Allreduce(MPI_IN_PLACE, &bits, 1, MPI_UINT32_T, MPI_BOR, MPI_COMM_WORLD),
              "Allreduce");
        m_bytesSent += sizeof bits;
    }
#endif
    return bits;
}

std::vector<std::uint8_t> Cluster::gatherAll(const std::vector<std::uint8_t>& mine) const {
#if RAYPROC_HAVE_MPI
    if (m_size > 1) {
        // Sizes first, then each rank's bytes broadcast from it in chunks.
        std::vector<std::uint64_t> sizes(std::size_t(m_size), 0);
        sizes[std::size_t(m_rank)] = mine.size();
        sumAll(sizes);
        std::uint64_t total = 0;
        for (auto s : sizes) total += s;
        std::vector<std::uint8_t> all(total);
        std::uint64_t offset = 0;
        for (int r = 0; r < m_size; ++r) {
            std::uint64_t n = sizes[std::size_t(r)];
            if (r == m_rank) std::copy(mine.begin(), mine.end(), all.begin() + std::ptrdiff_t(offset));
            for (std::uint64_t at = 0; at < n; at += kChunkBytes) {
                int count = int(std::min<std::uint64_t>(kChunkBytes, n - at));
                check(MPI_Bcast(all.data() + offset + at, count, MPI_BYTE, r, MPI_COMM_WORLD),
                      "Bcast");
                if (r == m_rank) m_bytesSent += std::uint64_t(count);
            }
            offset += n;
        }
        return all;
    }
#endif
    return mine;
}

bool agreeInterrupted(const Cluster& cluster) {
    std::uint32_t bits = cluster.orAll(interruptBits());
    adoptInterrupt(bits); // with the signal a rank received: rank 0 exits 143 for a SIGTERM
    return bits != 0;
}

// A new counter in ThreadStats must be added to the list below. The contributions by strategy
// (path mode's --stats breakdown) are not summed: rank 0 reports its own pixels' (its shares
// are of those).
static_assert(sizeof(ThreadStats) ==
              sizeof(StageCounters) * kStageCount +
                  (5 + ThreadStats::kModeCounterCount) * sizeof(std::uint64_t) +
                  sizeof(QueueCounters) * kRayKindCount +
                  sizeof(std::vector<ContributionMoments>));

void sumToRoot(const Cluster& cluster, ThreadStats& s) {
    if (!cluster.distributed()) return;
    std::vector<std::uint64_t> counts;
    std::vector<double> seconds;
    for (const StageCounters& c : s.stages) {
        counts.push_back(c.raysIn);
        counts.push_back(c.raysOut);
        seconds.push_back(c.seconds);
    }
    std::vector<std::uint64_t*> fields = {&s.raysTraced, &s.samples, &s.invalidSamples,
                                          &s.clampedSamples, &s.batches};
    for (std::uint64_t& c : s.modeCounters) fields.push_back(&c);
    for (QueueCounters& q : s.queues) {
        fields.push_back(&q.batches);
        fields.push_back(&q.rays);
    }
    for (std::uint64_t* f : fields) counts.push_back(*f);
    cluster.sumToRoot(counts);
    cluster.sumToRoot(seconds);
    if (!cluster.root()) return;
    std::size_t i = 0;
    for (std::size_t k = 0; k < s.stages.size(); ++k) {
        s.stages[k].raysIn = counts[i++];
        s.stages[k].raysOut = counts[i++];
        s.stages[k].seconds = seconds[k];
    }
    for (std::uint64_t* f : fields) *f = counts[i++];
}

void shareOf(std::uint64_t count, int rank, int size, std::uint64_t& first, std::uint64_t& last) {
    std::uint64_t n = std::uint64_t(std::max(size, 1));
    std::uint64_t r = std::uint64_t(std::clamp(rank, 0, int(n) - 1));
    first = count / n * r + std::min(r, count % n);
    last = first + count / n + (r < count % n ? 1 : 0);
}

} // namespace rayproc
