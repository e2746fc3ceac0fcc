// `octrace validate --golden DIR --cost-baseline FILE` as a user runs it from the repository
// root: PASS (exit 0, `golden` and `cost_baseline` in the JSON) on the committed files, FAIL
// (exit 1, one error line) on an altered image or an inflated cost, and --update rewrites.
// Skipped without the octrace binary of the same build.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/io/output_file.h"
#include "tests/cli_harness.h"
#include "tests/json_file.h"
#include "validation/regression/golden.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using octtest::RunResult;

RunResult run(const std::vector<std::string>& args) {
    static octtest::TempDir capture("regression_cli");
    octtest::RunOptions opt;
    opt.workingDir = OCT_SOURCE_DIR;  // scene paths in the files are relative to the root
    return octtest::runOctrace(args, capture.path(), opt);
}

using octtest::readJson;

class RegressionCli : public ::testing::Test {
protected:
    void SetUp() override {
        if (!fs::exists(octtest::octraceBinary()))
            GTEST_SKIP() << "no " << octtest::octraceBinary() << ": build target octrace";
    }
};

TEST_F(RegressionCli, CommittedFilesPass) {
    RunResult r = run({"validate", "--golden", "tests/data/golden", "--cost-baseline",
                       "tests/data/cost_baselines.json", "--json", "-"});
    ASSERT_EQ(r.status, 0) << r.err;
    json j;
    ASSERT_NO_THROW(j = json::parse(r.out)) << r.out;
    EXPECT_TRUE(j["pass"].get<bool>());
    EXPECT_TRUE(j["golden"]["pass"].get<bool>());
    EXPECT_TRUE(j["cost_baseline"]["pass"].get<bool>());
    EXPECT_NE(r.err.find("golden "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("cost "), std::string::npos) << r.err;
}

TEST_F(RegressionCli, AlteredImageAndInflatedCostFail) {
    octtest::TempDir dir("regression_cli_bad");
    // One image, altered: 40 pixels off by 3 levels.
    json m = readJson(OCT_SOURCE_DIR "/tests/data/golden/golden.json");
    json kept = json::array();
    for (const json& e : m["images"])
        if (e["file"] == "cube_binary.ply.png") kept.push_back(e);
    m["images"] = kept;
    fs::create_directories(dir.path() / "golden");
    std::ofstream(dir.path() / "golden" / "golden.json") << m.dump(2);
    int w = 0, h = 0;
    std::vector<uint8_t> rgb =
        oct::readPngRgb(OCT_SOURCE_DIR "/tests/data/golden/cube_binary.ply.png", w, h);
    for (int i = 0; i < 40; ++i) {
        uint8_t& v = rgb[3 * size_t(i * 300)];
        v = uint8_t(v >= 3 ? v - 3 : v + 3);
    }
    oct::writePng((dir.path() / "golden" / "cube_binary.ply.png").string(), w, h, rgb);
    RunResult r = run({"validate", "--golden", (dir.path() / "golden").string()});
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("FAIL"), std::string::npos) << r.out;
    EXPECT_NE(r.err.find("validation FAILED"), std::string::npos) << r.err;
    EXPECT_TRUE(octtest::isOneLineVerdict(r, 1));

    // The cost of one scene's layouts, baselines halved: the build costs twice as much.
    json c = readJson(OCT_SOURCE_DIR "/tests/data/cost_baselines.json");
    json scenes = json::array();
    for (json& s : c["scenes"])
        if (s["scene"] == "meshes/cube_binary.ply") {
            for (auto& [name, v] : s["layouts"].items())
                v["prims"] = v["prims"].get<uint64_t>() / 2;
            scenes.push_back(s);
        }
    c["scenes"] = scenes;
    const std::string cost = dir.str("cost.json");
    std::ofstream(cost) << c.dump(2);
    r = run({"validate", "--cost-baseline", cost, "--json", dir.str("report.json")});
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("increased"), std::string::npos) << r.out;
    EXPECT_FALSE(readJson(dir.path() / "report.json")["cost_baseline"]["pass"].get<bool>());

    // --update rewrites both and passes; a second check is clean.
    r = run({"validate", "--golden", (dir.path() / "golden").string(), "--cost-baseline", cost,
             "--update"});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("40 pixels changed"), std::string::npos) << r.out;
    r = run({"validate", "--golden", (dir.path() / "golden").string(), "--cost-baseline", cost});
    EXPECT_EQ(r.status, 0) << r.out << r.err;
}

TEST_F(RegressionCli, NothingToDoIsRefused) {
    RunResult r = run({"validate", "--update"});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(octtest::isOneLineError(r));
    EXPECT_NE(r.err.find("--golden"), std::string::npos) << r.err;
}

}  // namespace
