// The processes of one render (docs/distributed.md). Under an MPI launcher (mpirun, srun) every
// process is a rank of MPI's world and takes a share of the work: camera tiles, photon index
// ranges, the irradiance cache's prepass tiles. The collectives below put the shares together
// so that the result is bit-identical to one process's. Without a launcher, or in a build
// without MPI, the cluster is this process alone and every collective is the identity.
//
// Every rank must call the collectives in the same order: code that branches before one does so
// on values every rank agrees on (the scene, the options, agreeInterrupted()).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rayproc {

struct ThreadStats;

class Cluster {
public:
    // MPI_Init when launched by an MPI launcher (rayproc built with MPI); call first in main.
    static void start(int& argc, char**& argv);
    // MPI_Finalize after a clean end. Not after an error: abort() ends the whole job instead.
    static void finish();
    // Ends every rank of the job with `status` (MPI_Abort); a process alone just exits.
    [[noreturn]] static void abort(int status);
    static const Cluster& world();
    static bool builtWithMpi();

    int rank() const { return m_rank; }
    int size() const { return m_size; }
    bool root() const { return m_rank == 0; }
    bool distributed() const { return m_size > 1; }
    // "rank 2 of 4" (empty for a process alone): prefixes messages of non-root ranks.
    std::string name() const;

    // Element-wise sums over the ranks, left in `values` on rank 0 (other ranks' are unchanged).
    void sumToRoot(std::vector<double>& values) const;
    void sumToRoot(std::vector<std::uint64_t>& values) const;
    // Element-wise sums over the ranks, on every rank.
    void sumAll(std::vector<double>& values) const;
    void sumAll(std::vector<std::uint64_t>& values) const;
    // Bitwise OR of every rank's bits, on every rank.
    std::uint32_t orAll(std::uint32_t bits) const;
    // Every rank's bytes, concatenated in rank order, on every rank (any size: sent in chunks).
    std::vector<std::uint8_t> gatherAll(const std::vector<std::uint8_t>& mine) const;

    // Bytes this rank sent through the collectives so far (the communication volume).
    std::uint64_t bytesSent() const { return m_bytesSent; }

private:
    int m_rank = 0;
    int m_size = 1;
    mutable std::uint64_t m_bytesSent = 0;
};

// True on every rank when any rank's interrupt (Ctrl-C, SIGTERM, SIGHUP) was requested; then
// requested on every rank too, so all stop alike. A collective: call it where every rank does.
bool agreeInterrupted(const Cluster& cluster);

// Every rank's counters and stage seconds added up, on rank 0 (seconds become CPU-seconds of
// the job's ranks). A collective.
void sumToRoot(const Cluster& cluster, ThreadStats& stats);

// The share [first, last) of `count` items that `rank` of `size` takes: contiguous ranges in
// rank order, sizes differing by at most one.
void shareOf(std::uint64_t count, int rank, int size, std::uint64_t& first, std::uint64_t& last);

} // namespace rayproc
