// dist/ranks.h in one process: how rows are split among ranks, the launcher's placement read from
// its environment, and the collective calls of a run of one rank (which move nothing).
#include "dist/ranks.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "core/system/launcher.h"

namespace oct {
namespace {

TEST(RowDeal, EveryRowHasOneOwnerAndEachRanksBlocksAreItsRowsInOrder) {
    for (uint64_t n : {0ull, 1ull, 2ull, 7ull, 512ull, 3001ull, 1000003ull, 40000000ull})
        for (int ranks : {1, 2, 3, 7, 64}) {
            const RowDeal d = dealRows(n, ranks);
            std::vector<int> owner(std::min<uint64_t>(n, 2000000), -1);
            uint64_t total = 0, smallest = UINT64_MAX, largest = 0;
            for (int r = 0; r < ranks; ++r) {
                uint64_t last = 0;
                for (const RowRange& b : d.blocksOf(r)) {
                    EXPECT_GE(b.begin, last);
                    EXPECT_LT(b.begin, b.end);
                    EXPECT_LE(b.count(), d.block);
                    last = b.end;
                    for (uint64_t i = b.begin; i < b.end && i < owner.size(); ++i) {
                        EXPECT_EQ(owner[i], -1) << "row " << i << " dealt twice";
                        owner[i] = r;
                        EXPECT_EQ(d.ownerOf(i), r);
                    }
                }
                const uint64_t c = d.countOf(r);
                total += c;
                smallest = std::min(smallest, c);
                largest = std::max(largest, c);
            }
            EXPECT_EQ(total, n) << n << " rows over " << ranks;
            for (size_t i = 0; i < owner.size(); ++i) ASSERT_GE(owner[i], 0) << "row " << i;
            // Round robin: the ranks' counts differ by at most a block.
            EXPECT_LE(largest - smallest, d.block) << n << " rows over " << ranks;
        }
}

TEST(RowDeal, BlocksAreASixteenthOfARanksShareUpTo65536Rows) {
    EXPECT_EQ(dealRows(3001, 3).block, 63u);  // ceil(3001 / 48)
    EXPECT_EQ(dealRows(10, 3).block, 1u);
    EXPECT_EQ(dealRows(0, 3).block, 1u);
    EXPECT_EQ(dealRows(4000000, 2).block, 65536u);
    EXPECT_EQ(dealRows(4000000, 1).block, 4000000u);  // one rank: one block
    const RowDeal d = dealRows(10, 3);
    EXPECT_EQ(d.blocksOf(0), (std::vector<RowRange>{{0, 1}, {3, 4}, {6, 7}, {9, 10}}));
    EXPECT_EQ(d.blocksOf(2), (std::vector<RowRange>{{2, 3}, {5, 6}, {8, 9}}));
    EXPECT_EQ(dealRows(2, 3).blocksOf(2), std::vector<RowRange>{});  // more ranks than rows
    EXPECT_THROW(d.blocksOf(3), std::invalid_argument);
    EXPECT_THROW(dealRows(10, 0), std::invalid_argument);
}

// Sets the launchers' variables for one test and clears them after.
class LauncherEnv : public ::testing::Test {
protected:
    const std::vector<std::string> names = {"OMPI_COMM_WORLD_RANK",
                                            "OMPI_COMM_WORLD_SIZE",
                                            "OMPI_COMM_WORLD_LOCAL_RANK",
                                            "PMI_RANK",
                                            "PMI_SIZE",
                                            "MPI_LOCALRANKID",
                                            "SLURM_PROCID",
                                            "SLURM_STEP_NUM_TASKS",
                                            "SLURM_LOCALID",
                                            "SLURM_NTASKS"};
    std::vector<std::pair<std::string, std::string>> saved;
    void SetUp() override {
        for (const std::string& n : names) {
            if (const char* v = std::getenv(n.c_str())) saved.push_back({n, v});
            unsetenv(n.c_str());
        }
    }
    void TearDown() override {
        for (const std::string& n : names) unsetenv(n.c_str());
        for (const auto& [n, v] : saved) setenv(n.c_str(), v.c_str(), 1);
    }
};

TEST_F(LauncherEnv, NoLauncherIsOneProcess) {
    const LauncherPlacement p = launcherPlacement();
    EXPECT_FALSE(p.launched);
    EXPECT_EQ(p.rank, 0);
    EXPECT_EQ(p.size, 1);
}

TEST_F(LauncherEnv, ReadsOpenMpiThenHydraThenSrun) {
    setenv("SLURM_PROCID", "5", 1);
    setenv("SLURM_STEP_NUM_TASKS", "8", 1);
    setenv("SLURM_LOCALID", "1", 1);
    LauncherPlacement p = launcherPlacement();
    EXPECT_TRUE(p.launched);
    EXPECT_EQ(p.rank, 5);
    EXPECT_EQ(p.size, 8);
    EXPECT_EQ(p.localRank, 1);
    setenv("OMPI_COMM_WORLD_RANK", "2", 1);
    setenv("OMPI_COMM_WORLD_SIZE", "3", 1);
    setenv("OMPI_COMM_WORLD_LOCAL_RANK", "0", 1);
    p = launcherPlacement();
    EXPECT_EQ(p.rank, 2);
    EXPECT_EQ(p.size, 3);
    EXPECT_EQ(p.localRank, 0);
}

TEST_F(LauncherEnv, ABatchScriptsTaskCountIsNoLaunch) {
    // sbatch's own shell: the job's task count, but no step of tasks this process is one of.
    setenv("SLURM_PROCID", "0", 1);
    setenv("SLURM_NTASKS", "16", 1);
    EXPECT_FALSE(launcherPlacement().launched);
}

TEST_F(LauncherEnv, NumbersOutOfRangeAreIgnored) {
    setenv("OMPI_COMM_WORLD_RANK", "3", 1);  // not below the size
    setenv("OMPI_COMM_WORLD_SIZE", "3", 1);
    EXPECT_FALSE(launcherPlacement().launched);
    setenv("OMPI_COMM_WORLD_RANK", "1x", 1);
    EXPECT_FALSE(launcherPlacement().launched);
    setenv("OMPI_COMM_WORLD_RANK", "1", 1);
    setenv("OMPI_COMM_WORLD_LOCAL_RANK", "-4", 1);  // a bad local rank: the node's first
    const LauncherPlacement p = launcherPlacement();
    EXPECT_TRUE(p.launched);
    EXPECT_EQ(p.localRank, 0);
}

// Without a launcher the world is this process: the collective calls leave data as it is, and a
// failure is this rank's line and status.
TEST(OneRank, CollectiveCallsKeepTheDataAndFailReturnsTheStatus) {
    Ranks& w = Ranks::world();
    ASSERT_EQ(w.size(), 1);
    EXPECT_TRUE(w.root());
    EXPECT_FALSE(w.distributed());
    EXPECT_EQ(w.blocksOf(9), (std::vector<RowRange>{RowRange{0, 9}}));
    std::vector<int> mine = {1, 2, 3}, all(3, 0);
    w.gatherRows(mine.data(), all.data(), 3, sizeof(int));
    EXPECT_EQ(all, mine);
    std::vector<uint8_t> bytes = {0x0f, 0xf0};
    w.combineOwned(bytes.data(), bytes.size());
    EXPECT_EQ(bytes, (std::vector<uint8_t>{0x0f, 0xf0}));
    EXPECT_EQ(w.maxOver(2.5), 2.5);
    EXPECT_EQ(w.sumOver(7), 7u);
    EXPECT_EQ(w.minOver(7), 7u);
    w.checkpoint();
    testing::internal::CaptureStderr();
    EXPECT_EQ(w.fail("octrace: error: x", 2), 2);
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "octrace: error: x\n");
}

}  // namespace
}  // namespace oct
