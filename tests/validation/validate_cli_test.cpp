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

namespace {

namespace fs = std::filesystem;

const std::string kBinary = OCT_BINARY_DIR "/octrace";
const std::string kCube = OCT_SOURCE_DIR "/meshes/cube_binary.ply";

struct RunResult {
    int status = -1;  // exit status, -1 when the process did not exit normally
    std::string out, err;
};

std::string quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

fs::path scratch(const std::string& name) {
    static int counter = 0;
    return fs::temp_directory_path() / ("octrace_validate_cli_" + std::to_string(::getpid()) + "_" +
                                        std::to_string(++counter) + "_" + name);
}

RunResult runOctrace(const std::string& args) {
    RunResult r;
    fs::path err = scratch("stderr.txt");
    std::string cmd = quote(kBinary) + " " + args + " 2>" + quote(err.string());
    FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) return r;
    char buf[4096];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
    int st = ::pclose(p);
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    std::ifstream in(err, std::ios::binary);
    r.err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    fs::remove(err);
    return r;
}

class ValidateCli : public ::testing::Test {
protected:
    void SetUp() override {
        if (!fs::exists(kBinary)) GTEST_SKIP() << "no " << kBinary << ": build target octrace";
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
    fs::path dir = scratch("meshes");
    fs::create_directories(dir);
    fs::copy_file(kCube, dir / "cube_binary.ply");
    RunResult r = runOctrace("validate --table1 --meshes " + quote(dir.string()) + " --json -");
    fs::remove_all(dir);
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

}  // namespace
