// The malformed-scene corpus (tests/data/bad/manifest.txt) through the `octrace` binary, as a
// user meets it: every file ends in exit status 1 with exactly one line "octrace: error: ..."
// on stderr naming the file, or in exit status 0 with the expected drop count printed; never a
// signal, never more than a few seconds. And a failed render leaves no output behind and an
// existing output untouched.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/bad_manifest.h"
#include "tests/cli_harness.h"

namespace {

namespace fs = std::filesystem;

using octtest::BadFile;
using octtest::kBadDir;
using octtest::RunResult;
const auto readManifest = octtest::readBadManifest;

RunResult runOctrace(const std::vector<std::string>& args, const fs::path& dir,
                     double timeoutSeconds = 20.0) {
    octtest::RunOptions opt;
    opt.timeoutSeconds = timeoutSeconds;
    return octtest::runOctrace(args, dir, opt);
}

class CliDir : public ::testing::Test {
protected:
    void SetUp() override {
        static std::atomic<int> counter{0};
        dir_ = fs::temp_directory_path() /
               ("octrace_bad_cli_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }
    fs::path dir_;
};

// The one-line error contract of the CLI.
void expectOneLineError(const RunResult& r, const std::string& path, const std::string& text) {
    ASSERT_FALSE(r.timedOut) << "killed after " << r.seconds << " s";
    ASSERT_EQ(r.signal, 0) << "ended by signal " << r.signal << "; stderr: " << r.err;
    EXPECT_EQ(r.status, 2) << r.err;  // kExitError: bad input
    EXPECT_EQ(r.err.rfind("octrace: error: ", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line: " << r.err;
    EXPECT_NE(r.err.find(path), std::string::npos) << "names the file: " << r.err;
    EXPECT_NE(r.err.find(text), std::string::npos) << r.err;
}

// One corpus file through `octrace info`.
void checkCorpusFile(const BadFile& e, const fs::path& dir) {
    const std::string path = kBadDir + "/" + e.file;
    const RunResult r = runOctrace({"info", path}, dir);
    EXPECT_LT(r.seconds, 5.0);
    if (e.expectError) {
        expectOneLineError(r, path, e.errorText);
        return;
    }
    ASSERT_FALSE(r.timedOut);
    ASSERT_EQ(r.signal, 0) << r.err;
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_NE(r.out.find("dropped      " + std::to_string(e.totalDropped()) + " ("),
              std::string::npos)
        << r.out;
}

class BadInputCli : public CliDir {};

TEST_F(BadInputCli, EveryCorpusFileExitsWithOneLineErrorOrReportsDrops) {
    const std::vector<BadFile> entries = readManifest();
    ASSERT_GE(entries.size(), 50u) << "manifest missing or short: " << kBadDir;
    for (const BadFile& e : entries) {
        SCOPED_TRACE(e.file);
        checkCorpusFile(e, dir_);
    }
}

TEST_F(BadInputCli, MissingDirectoryAndFifoAreOneLineErrors) {
    const std::string missing = (dir_ / "nothing.obj").string();
    expectOneLineError(runOctrace({"info", missing}, dir_), missing, "No such file");
    const std::string folder = (dir_ / "folder.ply").string();
    fs::create_directories(folder);
    expectOneLineError(runOctrace({"info", folder}, dir_), folder, "directory");
    const std::string fifo = (dir_ / "pipe.stl").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    expectOneLineError(runOctrace({"info", fifo}, dir_), fifo, "not a regular file");
}

// A render that fails (here: on a bad scene) writes nothing, and leaves an existing output as
// it was; no temporary file is left beside it.
TEST_F(BadInputCli, FailedRenderLeavesNoPartialOrReplacedOutput) {
    const std::string bad = kBadDir + "/ply_truncated_binary_faces.ply";
    const fs::path png = dir_ / "out" / "image.png";
    const fs::path depth = dir_ / "out" / "depth.npy";
    fs::create_directories(png.parent_path());
    std::ofstream(png, std::ios::binary) << "previous image";
    RunResult r = runOctrace({"render", bad, "--out", png.string(), "--depth", depth.string(),
                              "--size", "16x16", "--backend", "cpu"},
                             dir_);
    expectOneLineError(r, bad, "truncated");
    EXPECT_EQ(octtest::readFile(png), "previous image");
    EXPECT_FALSE(fs::exists(depth));
    size_t entries = 0;
    for (const auto& entry : fs::directory_iterator(png.parent_path())) {
        ++entries;
        EXPECT_EQ(entry.path().filename(), "image.png") << "left behind: " << entry.path();
    }
    EXPECT_EQ(entries, 1u);
    // The same with a good scene replaces the file with a complete PNG.
    r = runOctrace({"render", std::string(OCT_SOURCE_DIR) + "/meshes/cube_binary.ply", "--out",
                    png.string(), "--size", "16x16", "--backend", "cpu"},
                   dir_);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(octtest::readFile(png).substr(1, 3), "PNG");
}

}  // namespace
