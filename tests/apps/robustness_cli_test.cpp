// Inputs octrace cannot answer correctly are refused with one line, never traced wrong in
// silence, never a crash or a hang (docs/ROBUSTNESS.md, "Ray files" and "Numeric range";
// docs/TRACE_FORMAT.md): ray files that are FIFOs or devices, rays the tracers cannot take,
// scenes beyond the numeric range; and messages that name the real cause.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/geometry/numeric_range.h"
#include "core/io/npy.h"
#include "core/octree/octree_limits.h"
#include "tests/cli_harness.h"
#include "tests/paths.h"
#include "validation/ambiguity_bound.h"

namespace oct {
namespace {

namespace fs = std::filesystem;

using octtest::isOneLineError;
using octtest::readFile;
using octtest::RunOptions;
using octtest::RunResult;
using octtest::show;

using octtest::kCube;
using octtest::kMeshes;

class Robustness : public ::testing::Test {
protected:
    void SetUp() override {
        root_ = std::make_unique<octtest::TempDir>("robustness_test");
        work_ = root_->path() / "work";
        fs::create_directories(work_);
    }
    RunResult run(const std::vector<std::string>& args, double timeout = 30) const {
        RunOptions opt;
        opt.timeoutSeconds = timeout;
        return octtest::runOctrace(args, root_->path() / "capture", opt);
    }
    std::string path(const std::string& name) const { return (work_ / name).string(); }
    void rays(const std::string& name, const std::vector<float>& rows) const {
        writeNpy(path(name), "<f4", {rows.size() / 8, 8}, rows.data(), 4);
    }
    std::vector<std::string> trace(const std::string& scene, const std::string& rayFile,
                                   const std::string& backend) const {
        return {"trace", scene, "--rays", rayFile, "--out", path("hits"), "--backend", backend};
    }

    std::unique_ptr<octtest::TempDir> root_;
    fs::path work_;
};

// One good ray down the cube's middle: hits the top face (z = 1) at t = 4.
const std::vector<float> kGoodRay = {0.5f, 0.5f, 5, 0, 0, -1, 0, INFINITY};

// --- ray files that are not regular files (item: a FIFO without a writer hung forever) -------

TEST_F(Robustness, RayFileThatIsAFifoWithoutAWriterIsRefusedAtOnce) {
    ASSERT_EQ(::mkfifo(path("R.npy").c_str(), 0644), 0);
    RunResult r = run(trace(kCube, path("R.npy"), "cpu"), 20);
    ASSERT_FALSE(r.timedOut) << "waited for a writer that never comes";
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("FIFO"), std::string::npos) << r.err;
}

// A FIFO with a writer and /dev/zero were "shorter than the 10-byte preamble".
TEST_F(Robustness, RayFileThatIsAFifoWithAWriterOrADeviceIsNamedAsSuch) {
    rays("good.npy", kGoodRay);
    const std::string bytes = readFile(path("good.npy"));
    ASSERT_EQ(::mkfifo(path("R.npy").c_str(), 0644), 0);
    const pid_t writer = ::fork();
    ASSERT_GE(writer, 0);
    if (writer == 0) {  // blocks until a reader opens the FIFO, then writes a valid file
        ::signal(SIGPIPE, SIG_IGN);
        int fd = ::open(path("R.npy").c_str(), O_WRONLY);
        if (fd >= 0 && ::write(fd, bytes.data(), bytes.size()) < 0) ::_exit(1);
        ::_exit(0);
    }
    RunResult r = run(trace(kCube, path("R.npy"), "cpu"), 20);
    ::kill(writer, SIGKILL);
    ::waitpid(writer, nullptr, 0);
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("FIFO"), std::string::npos) << r.err;

    fs::create_symlink("/dev/zero", path("zero.npy"));
    r = run(trace(kCube, path("zero.npy"), "cpu"), 20);
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("character device"), std::string::npos) << r.err;
    fs::create_directories(work_ / "dir.npy");
    r = run(trace(kCube, path("dir.npy"), "cpu"), 20);
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("directory"), std::string::npos) << r.err;
}

// Item: a wrong shape was reported as "got dtype <f4".
TEST_F(Robustness, WrongRayShapeNamesTheShape) {
    std::vector<float> seven(16 * 7, 1.0f);
    writeNpy(path("s7.npy"), "<f4", {16, 7}, seven.data(), 4);
    RunResult r = run(trace(kCube, path("s7.npy"), "cpu"));
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("(16, 7)"), std::string::npos) << r.err;
    std::vector<int32_t> ints(8, 1);
    writeNpy(path("i.npy"), "<i4", {1, 8}, ints.data(), 4);
    r = run(trace(kCube, path("i.npy"), "cpu"));
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("<i4"), std::string::npos) << r.err;
}

// --- rays the tracers cannot take (item: Embree aborted on rays the format called valid) ----

// Each row is refused the same way on every backend, naming the row and the rule; before,
// Embree ended in SIGABRT on the first and the CPU traced them.
TEST_F(Robustness, RaysOutsideTheTracersRangeAreRefusedAlikeOnEveryBackend) {
    struct Case {
        const char* name;
        std::vector<float> row;
        const char* says;
    };
    const std::vector<Case> cases = {
        {"negative tmin", {0.5f, 0.5f, 5, 0, 0, 1, -10, INFINITY}, "tmin"},
        {"huge direction", {0.5f, 0.5f, 5, 0, 0, -1e30f, 0, INFINITY}, "direction"},
        {"tiny direction", {0.5f, 0.5f, 5, 0, 0, -1e-30f, 0, INFINITY}, "direction"},
        {"far origin", {1e30f, 0.5f, 0.5f, -1, 0, 0, 0, INFINITY}, "origin"},
    };
    for (const Case& c : cases) {
        std::vector<float> rows = kGoodRay;
        rows.insert(rows.end(), c.row.begin(), c.row.end());
        rays("bad.npy", rows);
        std::string first;
        for (const char* backend : {"cpu", "embree"}) {
            RunResult r = run(trace(kCube, path("bad.npy"), backend));
            EXPECT_TRUE(isOneLineError(r)) << c.name << " on " << backend;
            EXPECT_NE(r.err.find("row 1"), std::string::npos) << r.err;
            EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
            EXPECT_FALSE(fs::exists(path("hits.t.npy")));
            if (first.empty()) first = r.err;
            EXPECT_EQ(r.err, first) << c.name << ": the same ray, the same answer";
        }
    }
}

// Directions of any length inside the accepted band give the same hit, in units of the
// direction, on every backend: t * |d| is the distance (4 to the cube's top face).
TEST_F(Robustness, DirectionLengthsAtTheBandsEndsTraceRightOnEveryBackend) {
    const std::vector<float> scales = {float(kMinRayDirection), 1e-10f, 1.0f, 1e10f,
                                       float(kMaxRayDirection)};
    std::vector<float> rows;
    for (float s : scales) {
        std::vector<float> r = {0.5f, 0.5f, 5, 0, 0, -s, 0, INFINITY};
        rows.insert(rows.end(), r.begin(), r.end());
    }
    rays("band.npy", rows);
    for (const char* backend : {"cpu", "embree"}) {
        for (const char* accel : {"exhaustive", "linear"}) {
            std::vector<std::string> args = trace(kCube, path("band.npy"), backend);
            args.insert(args.end(), {"--accel", accel});
            RunResult r = run(args);
            ASSERT_EQ(r.status, 0) << show(r);
            NpyArray t = readNpy(path("hits.t.npy"));
            NpyArray prim = readNpy(path("hits.prim.npy"));
            for (size_t i = 0; i < scales.size(); ++i) {
                float ti;
                int32_t pi;
                std::memcpy(&ti, t.data.data() + 4 * i, 4);
                std::memcpy(&pi, prim.data.data() + 4 * i, 4);
                EXPECT_GE(pi, 0) << backend << " " << accel << " scale " << scales[i];
                EXPECT_NEAR(double(ti) * scales[i], 4.0, 4e-6)
                    << backend << " " << accel << " scale " << scales[i];
            }
        }
    }
}

// --- scenes beyond the numeric range (item: t = +inf "hits" at extents 1e13 .. 1e17) ---------

std::string tetrahedron(double s) {
    std::ostringstream o;
    o.precision(17);
    o << "v 0 0 0\nv " << s << " 0 0\nv 0 " << s << " 0\nv 0 0 " << s << "\n"
      << "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    return o.str();
}

TEST_F(Robustness, SceneBeyondTheCoordinateRangeIsRefusedNotTracedToInfinity) {
    ASSERT_TRUE(octtest::writeFile(path("big.obj"), tetrahedron(1e14)));
    rays("r.npy", {5e11f, 5e11f, -5e11f, 0, 0, 1, 0, INFINITY});  // an origin in range
    for (const char* backend : {"cpu", "embree"}) {
        RunResult r = run(trace(path("big.obj"), path("r.npy"), backend));
        EXPECT_TRUE(isOneLineError(r)) << backend;
        EXPECT_NE(r.err.find("rescale"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(path("hits.t.npy")));
    }
    RunResult r = run(
        {"render", path("big.obj"), "--backend", "cpu", "--size", "8x8", "--out", path("o.png")});
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_FALSE(fs::exists(path("o.png")));
}

// The lower end: a scene too small for float32's exponent range, and a triangle whose area
// underflows (it could never be hit) inside an ordinary scene.
TEST_F(Robustness, SceneTooSmallForFloatIsRefused) {
    ASSERT_TRUE(octtest::writeFile(path("tiny.obj"), tetrahedron(1e-20)));
    RunResult r = run({"info", path("tiny.obj")});
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("extent"), std::string::npos) << r.err;

    ASSERT_TRUE(octtest::writeFile(path("speck.obj"),
                                   tetrahedron(1.0) + "v 1e-30 0 0\nv 0 1e-30 0\nf 1 5 6\n"));
    r = run({"info", path("speck.obj")});
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("area"), std::string::npos) << r.err;
}

// --- messages that name the real cause ------------------------------------------------------

// Item: --eye 1e30,0,0 was blamed on --up.
TEST_F(Robustness, EyeBeyondTheRangeIsBlamedOnTheEye) {
    for (const std::string option : {"--eye", "--target", "--light"}) {
        std::vector<std::string> args = {"render", kCube,   "--backend",   "cpu",  "--size",
                                         "8x8",    "--out", path("o.png"), option, "1e30,0,0"};
        RunResult r = run(args);
        EXPECT_TRUE(isOneLineError(r)) << option;
        EXPECT_NE(r.err.find(option), std::string::npos) << r.err;
        EXPECT_EQ(r.err.find("--up"), std::string::npos) << r.err;
    }
    // Only the direction of --up matters: a huge or tiny one (whose length over- or underflows
    // float) is not "parallel to the view direction (or zero)".
    for (const char* up : {"0,1e30,0", "0,1e-30,0"}) {
        RunResult r = run({"render", kCube, "--backend", "cpu", "--size", "8x8", "--out",
                           path("o.png"), "--up", up});
        EXPECT_EQ(r.status, 0) << up << "\n" << show(r);
    }
}

// A scene at the coordinate bound seen through a very narrow --fov would put the default eye
// beyond the origin bound: blamed on --fov (and --eye), not traced.
TEST_F(Robustness, DefaultEyeBeyondTheRangeIsBlamedOnTheFov) {
    const std::string scene = OCT_SOURCE_DIR "/tests/data/bad/range_coordinates_at_bound.obj";
    RunResult r = run({"render", scene, "--backend", "cpu", "--size", "8x8", "--fov", "0.001",
                       "--out", path("o.png")});
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("--fov"), std::string::npos) << r.err;
    r = run({"render", scene, "--backend", "cpu", "--size", "8x8", "--out", path("o.png")});
    EXPECT_EQ(r.status, 0) << show(r);  // the default --fov frames it from within the range
}

// Item: `info` running out of memory suggested --size, which info does not have.
TEST_F(Robustness, OutOfMemoryAdviceFitsTheCommand) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "AddressSanitizer reserves more address space than the limit allows";
#else
    RunOptions opt;
    opt.addressSpaceLimit = uint64_t(512) << 20;
    opt.timeoutSeconds = 120;
    RunResult r = octtest::runOctrace(
        {"info", kMeshes + "/teapot.obj", "--max-depth", "14", "--max-prims", "1"},
        root_->path() / "capture", opt);
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("memory"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("--size"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--max-depth"), std::string::npos) << r.err;
#endif
}

// --- work without bounds (item: hostile input, third round) ----------------------------------

// `rays --size 16384x16384` needed about 17 GB (the rows, a growth copy, an encoded copy) and
// died in bad_alloc after seconds of work. Its memory is estimated before a row is drawn and
// refused with the figure, naming rays' own options only.
TEST_F(Robustness, RaysTooLargeForMemoryAreRefusedWithTheFigure) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "AddressSanitizer reserves more address space than the limit allows";
#else
    RunOptions opt;
    opt.addressSpaceLimit = uint64_t(2) << 30;
    opt.timeoutSeconds = 60;
    RunResult r = octtest::runOctrace(
        {"rays", kMeshes + "/teapot.obj", "--size", "16384x16384", "--out", path("r.npy")},
        root_->path() / "capture", opt);
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("--size 16384x16384"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("GiB of memory"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("ulimit -v"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("--max-depth"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("--max-prims"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("r.npy")));
#endif
}

// The rays are written from where they lie: the camera set of 2048x2048 (4.2 M rows, 134 MB)
// is held once, not also as a join copy or behind an encoded .npy copy (each showed as another
// 134 MB of peak memory). Besides the rows: the answers and verdicts of octrace's kernel on them
// while its ambiguous counts are measured (validation/ambiguity_bound.h, at most
// kBaselineBytesPerRow a row, some 35 measured), which a copy of the rows would still exceed.
TEST_F(Robustness, RaysAreWrittenWithoutACopyOfThem) {
    auto peak = [&](const std::string& size) {
        RunResult r = run({"rays", kMeshes + "/teapot.obj", "--set", "camera", "--size", size,
                           "--out", path("r.npy")});
        EXPECT_EQ(r.status, 0) << show(r);
        return double(r.peakRssBytes);
    };
    const double base = peak("8x8");
    const double rows = 2048.0 * 2048.0 * 32.0;
    const double baseline = 2048.0 * 2048.0 * double(kBaselineBytesPerRow);
    const double extra = peak("2048x2048") - base;
    EXPECT_GT(extra, 0.9 * rows);  // the measure sees the rows themselves
    EXPECT_LT(extra, 1.4 * rows + baseline) << "a copy of the rays was held at once";
}

// `info quad.obj --max-depth 21 --max-prims 1` (two triangles sharing a diagonal) built cells
// along the diagonal down to depth 21: 48 s and 6 GB, then bad_alloc. The builder's node
// budget (--node-budget) and its memory check refuse the level that would pass them, naming the
// figure and the options that shrink the tree.
TEST_F(Robustness, OctreeNodesAreBoundedWhileBuilding) {
    ASSERT_TRUE(octtest::writeFile(path("quad.obj"),
                                   "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n"));
    RunResult r = run({"info", path("quad.obj"), "--max-depth", "21", "--max-prims", "1",
                       "--node-budget", "200000"});
    EXPECT_TRUE(isOneLineError(r));
    for (const char* says :
         {"more than 200000 nodes", "--node-budget", "--max-depth", "--max-prims"})
        EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
#if !defined(__SANITIZE_ADDRESS__)
    // Under a memory limit the default budget is not reached first: the memory check refuses.
    // (The largest budget, 2^31 nodes, is above the cells along the diagonal, so the count
    // before building does not refuse it.)
    RunOptions opt;
    opt.addressSpaceLimit = uint64_t(1) << 30;
    opt.timeoutSeconds = 60;
    r = octtest::runOctrace({"info", path("quad.obj"), "--max-depth", "21", "--max-prims", "1",
                             "--node-budget", std::to_string(kMaxNodeBudget)},
                            root_->path() / "capture", opt);
    EXPECT_TRUE(isOneLineError(r));
    for (const char* says : {"nodes", "of memory", "ulimit -v", "--max-depth", "--max-prims"})
        EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("bad_alloc"), std::string::npos) << r.err;
#endif
}

// The same quad under a layout's own bound: the linear layout stores a complete array of
// (8^(d+1) - 1) / 7 records, so --linear-budget bounds the depth; the hash layout needs at least
// nodes / B buckets of B slots, so --hash-budget bounds the nodes. `render quad.obj --max-depth
// 21 --max-prims 1` built 2^25 nodes down to depth 20 first (13 s, 90 s on a busy machine) and
// was refused by the node budget; the build now refuses the first level the layout cannot store
// before making it: linear at depth 9 (its array would need 7 GiB, over 4 GiB), hash at the level
// that passes the 21,844 nodes 1 MiB of buckets can hold. Each is one line naming the options.
TEST_F(Robustness, ALayoutsBoundRefusesTheBuildAtTheFirstLevelPastIt) {
    ASSERT_TRUE(octtest::writeFile(path("quad.obj"),
                                   "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n"));
    const std::vector<std::string> deep = {"--max-depth", "21", "--max-prims", "1"};
    auto refused = [&](std::vector<std::string> args, std::vector<const char*> says) {
        args.insert(args.end(), deep.begin(), deep.end());
        const RunResult r = run(args);
        EXPECT_TRUE(isOneLineError(r)) << show(r);
        for (const char* s : says)
            EXPECT_NE(r.err.find(s), std::string::npos) << s << ": " << r.err;
    };
    const std::vector<std::string> render = {"render", path("quad.obj"), "--out", path("q.png")};
    refused(render, {"depth 9", "linear", "--linear-budget", "--max-depth", "--max-prims"});
    std::vector<std::string> hash = render;
    hash.insert(hash.end(), {"--accel", "hash", "--hash-budget", "1"});
    refused(hash, {"the hash layout", "nodes", "--hash-budget", "--max-depth"});
    refused({"validate", path("quad.obj"), "--size", "8x8", "--rays", "10"},
            {"depth 9", "--linear-budget", "--max-depth"});
    // The node budget, where no layout's bound is the tighter (hash and compact at their
    // defaults, and `info`): the cells along the shared diagonal alone pass 2^25 nodes, which is
    // counted before building (the level-by-level check refused it only at depth 20, after
    // 27-33 s).
    const std::vector<const char*> budget = {"more than 33554432 nodes (the node budget)",
                                             "the edge (0, 0, 0)-(1, 1, 0)",
                                             "counted before building",
                                             "--node-budget",
                                             "--max-depth",
                                             "--max-prims"};
    std::vector<std::string> compact = render;
    compact.insert(compact.end(), {"--accel", "compact"});
    refused(compact, budget);
    refused({"info", path("quad.obj")}, budget);
}

// `--threads 4096` under a memory limit ended in libgomp's "Thread creation failed" (an abort,
// no octrace line). --threads is bounded by the machine: at most 8 per core online.
TEST_F(Robustness, ThreadsBeyondTheMachineAreRefusedWithTheBound) {
    const int most = 8 * int(sysconf(_SC_NPROCESSORS_ONLN));
    rays("one.npy", kGoodRay);
    auto traceWith = [&](int threads, uint64_t addressSpace) {
        std::vector<std::string> args = trace(kCube, path("one.npy"), "cpu");
        args.insert(args.end(), {"--threads", std::to_string(threads)});
        RunOptions opt;
        opt.timeoutSeconds = 30;
        opt.addressSpaceLimit = addressSpace;
        return octtest::runOctrace(args, root_->path() / "capture", opt);
    };
    RunResult r = traceWith(most + 1, 0);
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("--threads: " + std::to_string(most + 1) + " is not in [1, " +
                         std::to_string(most) + "]"),
              std::string::npos)
        << r.err;
    r = traceWith(most, 0);
    EXPECT_EQ(r.status, 0) << show(r);
#if !defined(__SANITIZE_ADDRESS__)
    if (most < 4096) {
        r = traceWith(4096, uint64_t(512) << 20);
        EXPECT_TRUE(isOneLineError(r));
        EXPECT_NE(r.err.find("--threads"), std::string::npos) << r.err;
    }
#endif
}

// A ray file of `rows` rows whose data are a hole (a sparse file: no disk, zeros when read):
// the reader's size checks pass and the rows would be refused only once read.
void sparseRayFile(const std::string& file, uint64_t rows) {
    const std::string header =
        "{'descr': '<f4', 'fortran_order': False, 'shape': (" + std::to_string(rows) + ", 8), }";
    std::string dict = header;
    dict.append((64 - (10 + dict.size() + 1) % 64) % 64, ' ');
    dict.push_back('\n');
    std::string bytes("\x93NUMPY\x01\x00", 8);
    bytes.push_back(char(dict.size() & 0xff));
    bytes.push_back(char(dict.size() >> 8));
    bytes += dict;
    ASSERT_TRUE(octtest::writeFile(file, bytes));
    fs::resize_file(file, bytes.size() + rows * 32);
}

// Every command that holds a user-sized array estimates it against the machine before
// allocating it and refuses with the figure: before, each of these ended in a bare bad_alloc
// (or, for validate and bench, minutes of work first).
TEST_F(Robustness, ArraysTooLargeForMemoryAreRefusedWithTheFigure) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "AddressSanitizer reserves more address space than the limit allows";
#else
    sparseRayFile(path("huge.npy"), uint64_t(64) << 20);  // 2 GiB of rows
    struct Case {
        std::vector<std::string> args;
        const char* names;  // the option or input whose size is refused
    };
    const std::vector<Case> cases = {
        {{"render", kCube, "--size", "16384x16384", "--out", path("o.png")}, "--size 16384x16384"},
        {trace(kCube, path("huge.npy"), "cpu"), "67108864 rays"},
        {{"certify", kCube, "--rays", path("huge.npy"), "--hits", path("hits")}, "67108864 rays"},
        {{"info", "grid:1000000000"}, "grid:1000000000"},
        {{"bench", "--clouds", "10", "--meshes", "none", "--backends", "cpu", "--size",
          "16384x16384", "--repeats", "1", "--warmup", "0", "--no-progress", "--out",
          path("bench")},
         "--size 16384x16384"},
    };
    for (const Case& c : cases) {
        RunOptions opt;
        opt.addressSpaceLimit = uint64_t(2) << 30;
        opt.timeoutSeconds = 60;
        const RunResult r = octtest::runOctrace(c.args, root_->path() / "capture", opt);
        SCOPED_TRACE(c.args[0] + " " + c.names);
        EXPECT_TRUE(isOneLineError(r));
        for (const char* says : {c.names, "of memory", "ulimit -v"})
            EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
    }
#endif
}

}  // namespace
}  // namespace oct
