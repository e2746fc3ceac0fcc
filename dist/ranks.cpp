#include "dist/ranks.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "core/system/launcher.h"

#if defined(OCT_HAVE_MPI)
#include <mpi.h>
#endif

namespace oct {

RowDeal dealRows(uint64_t n, int ranks) {
    if (ranks < 1) throw std::invalid_argument("dealRows: " + std::to_string(ranks) + " ranks");
    constexpr uint64_t kLargestBlock = 65536, kBlocksPerRank = 16;
    const uint64_t k = uint64_t(ranks) * kBlocksPerRank;
    RowDeal d;
    d.n = n;
    d.ranks = ranks;
    // One rank: one block of every row.
    d.block = ranks == 1 ? std::max<uint64_t>(1, n)
                         : std::max<uint64_t>(1, std::min(kLargestBlock, (n + k - 1) / k));
    return d;
}

std::vector<RowRange> RowDeal::blocksOf(int rank) const {
    if (rank < 0 || rank >= ranks)
        throw std::invalid_argument("RowDeal: rank " + std::to_string(rank) + " of " +
                                    std::to_string(ranks));
    std::vector<RowRange> out;
    const uint64_t step = block * uint64_t(ranks);
    for (uint64_t b = uint64_t(rank) * block; b < n; b += step)
        out.push_back({b, std::min(n, b + block)});
    return out;
}

uint64_t RowDeal::countOf(int rank) const {
    uint64_t c = 0;
    for (const RowRange& r : blocksOf(rank)) c += r.count();
    return c;
}

void packRows(const std::vector<RowRange>& blocks, const void* whole, void* packed,
              size_t elemBytes) {
    uint64_t at = 0;
    for (const RowRange& b : blocks) {
        std::memmove(static_cast<char*>(packed) + at * elemBytes,
                     static_cast<const char*>(whole) + b.begin * elemBytes, b.count() * elemBytes);
        at += b.count();
    }
}

void unpackRows(const std::vector<RowRange>& blocks, const void* packed, void* whole,
                size_t elemBytes) {
    uint64_t at = 0;
    for (const RowRange& b : blocks) {
        std::memmove(static_cast<char*>(whole) + b.begin * elemBytes,
                     static_cast<const char*>(packed) + at * elemBytes, b.count() * elemBytes);
        at += b.count();
    }
}

Ranks& Ranks::world() {
    static Ranks w;
    return w;
}

bool builtWithMpi() {
#if defined(OCT_HAVE_MPI)
    return true;
#else
    return false;
#endif
}

#if defined(OCT_HAVE_MPI)

namespace {

// MPI counts are ints: data moves in pieces of at most 1 GiB.
constexpr uint64_t kPieceBytes = uint64_t(1) << 30;

// "octrace: error: ..." -> "octrace: rank 2 of 3: error: ...".
std::string namedLine(const std::string& line, int rank, int size) {
    const std::string head = "octrace: ";
    const std::string who = "rank " + std::to_string(rank) + " of " + std::to_string(size) + ": ";
    if (line.compare(0, head.size(), head) == 0) return head + who + line.substr(head.size());
    return head + who + line;
}

}  // namespace

int Ranks::agree(bool failed, std::string& line, int& status) {
    if (size_ == 1) return failed ? 0 : 1;
    int lowest = failed ? rank_ : size_;
    MPI_Allreduce(MPI_IN_PLACE, &lowest, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (lowest == size_) return lowest;
    // The lowest failed rank's line and status, to every rank.
    int head[2] = {status, int(line.size())};
    MPI_Bcast(head, 2, MPI_INT, lowest, MPI_COMM_WORLD);
    std::vector<char> text(size_t(head[1]) + 1, '\0');
    if (rank_ == lowest) std::memcpy(text.data(), line.data(), line.size());
    MPI_Bcast(text.data(), head[1], MPI_CHAR, lowest, MPI_COMM_WORLD);
    status = head[0];
    line = namedLine(std::string(text.data(), size_t(head[1])), lowest, size_);
    return lowest;
}

void Ranks::checkpoint() {
    if (size_ == 1) return;
    std::string line;
    int status = 0;
    if (agree(false, line, status) != size_) throw RankFailed(root() ? line : "", status);
}

namespace {

// Calls op(at, m) on consecutive pieces of at most kPieceBytes of the `bytes` at `at`: MPI counts
// are ints.
template <class Op>
void inPieces(char* at, uint64_t bytes, Op op) {
    for (uint64_t left = bytes; left > 0;) {
        const int m = int(std::min(left, kPieceBytes));
        op(at, m);
        at += m;
        left -= uint64_t(m);
    }
}

// Rank 0 receives every other rank's blocks in turn, into their places in `whole`; a rank sends
// its blocks from its packed rows.
void gatherBlocks(int rank, int size, const RowDeal& d, const char* packed, char* whole,
                  size_t elemBytes) {
    if (rank == 0) {
        for (int r = 1; r < size; ++r)
            for (const RowRange& b : d.blocksOf(r))
                inPieces(whole + b.begin * elemBytes, b.count() * elemBytes, [r](char* at, int m) {
                    MPI_Recv(at, m, MPI_BYTE, r, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
                });
        return;
    }
    // Block by block, as rank 0 receives them (a message's pieces must match its receive's).
    uint64_t at = 0;
    for (const RowRange& b : d.blocksOf(rank)) {
        inPieces(const_cast<char*>(packed) + at * elemBytes, b.count() * elemBytes,
                 [](char* p, int m) { MPI_Send(p, m, MPI_BYTE, 0, 0, MPI_COMM_WORLD); });
        at += b.count();
    }
}

}  // namespace

void Ranks::gatherRows(const void* mine, void* all, uint64_t n, size_t elemBytes) {
    checkpoint();
    const RowDeal d = deal(n);
    if (root() && mine != all) unpackRows(d.blocksOf(0), mine, all, elemBytes);
    if (size_ == 1) return;
    gatherBlocks(rank_, size_, d, static_cast<const char*>(mine), static_cast<char*>(all),
                 elemBytes);
}

void Ranks::allgatherRows(const void* mine, void* all, uint64_t n, size_t elemBytes) {
    const RowDeal d = deal(n);
    unpackRows(d.blocksOf(rank_), mine, all, elemBytes);  // this rank's in place, then all
    checkpoint();
    if (size_ == 1) return;
    gatherBlocks(rank_, size_, d, static_cast<const char*>(mine), static_cast<char*>(all),
                 elemBytes);
    inPieces(static_cast<char*>(all), n * elemBytes,
             [](char* at, int m) { MPI_Bcast(at, m, MPI_BYTE, 0, MPI_COMM_WORLD); });
}

void Ranks::combineOwned(void* data, uint64_t bytes) {
    checkpoint();
    if (size_ == 1) return;
    inPieces(static_cast<char*>(data), bytes, [](char* at, int m) {
        MPI_Allreduce(MPI_IN_PLACE, at, m, MPI_BYTE, MPI_BOR, MPI_COMM_WORLD);
    });
}

double Ranks::maxOver(double v) {
    checkpoint();
    if (size_ > 1) MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    return v;
}

uint64_t Ranks::sumOver(uint64_t v) {
    checkpoint();
    if (size_ > 1) MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    return v;
}

uint64_t Ranks::minOver(uint64_t v) {
    checkpoint();
    if (size_ > 1) MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_UINT64_T, MPI_MIN, MPI_COMM_WORLD);
    return v;
}

RanksSession::RanksSession(int& argc, char**& argv) {
    const LauncherPlacement p = launcherPlacement();
    if (!p.launched || p.size == 1) return;  // one process (srun --pty bash, mpirun -np 1)
    int provided = 0;
    // One thread calls MPI (the main one); OpenMP's threads never do.
    if (MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
        throw std::runtime_error("MPI_Init failed (the launcher placed this process as rank " +
                                 std::to_string(p.rank) + " of " + std::to_string(p.size) + ")");
    started_ = true;
    Ranks& w = Ranks::world();
    MPI_Comm_rank(MPI_COMM_WORLD, &w.rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &w.size_);
    w.localRank_ = p.localRank;
    if (w.size_ != p.size) {  // a singleton under another MPI's launcher: K whole runs
        const int size = w.size_;
        w.rank_ = 0;
        w.size_ = 1;
        MPI_Finalize();
        started_ = false;
        throw std::runtime_error("launched as rank " + std::to_string(p.rank) + " of " +
                                 std::to_string(p.size) + ", but MPI started " +
                                 std::to_string(size) +
                                 " (a launcher of another MPI than this octrace's?): run it "
                                 "with the mpirun of the MPI it was built with");
    }
    const char* keep = std::getenv("OCT_RANKS_OUTPUT");
    if (w.rank_ != 0 && !(keep && std::strcmp(keep, "all") == 0)) {
        std::fflush(stdout);
        std::fflush(stderr);
        // Best effort: a rank that cannot open /dev/null prints as rank 0 does.
        if (!std::freopen("/dev/null", "w", stdout)) std::clearerr(stdout);
        if (!std::freopen("/dev/null", "w", stderr)) std::clearerr(stderr);
    }
}

RanksSession::~RanksSession() {
    if (started_) MPI_Finalize();
}

#else  // no MPI: one rank

int Ranks::agree(bool failed, std::string&, int&) { return failed ? 0 : 1; }
void Ranks::checkpoint() {}
void Ranks::gatherRows(const void* mine, void* all, uint64_t n, size_t elemBytes) {
    if (mine != all) std::memmove(all, mine, n * elemBytes);  // one rank: its rows are all
}
void Ranks::allgatherRows(const void* mine, void* all, uint64_t n, size_t elemBytes) {
    if (mine != all) std::memmove(all, mine, n * elemBytes);  // one rank: its rows are all
}
void Ranks::combineOwned(void*, uint64_t) {}
double Ranks::maxOver(double v) { return v; }
uint64_t Ranks::sumOver(uint64_t v) { return v; }
uint64_t Ranks::minOver(uint64_t v) { return v; }

RanksSession::RanksSession(int&, char**&) {
    const LauncherPlacement p = launcherPlacement();
    if (p.launched && p.size > 1)
        throw std::runtime_error(
            "launched as rank " + std::to_string(p.rank) + " of " + std::to_string(p.size) +
            ", but this octrace was built without MPI (each rank would do the whole run): "
            "install libopenmpi-dev and openmpi-bin and rebuild (scripts/setup), or run one "
            "process");
}

RanksSession::~RanksSession() {}

#endif

int Ranks::fail(const std::string& line, int status) {
    if (size_ == 1) {
        std::fprintf(stderr, "%s\n", line.c_str());
        return status;
    }
    std::string shared = line;
    int code = status;
    agree(true, shared, code);
    if (root()) std::fprintf(stderr, "%s\n", shared.c_str());
    return code;
}

}  // namespace oct
