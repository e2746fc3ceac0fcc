// `octrace validate` run as a user runs it: with `--json -` the JSON report is the only thing
// on stdout (the human summary goes to stderr), so it can be piped into a JSON reader; and an
// absurd `--rays` is refused with a message that names the option. Needs the octrace binary
// of the same build (cmake --build ... --target octrace); skipped without it.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/cli_harness.h"
#include "tests/paths.h"

namespace {

namespace fs = std::filesystem;

using octtest::kCube;

using octtest::quote;
using octtest::RunResult;

RunResult runOctrace(const std::string& args) {
    static octtest::TempDir capture("validate_cli");
    return octtest::runOctrace(args, capture.path());
}

class ValidateCli : public ::testing::Test {
protected:
    void SetUp() override {
        if (!fs::exists(octtest::octraceBinary()))
            GTEST_SKIP() << "no " << octtest::octraceBinary() << ": build target octrace";
    }
};

TEST_F(ValidateCli, JsonOnStdoutIsTheOnlyThingThere) {
    RunResult r = runOctrace("validate " + quote(kCube) + " --size 16x16 --rays 300 --json -");
    ASSERT_EQ(r.status, 0) << r.err;
    nlohmann::json j;
    ASSERT_NO_THROW(j = nlohmann::json::parse(r.out)) << "stdout is not JSON:\n" << r.out;
    EXPECT_TRUE(j["pass"].get<bool>());
    EXPECT_NE(r.err.find("PASS"), std::string::npos) << "the human summary goes to stderr";
    // Without --json - the summary stays on stdout.
    r = runOctrace("validate " + quote(kCube) + " --size 16x16 --rays 0 --no-replication");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("PASS"), std::string::npos) << r.out;
}

TEST_F(ValidateCli, Table1JsonOnStdoutIsTheOnlyThingThere) {
    octtest::TempDir dir("validate_cli_meshes");
    fs::copy_file(kCube, dir.path() / "cube_binary.ply");
    RunResult r =
        runOctrace("validate --table1 --meshes " + quote(dir.path().string()) + " --json -");
    ASSERT_EQ(r.status, 0) << r.err;
    nlohmann::json j;
    ASSERT_NO_THROW(j = nlohmann::json::parse(r.out)) << "stdout is not JSON:\n" << r.out;
    EXPECT_NE(r.out.find("cube_binary"), std::string::npos) << r.out;
    EXPECT_NE(r.err.find("Table 1"), std::string::npos) << r.err;
}

TEST_F(ValidateCli, RayCountIsBounded) {
    // Far beyond memory: refused up front with the option named, not a bare bad_alloc.
    RunResult r = runOctrace("validate " + quote(kCube) + " --rays 1000000000000");
    ASSERT_NE(r.status, 0);
    EXPECT_NE(r.err.find("--rays 1000000000000"), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");
    // One past the limit.
    r = runOctrace("validate " + quote(kCube) + " --rays 100000001");
    ASSERT_NE(r.status, 0);
    EXPECT_NE(r.err.find("--rays 100000001"), std::string::npos) << r.err;
}

// `--box-rays 99999999999` just ran (some 10 us a ray: 12 days). Bounded like --rays: at most
// 1e8, some 17 minutes; beyond, one line naming the bound, at once.
TEST_F(ValidateCli, BoxRayCountIsBounded) {
    octtest::TempDir capture("validate_box_rays");
    octtest::RunOptions opt;
    opt.timeoutSeconds = 20;
    for (const char* count : {"99999999999", "100000001"}) {
        RunResult r = octtest::runOctrace(
            {"validate", kCube, "--size", "8x8", "--rays", "0", "--box-rays", count},
            capture.path(), opt);
        EXPECT_TRUE(octtest::isOneLineError(r)) << count;
        EXPECT_NE(r.err.find(std::string("--box-rays: ") + count + " is not in [0, 1e+08]"),
                  std::string::npos)
            << r.err;
    }
}

// The per-pixel check holds a Film per tracer and the reference's (20 bytes a pixel each, twice
// with the inside view): at 16384x16384 that is more than a small machine has, refused with the
// figure before anything is rendered.
TEST_F(ValidateCli, ImageTooLargeForMemoryIsRefusedWithTheFigure) {
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "AddressSanitizer reserves more address space than the limit allows";
#else
    octtest::TempDir capture("validate_memory");
    octtest::RunOptions opt;
    opt.timeoutSeconds = 60;
    opt.addressSpaceLimit = uint64_t(2) << 30;
    RunResult r = octtest::runOctrace({"validate", kCube, "--size", "16384x16384", "--rays", "0"},
                                      capture.path(), opt);
    EXPECT_TRUE(octtest::isOneLineError(r));
    for (const char* says : {"--size 16384x16384", "GiB of memory", "ulimit -v"})
        EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
#endif
}

}  // namespace
