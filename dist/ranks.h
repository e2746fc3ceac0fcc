// The ranks of one octrace run (docs/DISTRIBUTED.md). Under a launcher (mpirun, srun) they are
// the processes of MPI_COMM_WORLD, and each takes a share of the rows, dealt in blocks (RowDeal):
// ray rows for trace and certify, image rows for render and validate. Otherwise there is one rank,
// this process, and every collective call below returns at once (a build without MPI is that case).
// Rank 0 writes the outputs and prints; RanksSession quiets the others.
//
// Failure, without a hang: every collective call starts with one agreement (an all-reduce of
// the lowest failed rank). A rank that fails (bad input only it read, out of memory) does not
// reach its next collective call; its CLI handler calls fail() instead, which meets the others'
// agreement. There every rank learns the lowest failed rank, that rank broadcasts its one line
// and exit status, the others throw RankFailed, and rank 0 prints the line naming the rank. A
// rank that dies (a signal) is the launcher's to report: mpirun ends the others (SIGTERM, which
// removes their temporaries, core/io/output_file.h).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace oct {

// Rows [begin, end).
struct RowRange {
    uint64_t begin = 0, end = 0;
    uint64_t count() const { return end - begin; }
    bool operator==(const RowRange& o) const { return begin == o.begin && end == o.end; }
};

// n rows dealt to `ranks` ranks in blocks of `block` rows, round robin: block b (rows
// [b * block, (b + 1) * block), the last one shorter) goes to rank b mod ranks. Contiguous halves
// would not balance: the rows of a ray file come set after set, and on the bunny the first half
// of 4M seeded rays took 1.5x the second's trace time (docs/PERFORMANCE.md, "Across ranks").
// A rank's rows are kept block after block, in row order (its "packed" rows).
struct RowDeal {
    uint64_t n = 0, block = 1;
    int ranks = 1;

    int ownerOf(uint64_t row) const { return int((row / block) % uint64_t(ranks)); }
    std::vector<RowRange> blocksOf(int rank) const;  // in row order
    uint64_t countOf(int rank) const;                // its rows
};

// A rank's rows of elemBytes bytes between their packed form (its blocks one after another) and
// their places in a whole array.
void packRows(const std::vector<RowRange>& blocks, const void* whole, void* packed,
              size_t elemBytes);
void unpackRows(const std::vector<RowRange>& blocks, const void* packed, void* whole,
                size_t elemBytes);

// The deal the ranks use for n rows: blocks of ceil(n / (16 ranks)) rows, at most 65,536 (at
// least 16 blocks a rank, each block large enough to read and send at once), 1 at least; one
// block of all rows for one rank.
// Throws std::invalid_argument for ranks < 1.
RowDeal dealRows(uint64_t n, int ranks);

// Thrown by a collective call on a rank that did not fail when another did: that rank's line is
// printed by rank 0 (line() holds it there, "" elsewhere); every rank exits with status().
class RankFailed : public std::runtime_error {
public:
    RankFailed(std::string line, int status)
        : std::runtime_error("another rank failed"), line_(std::move(line)), status_(status) {}
    const std::string& line() const { return line_; }
    int status() const { return status_; }

private:
    std::string line_;
    int status_;
};

class Ranks {
public:
    // The run's ranks: one until RanksSession starts MPI.
    static Ranks& world();

    int rank() const { return rank_; }
    int size() const { return size_; }
    int localRank() const { return localRank_; }  // on this node (the GPU it takes)
    bool root() const { return rank_ == 0; }
    bool distributed() const { return size_ > 1; }
    RowDeal deal(uint64_t n) const { return dealRows(n, size_); }
    std::vector<RowRange> blocksOf(uint64_t n) const { return deal(n).blocksOf(rank_); }

    // ---- Collective: every rank makes the same calls in the same order. Each throws RankFailed
    // when some rank failed, before it moves any data.
    void checkpoint();
    // Rows of elemBytes bytes dealt by deal(n): `mine` holds this rank's rows packed (block after
    // block); afterwards rank 0's `all` (n rows; ignored elsewhere, may be null) holds every
    // rank's, each in its place.
    void gatherRows(const void* mine, void* all, uint64_t n, size_t elemBytes);
    // The same, with every rank's `all` (n rows) holding every rank's rows afterwards.
    void allgatherRows(const void* mine, void* all, uint64_t n, size_t elemBytes);
    // Merges `bytes` bytes in place from every rank by bitwise or: each byte set by at most one
    // rank, zero on the others (the arrays certify's ranks fill row by row, validation/).
    void combineOwned(void* data, uint64_t bytes);
    // The largest of the ranks' values (the slowest rank's seconds), on every rank.
    double maxOver(double v);
    // The sum and the least of the ranks' values, on every rank.
    uint64_t sumOver(uint64_t v);
    uint64_t minOver(uint64_t v);

    // The CLI's handler on a rank that failed, with its one line ("octrace: error: ...") and exit
    // status: meets the others' agreement and returns the status every rank exits with; rank 0
    // prints the line of the lowest failed rank, named ("octrace: rank 2 of 3: error: ...").
    int fail(const std::string& line, int status);

private:
    friend class RanksSession;
    int rank_ = 0, size_ = 1, localRank_ = 0;
    // The agreement: the lowest failed rank (size_ when none), after this rank's `failed`. When
    // one failed, its line and status are broadcast to every rank.
    int agree(bool failed, std::string& line, int& status);
};

// The one place MPI starts and ends: MPI_Init when a launcher placed the process as one of
// several (core/system/launcher.h) and the build has MPI, MPI_Finalize when it goes. On ranks
// other than 0 standard output and error go to /dev/null (OCT_RANKS_OUTPUT=all keeps them, for
// debugging a cluster run). Throws std::runtime_error when the launcher placed the process but
// MPI cannot start, starts another number of processes than the launcher's, or this build has
// no MPI (the run would be K copies of one process).
class RanksSession {
public:
    RanksSession(int& argc, char**& argv);
    ~RanksSession();
    RanksSession(const RanksSession&) = delete;
    RanksSession& operator=(const RanksSession&) = delete;

private:
    bool started_ = false;
};

// True when this build runs across MPI ranks (OCT_MPI).
bool builtWithMpi();

}  // namespace oct
