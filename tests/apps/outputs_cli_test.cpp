// What octrace promises about the files it writes (docs/ROBUSTNESS.md, "Outputs"), through the
// real binary: an output naming an input or another output is refused before any work; an
// output that is a device, FIFO or folder is refused; SIGINT, SIGTERM and SIGHUP while writing
// leave neither a temporary nor a partial output; a full disk or a failing standard output is
// a one-line error that leaves every existing file as it was.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "core/io/npy.h"
#include "tests/cli_harness.h"
#include "tests/paths.h"

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
using octtest::kTeapot;
const std::string kKeep = "existing bytes that must survive\n";

class Outputs : public ::testing::Test {
protected:
    void SetUp() override {
        root_ = std::make_unique<octtest::TempDir>("outputs_test");
        work_ = root_->path() / "work";
        fs::create_directories(work_);
    }

    RunResult run(const std::vector<std::string>& args, const RunOptions& opt = {}) const {
        return octtest::runOctrace(args, root_->path() / "capture", opt);
    }
    std::string path(const std::string& name) const { return (work_ / name).string(); }
    std::set<std::string> listing() const {
        std::set<std::string> names;
        for (const auto& e : fs::directory_iterator(work_)) names.insert(e.path().filename());
        return names;
    }
    void put(const std::string& name, const std::string& bytes) const {
        ASSERT_TRUE(octtest::writeFile(path(name), bytes));
    }
    // A small render's arguments (shallow tree: the test is about files, not the picture).
    std::vector<std::string> render(const std::string& scene) const {
        return {"render", scene, "--backend", "cpu", "--max-depth", "4", "--size", "8x8"};
    }
    static std::vector<std::string> plus(std::vector<std::string> a,
                                         const std::vector<std::string>& b) {
        a.insert(a.end(), b.begin(), b.end());
        return a;
    }

    std::unique_ptr<octtest::TempDir> root_;
    fs::path work_;
};

// Item: `octrace render s.obj --out s.obj` replaced the scene by a PNG and exited 0.
TEST_F(Outputs, OutputNamingTheSceneIsRefusedAndTheSceneKept) {
    fs::copy_file(kTeapot, path("s.obj"));
    const std::string scene = readFile(path("s.obj"));
    for (const char* option : {"--out", "--depth", "--prim", "--cost"}) {
        std::vector<std::string> args = render(path("s.obj"));
        if (std::string(option) != "--out") args = plus(args, {"--out", path("ok.png")});
        RunResult r = run(plus(args, {option, path("s.obj")}));
        EXPECT_TRUE(isOneLineError(r)) << option;
        EXPECT_NE(r.err.find("input"), std::string::npos) << r.err;
        EXPECT_TRUE(readFile(path("s.obj")) == scene) << option << " destroyed the scene";
        EXPECT_EQ(listing(), std::set<std::string>{"s.obj"}) << option;
    }
    // The report files of info, validate and explain, explain's page, the ray sets of rays,
    // and render's teaching images too.
    const std::vector<std::vector<std::string>> others = {
        {"info", path("s.obj"), "--json", path("s.obj")},
        {"validate", path("s.obj"), "--json", path("s.obj")},
        {"explain", path("s.obj"), "--json", path("s.obj")},
        {"explain", path("s.obj"), "--html", path("s.obj")},
        {"rays", path("s.obj"), "--set", "around", "--count", "4", "--out", path("s.obj")},
        plus(render(path("s.obj")), {"--heatmap", path("s.obj")}),
        plus(render(path("s.obj")), {"--overlay", path("s.obj")})};
    for (const std::vector<std::string>& args : others) {
        RunResult r = run(args);
        EXPECT_TRUE(isOneLineError(r)) << args[0] << " " << args[2] << show(r);
        EXPECT_TRUE(readFile(path("s.obj")) == scene) << args[0] << " destroyed the scene";
        EXPECT_EQ(listing(), std::set<std::string>{"s.obj"}) << args[0];
    }
    // The same file under another spelling, through a symlink and through a hard link.
    fs::create_symlink(path("s.obj"), path("link.png"));
    fs::create_hard_link(path("s.obj"), path("hard.png"));
    for (const std::string& out :
         {std::string("./s.obj"), path("sub/../s.obj"), path("link.png"), path("hard.png")}) {
        fs::create_directories(work_ / "sub");
        RunResult r = octtest::runOctrace(plus(render("s.obj"), {"--out", out}),
                                          root_->path() / "capture", [&] {
                                              RunOptions o;
                                              o.workingDir = work_.string();
                                              return o;
                                          }());
        EXPECT_TRUE(isOneLineError(r)) << out;
        EXPECT_TRUE(readFile(path("s.obj")) == scene) << out;
        EXPECT_TRUE(fs::is_symlink(path("link.png")));
        fs::remove(work_ / "sub");
    }
}

// Item: `trace --rays R.t.npy --out R` overwrote its own ray file.
TEST_F(Outputs, TraceOutputNamingTheRayFileIsRefused) {
    const std::vector<float> ray = {0.5f, 0.5f, 5, 0, 0, -1, 0, INFINITY};
    writeNpy(path("R.t.npy"), "<f4", {1, 8}, ray.data(), 4);
    const std::string rays = readFile(path("R.t.npy"));
    RunResult r =
        run({"trace", kCube, "--backend", "cpu", "--rays", path("R.t.npy"), "--out", path("R")});
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_TRUE(readFile(path("R.t.npy")) == rays);
    EXPECT_EQ(listing(), std::set<std::string>{"R.t.npy"});
    // And the scene as an output of trace.
    fs::copy_file(kCube, path("c.prim.npy"));
    r = run({"trace", path("c.prim.npy"), "--backend", "cpu", "--rays", path("R.t.npy"), "--out",
             path("c")});
    EXPECT_FALSE(r.status == 0) << show(r);
    EXPECT_TRUE(readFile(path("c.prim.npy")) == readFile(kCube));
}

// Item: `--out prev.png --depth prev.png` failed with "cannot replace ...: No such file or
// directory" after writing the other outputs, and left .npy data in a good prev.png.
TEST_F(Outputs, TwoOutputsNamingOneFileAreRefusedBeforeAnyWork) {
    put("prev.png", kKeep);
    RunResult r = run(plus(render(kCube), {"--out", path("prev.png"), "--depth", path("prev.png"),
                                           "--prim", path("p.npy")}));
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("same file"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("cannot replace"), std::string::npos) << r.err;
    EXPECT_TRUE(readFile(path("prev.png")) == kKeep);
    EXPECT_EQ(listing(), std::set<std::string>{"prev.png"});

    // "./w.npy" and "w.npy" are one file, existing or not.
    for (bool exists : {false, true}) {
        if (exists) put("w.npy", kKeep);
        RunOptions inWork;
        inWork.workingDir = work_.string();
        r = octtest::runOctrace(
            plus(render(kCube), {"--out", "o.png", "--depth", "./w.npy", "--cost", "w.npy"}),
            root_->path() / "capture", inWork);
        EXPECT_TRUE(isOneLineError(r)) << "exists " << exists;
        EXPECT_FALSE(fs::exists(path("o.png")));
        if (exists) {
            EXPECT_TRUE(readFile(path("w.npy")) == kKeep);
        }
    }
}

// An output that is not a regular file would be replaced by the rename (as root, --out
// /dev/null would replace the device node): refused, and left as it was.
TEST_F(Outputs, OutputThatIsAFifoOrAFolderIsRefused) {
    ASSERT_EQ(::mkfifo(path("fifo.png").c_str(), 0644), 0);
    fs::create_directories(work_ / "folder.png");
    for (const char* name : {"fifo.png", "folder.png"}) {
        RunResult r = run(plus(render(kCube), {"--out", path(name)}));
        EXPECT_TRUE(isOneLineError(r)) << name;
        EXPECT_NE(r.err.find("regular file"), std::string::npos) << r.err;
    }
    struct stat st;
    ASSERT_EQ(::lstat(path("fifo.png").c_str(), &st), 0);
    EXPECT_TRUE(S_ISFIFO(st.st_mode));
    EXPECT_TRUE(fs::is_directory(work_ / "folder.png"));
    EXPECT_EQ(listing(), (std::set<std::string>{"fifo.png", "folder.png"}));
}

// Item: SIGINT or SIGTERM while the outputs are written left NAME.tmp.PID (18-31 MB of an
// 80 MB output) behind. The render looks away from the scene (every ray misses at the root
// box, so the frame is quick) at 3072x3072 with three .npy outputs (150 MB): the signal is
// sent as soon as the first temporary appears, i.e. while the outputs are being written.
TEST_F(Outputs, SignalWhileWritingLeavesNoTemporaryAndNoPartialOutput) {
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
        SCOPED_TRACE(strsignal(sig));
        put("out.png", kKeep);
        bool sent = false;
        RunOptions opt;
        opt.timeoutSeconds = 120;
        opt.whileRunning = [&](pid_t pid, double) {
            if (sent) return;
            for (const auto& e : fs::directory_iterator(work_))
                if (e.path().filename().string().find(".tmp.") != std::string::npos) {
                    ::kill(pid, sig);
                    sent = true;
                    return;
                }
        };
        RunResult r = run(
            {"render",      kCube,         "--backend", "cpu",           "--accel", "linear",
             "--max-depth", "2",           "--size",    "3072x3072",     "--eye",   "0,0,10",
             "--target",    "0,0,20",      "--out",     path("out.png"), "--depth", path("t.npy"),
             "--prim",      path("p.npy"), "--cost",    path("c.npy")},
            opt);
        ASSERT_TRUE(sent) << "no temporary seen while it ran: " << show(r);
        EXPECT_EQ(r.signal, sig) << "ends by the signal, as its parent expects: " << show(r);
        const std::set<std::string> left = listing();
        for (const std::string& name : left) {
            EXPECT_EQ(name.find(".tmp."), std::string::npos) << "left behind: " << name;
            EXPECT_EQ(name.find(".lock"), std::string::npos) << "left behind: " << name;
        }
        // All or none: either nothing was replaced, or every output is complete.
        if (readFile(path("out.png")) == kKeep) {
            EXPECT_EQ(left, std::set<std::string>{"out.png"});
        } else {
            for (const char* npy : {"t.npy", "p.npy", "c.npy"})
                EXPECT_EQ(readNpy(path(npy)).shape.at(0), 3072u) << npy;
        }
        for (const std::string& name : left) fs::remove(work_ / name);
    }
}

// Item: outputs were written to the predictable NAME.tmp.PID, opened with fopen("wb"), which
// follows a symlink: `ln -s victim.txt out.png.tmp.$$; exec octrace render ... --out out.png`
// truncated victim.txt to 0 bytes (checkWritable, before any work), filled it with the PNG and
// renamed the link onto out.png, exit 0. Here the shell that becomes octrace (same pid) plants
// such a link at every output's old temporary name, for render, rays, trace and certify --json;
// one of render's links dangles (fopen would have created its target).
TEST_F(Outputs, SymlinkAtTheOldTemporaryNameLeavesItsTargetAlone) {
    put("victim.txt", kKeep);
    struct Case {
        std::vector<std::string> args, outputs;
    };
    const std::vector<Case> cases = {
        {plus(render(kCube), {"--out", path("out.png"), "--depth", path("d.npy")}),
         {"out.png", "d.npy"}},
        {{"rays", kCube, "--count", "200", "--size", "16x16", "--out", path("R.npy"), "--triangles",
          path("T.npy")},
         {"R.npy", "R.json", "T.npy"}},
        {{"trace", kCube, "--rays", path("R.npy"), "--out", path("H"), "--backend", "cpu",
          "--accel", "linear", "--max-depth", "5"},
         {"H.t.npy", "H.prim.npy"}},
        {{"certify", kCube, "--rays", path("R.npy"), "--hits", path("H"), "--json", path("J.json")},
         {"J.json"}}};
    for (const Case& c : cases) {
        SCOPED_TRACE(c.args[0]);
        RunOptions opt;
        for (const std::string& out : c.outputs) {
            const std::string target = out == "d.npy" ? "made.txt" : "victim.txt";
            opt.shellBefore += "ln -s " + octtest::quote(path(target)) + " " +
                               octtest::quote(path(out)) + ".tmp.$$\n";
        }
        RunResult r = run(c.args, opt);
        EXPECT_EQ(r.status, 0) << show(r);
        EXPECT_TRUE(readFile(path("victim.txt")) == kKeep) << "the link's target was written";
        EXPECT_FALSE(fs::exists(path("made.txt"))) << "the dangling link's target was created";
        for (const std::string& out : c.outputs) {
            EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(path(out)))) << out;
            EXPECT_GT(fs::file_size(path(out)), 0u) << out;
        }
        // The planted links are not octrace's: left where they were, still links.
        for (const std::string& name : listing())
            if (name.find(".tmp.") != std::string::npos) {
                EXPECT_TRUE(fs::is_symlink(work_ / name)) << name;
                fs::remove(work_ / name);
            }
    }
}

// Item: two runs into one prefix mixed their outputs (trace renames PREFIX.t.npy and
// PREFIX.prim.npy one after the other). A run holds an flock on PREFIX.lock while it works: a
// second run into the same prefix is refused at once, exit status 2, writing nothing. The test
// holds the lock itself, as another run would.
TEST_F(Outputs, TraceIntoAPrefixAnotherRunIsWritingIsRefused) {
    const std::vector<float> ray = {0.5f, 0.5f, 5, 0, 0, -1, 0, INFINITY};
    writeNpy(path("R.npy"), "<f4", {1, 8}, ray.data(), 4);
    const std::vector<std::string> trace = {"trace",  kCube,         "--backend", "cpu",
                                            "--rays", path("R.npy"), "--out",     path("H")};
    {
        const int fd = ::open(path("H.lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        ASSERT_GE(fd, 0);
        ASSERT_EQ(::flock(fd, LOCK_EX), 0);
        RunResult r = run(trace);
        ::close(fd);
        EXPECT_TRUE(isOneLineError(r));
        EXPECT_EQ(r.status, 2);
        EXPECT_NE(r.err.find("another octrace run is writing '" + path("H") + "'"),
                  std::string::npos)
            << r.err;
        EXPECT_EQ(listing(), (std::set<std::string>{"R.npy", "H.lock"}));
    }
    // Released, the run goes ahead; the lock file it found is not its own and stays.
    RunResult r = run(trace);
    EXPECT_EQ(r.status, 0) << show(r);
    EXPECT_EQ(listing(),
              (std::set<std::string>{"R.npy", "H.lock", "H.t.npy", "H.prim.npy", "H.run.json"}));
    // A run that made its lock file removes it.
    r = run(plus(std::vector<std::string>(trace.begin(), trace.end() - 1), {path("G")}));
    EXPECT_EQ(r.status, 0) << show(r);
    EXPECT_FALSE(fs::exists(path("G.lock")));
}

// The same for every output of a command that writes several (render, rays, certify, explain):
// each output's NAME.lock.
TEST_F(Outputs, RenderIntoAnOutputAnotherRunIsWritingIsRefused) {
    const int fd = ::open(path("d.npy.lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(::flock(fd, LOCK_EX), 0);
    RunResult r = run(plus(render(kCube), {"--out", path("o.png"), "--depth", path("d.npy")}));
    ::close(fd);
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("another octrace run is writing '" + path("d.npy") + "'"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(listing(), std::set<std::string>{"d.npy.lock"});
}

// A write that fails mid-file (here RLIMIT_FSIZE: the write returns EFBIG exactly as a full
// disk returns ENOSPC) is a one-line error; no temporary stays, existing outputs are kept.
TEST_F(Outputs, WriteFailingMidFileIsAnErrorThatKeepsEveryFile) {
    put("out.png", kKeep);
    put("t.npy", kKeep);
    RunOptions opt;
    opt.fileSizeLimit = 256 * 1024;  // the PNG fits, the 1 MB depth array does not
    RunResult r = run({"render", kCube, "--backend", "cpu", "--max-depth", "4", "--size", "512x512",
                       "--out", path("out.png"), "--depth", path("t.npy")},
                      opt);
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("t.npy"), std::string::npos) << r.err;
    EXPECT_TRUE(readFile(path("out.png")) == kKeep);
    EXPECT_TRUE(readFile(path("t.npy")) == kKeep);
    EXPECT_EQ(listing(), (std::set<std::string>{"out.png", "t.npy"}));
}

// The real thing where this process may mount a 1 MiB tmpfs (root in a container, CI as
// root); skipped elsewhere, the test above covers the code path.
TEST_F(Outputs, FullDiskIsAnErrorThatKeepsEveryFile) {
    const fs::path disk = work_ / "disk";
    fs::create_directories(disk);
    if (::mount("tmpfs", disk.c_str(), "tmpfs", 0, "size=1m") != 0)
        GTEST_SKIP() << "cannot mount a tmpfs here: " << std::strerror(errno);
    struct Unmount {
        fs::path p;
        ~Unmount() { ::umount2(p.c_str(), MNT_DETACH); }
    } unmount{disk};
    ASSERT_TRUE(octtest::writeFile(disk / "out.png", kKeep));
    RunResult r = run({"render", kCube, "--backend", "cpu", "--max-depth", "4", "--size", "512x512",
                       "--out", (disk / "out.png").string(), "--depth", (disk / "t.npy").string()});
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("No space left"), std::string::npos) << r.err;
    EXPECT_TRUE(readFile(disk / "out.png") == kKeep);
    std::set<std::string> left;
    for (const auto& e : fs::directory_iterator(disk)) left.insert(e.path().filename());
    EXPECT_EQ(left, std::set<std::string>{"out.png"});
}

// Standard output is a stream octrace writes too: `--json -` into a full device must fail, not
// exit 0 having written nothing.
TEST_F(Outputs, FailingStandardOutputIsAnError) {
    if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
    RunOptions opt;
    opt.stdoutPath = "/dev/full";
    RunResult r = run({"info", kCube, "--json", "-"}, opt);
    EXPECT_TRUE(isOneLineError(r));
    EXPECT_NE(r.err.find("standard output"), std::string::npos) << r.err;
    r = run(plus(render(kCube), {"--out", path("o.png")}), opt);
    EXPECT_TRUE(isOneLineError(r));
}

}  // namespace
}  // namespace oct
