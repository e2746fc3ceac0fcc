// octrace under mpirun (dist/): trace, render, certify and validate across 2 and 3 ranks write
// the same files, byte for byte, as one process (reports: the same JSON but for its seconds), on
// the committed meshes and a grid cloud; a rank that fails or dies fails the whole run and
// leaves no output. Skipped in a build without MPI (OCT_MPI=OFF) or without mpirun.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/io/npy.h"
#include "dist/ranks.h"
#include "tests/cli_harness.h"
#include "tests/paths.h"

namespace oct {
namespace {

namespace fs = std::filesystem;
using octtest::kMeshes;
using octtest::kTeapot;
using octtest::quote;
using octtest::readFile;
using octtest::runOctrace;
using octtest::RunOptions;
using octtest::RunResult;
using octtest::show;

const std::string kMpiexec = OCT_MPIEXEC;
const std::string kCornell = kMeshes + "/cornell_box.obj";
const std::string kGrid = "grid:4096:3";  // the paper's grid cloud, one sphere a deepest leaf

// mpirun's words for `ranks` processes on this machine: more ranks than cores allowed, as root
// when the tests run as root (CI's container), and without Open MPI's own boxes (--quiet) unless
// the test reads them.
std::vector<std::string> mpirun(int ranks, bool quiet = true) {
    std::vector<std::string> w = {kMpiexec, "--oversubscribe", "-np", std::to_string(ranks)};
    if (::geteuid() == 0) w.push_back("--allow-run-as-root");
    if (quiet) w.push_back("--quiet");
    return w;
}

// A report without its timings: every "seconds" entry, at any depth.
nlohmann::json withoutSeconds(const nlohmann::json& j) {
    if (j.is_object()) {
        nlohmann::json out = nlohmann::json::object();
        for (auto it = j.begin(); it != j.end(); ++it)
            if (it.key() != "seconds") out[it.key()] = withoutSeconds(it.value());
        return out;
    }
    if (j.is_array()) {
        nlohmann::json out = nlohmann::json::array();
        for (const auto& v : j) out.push_back(withoutSeconds(v));
        return out;
    }
    return j;
}

class Mpi : public ::testing::Test {
protected:
    void SetUp() override {
        if (!builtWithMpi()) GTEST_SKIP() << "built without MPI (OCT_MPI=OFF)";
        if (kMpiexec.empty() || !fs::exists(kMpiexec)) GTEST_SKIP() << "no mpirun";
        dir_ = std::make_unique<octtest::TempDir>("mpi");
    }
    std::string p(const std::string& name) const { return dir_->str(name); }
    std::string q(const std::string& name) const { return quote(p(name)); }

    RunResult one(const std::string& args) const {
        return runOctrace(args, dir_->path() / "capture");
    }
    RunResult ranks(int k, const std::string& args, bool quiet = true) const {
        RunOptions o;
        o.launcher = mpirun(k, quiet);
        o.timeoutSeconds = 240;
        return runOctrace(octtest::splitWords(args), dir_->path() / "capture", o);
    }
    // Both files exist and hold the same bytes.
    ::testing::AssertionResult sameBytes(const std::string& a, const std::string& b) const {
        if (!fs::exists(p(a)) || !fs::exists(p(b)))
            return ::testing::AssertionFailure() << a << " or " << b << " is missing";
        if (readFile(p(a)) != readFile(p(b)))
            return ::testing::AssertionFailure() << a << " and " << b << " differ";
        return ::testing::AssertionSuccess();
    }
    nlohmann::json report(const std::string& name) const {
        return withoutSeconds(nlohmann::json::parse(readFile(p(name))));
    }
    // Nothing in the folder but the inputs named (no output, no temporary, no lock file).
    std::vector<std::string> filesBut(const std::vector<std::string>& inputs) const {
        std::vector<std::string> left;
        for (const auto& e : fs::directory_iterator(dir_->path())) {
            const std::string name = e.path().filename().string();
            if (name == "capture") continue;
            if (std::find(inputs.begin(), inputs.end(), name) == inputs.end()) left.push_back(name);
        }
        return left;
    }
    void makeRays(const std::string& scene, const std::string& name, const std::string& extra) {
        const RunResult r = one("rays " + quote(scene) + " --out " + q(name) + " " + extra);
        ASSERT_EQ(r.status, 0) << show(r);
    }

    std::unique_ptr<octtest::TempDir> dir_;
};

TEST_F(Mpi, TraceWritesTheOneProcessFilesOnTwoAndThreeRanks) {
    for (const auto& [scene, accel] : {std::pair{kTeapot, "hash"}, {kGrid, "linear"}}) {
        SCOPED_TRACE(scene);
        makeRays(scene, "R.npy", "--count 3001 --size 31x17");
        const std::string trace =
            "trace " + quote(scene) + " --backend cpu --accel " + accel + " --rays " + q("R.npy");
        RunResult r = one(trace + " --out " + q("one"));
        ASSERT_EQ(r.status, 0) << show(r);
        for (int k : {2, 3}) {
            const std::string out = "k" + std::to_string(k);
            r = ranks(k, trace + " --out " + q(out));
            ASSERT_EQ(r.status, 0) << show(r);
            EXPECT_EQ(r.err, "");
            EXPECT_NE(r.out.find("ranks   " + std::to_string(k)), std::string::npos) << r.out;
            EXPECT_TRUE(sameBytes("one.t.npy", out + ".t.npy"));
            EXPECT_TRUE(sameBytes("one.prim.npy", out + ".prim.npy"));
            // The record: the same rows and digests (its id and file stamps are each run's).
            const nlohmann::json a = nlohmann::json::parse(readFile(p("one.run.json")));
            const nlohmann::json b = nlohmann::json::parse(readFile(p(out + ".run.json")));
            EXPECT_EQ(a["rows"], b["rows"]);
            EXPECT_EQ(a["t"]["fnv1a64"], b["t"]["fnv1a64"]);
            EXPECT_EQ(a["prim"]["fnv1a64"], b["prim"]["fnv1a64"]);
            // certify takes the pair as trace's own (the record vouches for both files).
            r = one("certify " + quote(scene) + " --rays " + q("R.npy") + " --hits " + q(out));
            EXPECT_EQ(r.status, 0) << show(r);
        }
        for (const std::string& f : filesBut({})) fs::remove(p(f));
    }
}

// No rank holds all rays: on a 512 MiB ray file (16M rows, every ray a miss, so tracing is quick)
// the largest of 3 ranks peaks at least 40 % of the file below one process, which reads it whole
// (rank 0 holds a third of the rays and every answer; both hold the same scene and libraries,
// and the ranks MPI's shared memory besides: 441 MiB against 302 MiB at 8M rows).
TEST_F(Mpi, NoRankHoldsAllRays) {
    constexpr uint64_t kRows = uint64_t(1) << 24, kChunk = 1 << 16;
    {
        std::ofstream f(p("big.npy"), std::ios::binary);
        std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (" +
                             std::to_string(kRows) + ", 8), }";
        header.append(64 - (10 + header.size() + 1) % 64, ' ');
        header += '\n';
        const uint16_t len = uint16_t(header.size());
        f.write("\x93NUMPY\x01\x00", 8);
        f.write(reinterpret_cast<const char*>(&len), 2);
        f << header;
        // From beyond the teapot's box, away from it: a miss at the root's box.
        const float row[8] = {0.0f, 0.0f, 1000.0f, 0.0f, 0.0f, 1.0f, 0.0f, INFINITY};
        std::vector<float> chunk(kChunk * 8);
        for (uint64_t i = 0; i < kChunk; ++i) std::memcpy(&chunk[8 * i], row, sizeof row);
        for (uint64_t done = 0; done < kRows; done += kChunk)
            f.write(reinterpret_cast<const char*>(chunk.data()), chunk.size() * sizeof(float));
        ASSERT_TRUE(f.good());
    }
    const std::string trace =
        "trace " + quote(kTeapot) + " --backend cpu --rays " + q("big.npy") + " --out ";
    const RunResult single = one(trace + q("one"));
    ASSERT_EQ(single.status, 0) << show(single);
    const double fileMiB = double(kRows) * 32 / (1 << 20);
    const double singleMiB = double(single.peakRssBytes) / (1 << 20);
    EXPECT_GT(singleMiB, fileMiB);  // the measure sees the rays
    const RunResult r = ranks(3, trace + q("k3"));
    ASSERT_EQ(r.status, 0) << show(r);
    const std::string key = "the largest rank's peak memory ";
    const size_t at = r.out.find(key);
    ASSERT_NE(at, std::string::npos) << r.out;
    const double largestMiB = std::stod(r.out.substr(at + key.size()));
    EXPECT_LT(largestMiB, singleMiB - 0.4 * fileMiB) << r.out;
    std::printf("peak memory: one process %.0f MiB, largest of 3 ranks %.0f MiB\n", singleMiB,
                largestMiB);
    EXPECT_TRUE(sameBytes("one.t.npy", "k3.t.npy"));
    fs::remove(p("big.npy"));
}

TEST_F(Mpi, RenderWritesTheOneProcessImagesAndArrays) {
    // 37 rows: no rank count divides them, and the ranks' bands differ in height.
    for (const std::string& scene : {kCornell, kGrid}) {
        SCOPED_TRACE(scene);
        auto render = [&](const std::string& tag) {
            return "render " + quote(scene) + " --backend cpu --size 45x37 --out " +
                   q(tag + ".png") + " --depth " + q(tag + ".t.npy") + " --prim " +
                   q(tag + ".prim.npy") + " --cost " + q(tag + ".cost.npy") + " --heatmap-out " +
                   q(tag + ".heat.png") + " --overlay-out " + q(tag + ".cells.png") +
                   " --compare-embree";
        };
        RunResult r = one(render("one"));
        ASSERT_EQ(r.status, 0) << show(r);
        const std::string agreement = r.out.substr(r.out.find("embree "));
        for (int k : {2, 3}) {
            const std::string tag = "k" + std::to_string(k);
            r = ranks(k, render(tag));
            ASSERT_EQ(r.status, 0) << show(r);
            for (const char* ext :
                 {".png", ".t.npy", ".prim.npy", ".cost.npy", ".heat.png", ".cells.png"})
                EXPECT_TRUE(sameBytes(std::string("one") + ext, tag + ext));
            // Embree's frame by bands as well: the same agreement line.
            EXPECT_NE(r.out.find(agreement), std::string::npos) << r.out;
        }
    }
}

TEST_F(Mpi, RenderWithMoreRanksThanRowsLeavesTheExtraRanksNothing) {
    RunResult r = one("render " + quote(kCornell) + " --backend cpu --size 9x2 --out " +
                      q("one.png") + " --depth " + q("one.t.npy"));
    ASSERT_EQ(r.status, 0) << show(r);
    r = ranks(3, "render " + quote(kCornell) + " --backend cpu --size 9x2 --out " + q("k.png") +
                     " --depth " + q("k.t.npy"));
    ASSERT_EQ(r.status, 0) << show(r);
    EXPECT_TRUE(sameBytes("one.png", "k.png"));
    EXPECT_TRUE(sameBytes("one.t.npy", "k.t.npy"));
}

// One process's hits of the ray file RAYS in SCENE (as trace writes them), to be made faulty.
struct Hits {
    std::vector<float> t;
    std::vector<int32_t> prim;
};

class MpiCertify : public Mpi {
protected:
    Hits traceHits(const std::string& scene, const std::string& rays) {
        const RunResult r =
            one("trace " + quote(scene) + " --backend cpu --rays " + q(rays) + " --out " + q("H"));
        EXPECT_EQ(r.status, 0) << show(r);
        const NpyArray t = readNpy(p("H.t.npy")), prim = readNpy(p("H.prim.npy"));
        Hits h{std::vector<float>(t.elementCount()), std::vector<int32_t>(t.elementCount())};
        std::memcpy(h.t.data(), t.data.data(), t.data.size());
        std::memcpy(h.prim.data(), prim.data.data(), prim.data.size());
        return h;
    }
    // Certifies `h` (as B) with and without a recheck cap: a FAIL, and on 2 and 3 ranks the same
    // verdict line, per-ray files (and diff image) and report as one process's.
    void expectRanksJudgeAsOneProcess(const std::string& scene, const std::string& rays,
                                      const Hits& h, const std::string& cap, bool diffImage) {
        writeNpy(p("B.t.npy"), "<f4", {h.t.size()}, h.t.data(), 4);
        writeNpy(p("B.prim.npy"), "<i4", {h.prim.size()}, h.prim.data(), 4);
        std::vector<std::string> files = {".class.npy", ".reasons.npy", ".leak.npy"};
        if (diffImage) files.push_back(".png");
        for (const std::string& c : std::vector<std::string>{"", cap}) {
            SCOPED_TRACE(c);
            auto certify = [&](const std::string& tag) {
                return "certify " + quote(scene) + " --rays " + q(rays) + " --hits " + q("B") +
                       " --verdicts " + q(tag) + " --json " + q(tag + ".json") +
                       (diffImage ? " --diff-image " + q(tag + ".png") : "") + c;
            };
            const RunResult single = one(certify("one"));
            ASSERT_EQ(single.status, 1) << show(single);  // FAIL
            for (int k : {2, 3}) {
                const std::string tag = "k" + std::to_string(k);
                const RunResult r = ranks(k, certify(tag));
                EXPECT_EQ(r.status, 1) << show(r);
                EXPECT_EQ(r.err, single.err);  // the verdict line, once
                for (const std::string& f : files) EXPECT_TRUE(sameBytes("one" + f, tag + f));
                EXPECT_EQ(report("one.json"), report(tag + ".json"));
            }
        }
    }
};

// A faulty tracer's answers under a recheck cap: the cap counts rows in row order across ranks,
// so the verdicts, counts and listed findings are the one process's.
TEST_F(MpiCertify, JudgesAFaultyTracerAsOneProcessDoes) {
    makeRays(kTeapot, "R.npy", "--count 4000 --size 24x16");
    Hits h = traceHits(kTeapot, "R.npy");
    const size_t n = h.t.size();
    for (size_t i = 0; i < n; i += 7) h.t[i] = std::isfinite(h.t[i]) ? h.t[i] * 1.01f : 5.0f;
    for (size_t i = 3; i < n; i += 11) h.prim[i] = (h.prim[i] + 3) % 992;
    for (size_t i = 5; i < n; i += 13) h.t[i] = INFINITY, h.prim[i] = -1;
    expectRanksJudgeAsOneProcess(kTeapot, "R.npy", h, " --max-rechecks 25", true);
}

// The slivers square's targets carry no triangles of their own: a leak candidate is rechecked
// against the truth, by the rank that owns its row, under the cap per set in row order.
TEST_F(MpiCertify, RechecksLeakCandidatesAsOneProcessDoes) {
    const std::string scene = "slivers:400:2";
    makeRays(scene, "S.npy", "--set slivers,around --count 3000");
    Hits h = traceHits(scene, "S.npy");
    for (size_t i = 0; i < h.t.size(); i += 3)  // a third pass through: leak candidates
        h.t[i] = INFINITY, h.prim[i] = -1;
    expectRanksJudgeAsOneProcess(scene, "S.npy", h, " --max-rechecks 40", false);
    EXPECT_GT(report("one.json")["leaks"].get<int64_t>(), 0);  // the candidates did leak
}

TEST_F(Mpi, ValidateReportsWhatOneProcessReports) {
    auto validate = [&](const std::string& tag) {
        return "validate " + quote(kCornell) +
               " --backend cpu --accel linear,hash --size 40x27 --rays 1500 --json " +
               q(tag + ".json") + " --diff-image " + q(tag + ".png");
    };
    RunResult r = one(validate("one"));
    ASSERT_EQ(r.status, 0) << show(r);
    for (int k : {2, 3}) {
        const std::string tag = "k" + std::to_string(k);
        r = ranks(k, validate(tag));
        ASSERT_EQ(r.status, 0) << show(r);
        EXPECT_EQ(report("one.json"), report(tag + ".json"));
        for (const char* run : {"-linear-cpu.png", "-hash-cpu.png"})
            EXPECT_TRUE(sameBytes(std::string("one") + run, tag + run));
    }
    // The regression set and Table 1 stay one process's: refused, in one line.
    r = ranks(2, "validate --table1");
    EXPECT_EQ(r.status, 2) << show(r);
    EXPECT_EQ(r.err.rfind("octrace: rank 0 of 2: error: across MPI ranks validate", 0), 0u)
        << r.err;
}

// Bad input only some ranks read (their blocks of the ray file): every rank stops, the run exits
// 2 with one line naming the rank of the lowest bad row, the row a whole read names, and leaves
// nothing. A lower bad row on a higher rank wins over rank 0's.
TEST_F(Mpi, TheRankOfTheLowestBadRowFailsTheRunInOneLine) {
    makeRays(kTeapot, "R.npy", "--count 3000 --size 16x16");
    const NpyArray rays = readNpy(p("R.npy"));
    const uint64_t n = rays.shape[0];
    const RowDeal deal = dealRows(n, 3);
    ASSERT_GT(n, 4 * deal.block);
    for (const std::vector<uint64_t>& bad :
         {std::vector<uint64_t>{n - 5}, {3 * deal.block + 2, deal.block + 7}}) {
        const uint64_t lowest = *std::min_element(bad.begin(), bad.end());
        SCOPED_TRACE("lowest bad row " + std::to_string(lowest));
        NpyArray b = rays;
        const float tmin = -1.0f;
        for (uint64_t row : bad) std::memcpy(b.data.data() + (row * 8 + 6) * 4, &tmin, 4);
        writeNpy(p("B.npy"), "<f4", b.shape, b.data.data(), 4);
        const std::string trace =
            "trace " + quote(kTeapot) + " --backend cpu --rays " + q("B.npy") + " --out " + q("T");
        const RunResult single = one(trace);
        ASSERT_EQ(single.status, 2) << show(single);
        ASSERT_NE(single.err.find("row " + std::to_string(lowest) + ":"), std::string::npos);
        const RunResult r = ranks(3, trace);
        EXPECT_TRUE(r.status == 2 && !r.timedOut) << show(r);
        // "octrace: error: MSG" from one process is "octrace: rank R of 3: error: MSG" here.
        EXPECT_EQ(r.err, "octrace: rank " + std::to_string(deal.ownerOf(lowest)) +
                             " of 3: " + single.err.substr(std::strlen("octrace: ")))
            << r.err;
        EXPECT_EQ(filesBut({"R.npy", "R.json", "B.npy"}), std::vector<std::string>{});
    }
}

// A rank that dies (SIGKILL, as the OOM killer sends) before it traces: mpirun ends the run, and
// rank 0 leaves no output, temporary or lock behind. mpirun's message names the dead rank when
// it reports the signal; under load it may report rank 0's exit after losing its peer instead.
TEST_F(Mpi, AKilledRankFailsTheRunAndLeavesNoOutput) {
    makeRays(kTeapot, "R.npy", "--count 2000 --size 16x16");
    RunOptions o;
    o.launcher = mpirun(2, false);
    for (const char* w :
         {"/bin/sh", "-c", "if [ \"$OMPI_COMM_WORLD_RANK\" = 1 ]; then kill -9 $$; fi; exec \"$@\"",
          "sh"})
        o.launcher.push_back(w);
    o.timeoutSeconds = 120;
    const RunResult r =
        runOctrace({"trace", kTeapot, "--backend", "cpu", "--rays", p("R.npy"), "--out", p("T")},
                   dir_->path() / "capture", o);
    EXPECT_FALSE(r.timedOut) << show(r);
    EXPECT_NE(r.status, 0) << show(r);
    if (r.err.find("exited on signal") != std::string::npos) {
        EXPECT_NE(r.err.find("rank 1 "), std::string::npos) << r.err;
    }
    EXPECT_EQ(filesBut({"R.npy", "R.json"}), std::vector<std::string>{});
}

// Rank 0's last write fails after every other rank is done (validate's per-run diff image names
// a folder): the others wait in their last agreement, so the run fails on every rank, without a
// hang, with rank 0's one line.
TEST_F(Mpi, RankZerosFailedLastWriteFailsTheRunOnEveryRank) {
    fs::create_directory(p("d-hash-cpu.png"));
    RunOptions o;
    o.launcher = mpirun(3);
    o.timeoutSeconds = 120;
    const RunResult r =
        runOctrace({"validate", kCornell, "--backend", "cpu", "--accel", "linear,hash", "--size",
                    "20x20", "--rays", "300", "--diff-image", p("d.png")},
                   dir_->path() / "capture", o);
    EXPECT_FALSE(r.timedOut) << show(r);
    EXPECT_EQ(r.status, 2) << show(r);
    EXPECT_EQ(r.err.rfind("octrace: rank 0 of 3: error: cannot write", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// A command that does not split its rows would run whole on every rank, each writing the same
// outputs: refused before any work, in one line.
TEST_F(Mpi, CommandsThatDoNotSplitAreRefused) {
    const RunResult r =
        ranks(2, "rays " + quote(kTeapot) + " --count 100 --size 8x8 --out " + q("R.npy"));
    EXPECT_EQ(r.status, 2) << show(r);
    EXPECT_EQ(r.err,
              "octrace: rank 0 of 2: error: octrace rays runs in one process; across MPI ranks "
              "run trace, certify, render or validate (docs/DISTRIBUTED.md)\n");
    EXPECT_FALSE(fs::exists(p("R.npy")));
}

// Ranks whose backends differ (as `auto` resolves on nodes with and without a GPU; here rank 1 is
// given embree) would gather two tracers' rows into one output (and hang in validate's unequal
// calls, which agree the same way): every rank refuses before the work, rank 0 in one line.
TEST_F(Mpi, RanksThatResolveTheBackendDifferentlyAreRefused) {
    makeRays(kTeapot, "R.npy", "--count 500 --size 8x8");
    for (const std::string command : {"trace", "render"}) {
        SCOPED_TRACE(command);
        RunOptions o;
        o.launcher = mpirun(2);
        for (const char* w : {"/bin/sh", "-c",
                              "b=cpu; [ \"$OMPI_COMM_WORLD_RANK\" = 1 ] && b=embree; "
                              "exec \"$@\" --backend $b",
                              "sh"})
            o.launcher.push_back(w);
        o.timeoutSeconds = 120;
        std::vector<std::string> args = {command, kTeapot};
        const std::vector<std::string> more =
            command == "trace" ? std::vector<std::string>{"--rays", p("R.npy"), "--out", p("T")}
                               : std::vector<std::string>{"--size", "16x16", "--out", p("T.png")};
        args.insert(args.end(), more.begin(), more.end());
        const RunResult r = runOctrace(args, dir_->path() / "capture", o);
        EXPECT_FALSE(r.timedOut) << show(r);
        EXPECT_EQ(r.status, 2) << show(r);
        EXPECT_EQ(r.err.rfind("octrace: rank 0 of 2: error: --backend cpu: the ranks resolved it "
                              "differently",
                              0),
                  0u)
            << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_EQ(filesBut({"R.npy", "R.json"}), std::vector<std::string>{});
    }
}

// A launcher's step of 2 tasks that MPI starts as 1 process (another MPI's launcher, here Slurm's
// variables without srun) would be 2 whole runs writing the same outputs: refused in one line,
// as a build without MPI refuses any launch of several ranks. Runs in every build.
TEST(Launcher, AStepOfSeveralTasksThatIsNotSeveralRanksIsRefused) {
    octtest::TempDir dir("launcher");
    RunOptions o;
    o.shellBefore = "export SLURM_PROCID=0 SLURM_STEP_NUM_TASKS=2 SLURM_LOCALID=0";
    o.timeoutSeconds = 60;
    const RunResult r = runOctrace({"info", kTeapot}, dir.path(), o);
    EXPECT_TRUE(octtest::isOneLineError(r));
    EXPECT_NE(r.err.find(builtWithMpi() ? "launched as rank 0 of 2, but MPI started 1"
                                        : "launched as rank 0 of 2, but this octrace was built "
                                          "without MPI"),
              std::string::npos)
        << r.err;
}

// An output rank 0 refuses (its folder is missing) stops every rank before the work.
TEST_F(Mpi, AnOutputRankZeroRefusesStopsEveryRank) {
    makeRays(kTeapot, "R.npy", "--count 500 --size 8x8");
    const RunResult r = ranks(3, "trace " + quote(kTeapot) + " --backend cpu --rays " + q("R.npy") +
                                     " --out " + q("missing/T"));
    EXPECT_EQ(r.status, 2) << show(r);
    EXPECT_EQ(r.err.rfind("octrace: rank 0 of 3: error: ", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

}  // namespace
}  // namespace oct
