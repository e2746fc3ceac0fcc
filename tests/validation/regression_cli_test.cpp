// `octrace validate --regression FILE` as a user runs it from the repository root: PASS (exit 0,
// `golden` and `cost_baseline` in the JSON) on the committed manifest, FAIL (exit 1, one error
// line) on an altered image or an inflated cost, --update rewrites, --regression-add adds.
// Skipped without the octrace binary of the same build.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "backends/backend_list.h"
#include "core/io/output_file.h"
#include "core/octree/layout_registry.h"
#include "tests/cli_harness.h"
#include "tests/json_file.h"
#include "tests/validation/regression_fixture.h"
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

// A manifest of the committed entry `name`, its default view alone, and its image, in `to`.
std::string copyOne(const fs::path& to, const std::string& name) {
    return octtest::copyRegression(to, {name}, [](json& m) {
        json& e = m["scenes"][0];
        e.erase("views");
        e["frames"] = json::array({e["frames"][0]});
    });
}

class RegressionCli : public ::testing::Test {
protected:
    void SetUp() override {
        if (!fs::exists(octtest::octraceBinary()))
            GTEST_SKIP() << "no " << octtest::octraceBinary() << ": build target octrace";
    }
};

TEST_F(RegressionCli, CommittedFilesPass) {
    RunResult r =
        run({"validate", "--regression", "tests/data/regression/regression.json", "--json", "-"});
    ASSERT_EQ(r.status, 0) << r.err;
    json j;
    ASSERT_NO_THROW(j = json::parse(r.out)) << r.out;
    EXPECT_TRUE(j["pass"].get<bool>());
    EXPECT_EQ(j["format"], "octrace-validate-report");
    EXPECT_EQ(j["version"], 2);  // 2: cost rows in boxes_tested, prims_tested
    EXPECT_TRUE(j["golden"]["pass"].get<bool>());
    EXPECT_TRUE(j["cost_baseline"]["pass"].get<bool>());
    EXPECT_NE(r.err.find("golden "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("cost "), std::string::npos) << r.err;
}

TEST_F(RegressionCli, AlteredImageAndInflatedCostFail) {
    octtest::TempDir dir("regression_cli_bad");
    // One image, altered: 40 pixels off by 3 levels.
    const std::string manifest = copyOne(dir.path(), "cube_binary.ply");
    int w = 0, h = 0;
    std::vector<uint8_t> rgb = oct::readPngRgb(dir.str("cube_binary.ply.png"), w, h);
    const std::vector<uint8_t> committed = rgb;
    for (int i = 0; i < 40; ++i) {
        uint8_t& v = rgb[3 * size_t(i * 300)];
        v = uint8_t(v >= 3 ? v - 3 : v + 3);
    }
    oct::writePng(dir.str("cube_binary.ply.png"), w, h, rgb);
    RunResult r = run({"validate", "--regression", manifest});
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("FAIL"), std::string::npos) << r.out;
    EXPECT_NE(r.err.find("validation FAILED"), std::string::npos) << r.err;
    EXPECT_TRUE(octtest::isOneLineVerdict(r, 1));
    oct::writePng(dir.str("cube_binary.ply.png"), w, h, committed);

    // The cost of the cube's layouts, baselines halved: the build costs twice as much.
    json m = readJson(manifest);
    for (auto& [name, v] : m["scenes"][0]["frames"][0]["cost"].items())
        v["prims_tested"] = v["prims_tested"].get<uint64_t>() / 2;
    std::ofstream(manifest) << m.dump(2);
    r = run({"validate", "--regression", manifest, "--json", dir.str("report.json")});
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("increased"), std::string::npos) << r.out;
    EXPECT_FALSE(readJson(dir.path() / "report.json")["cost_baseline"]["pass"].get<bool>());
    EXPECT_TRUE(readJson(dir.path() / "report.json")["golden"]["pass"].get<bool>());

    // --update rewrites both and passes; a second check is clean.
    oct::writePng(dir.str("cube_binary.ply.png"), w, h, rgb);
    r = run({"validate", "--regression", manifest, "--update"});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("40 pixels changed"), std::string::npos) << r.out;
    r = run({"validate", "--regression", manifest});
    EXPECT_EQ(r.status, 0) << r.out << r.err;
}

// Adding a scene in two commands, as docs/VALIDATION.md shows: --regression-add, then the check.
TEST_F(RegressionCli, ASceneIsAddedWithItsLayoutsViewsAndSizeAndThenPasses) {
    octtest::TempDir dir("regression_cli_add");
    const std::string manifest = copyOne(dir.path(), "cube_binary.ply");
    RunResult r = run({"validate", "--regression", manifest, "--regression-add",
                       "meshes/sphere_with_hole.stl", "--regression-name", "hole", "--layouts",
                       "linear,compact", "--views", "default,-x", "--size", "48x32"});
    ASSERT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("hole-xneg.png"), std::string::npos) << r.out;
    const json e = readJson(manifest)["scenes"][1];
    EXPECT_EQ(e["name"], "hole");
    EXPECT_EQ(e["layouts"], json({"linear", "compact"}));
    EXPECT_EQ(e["height"], 32);
    r = run({"validate", "--regression", manifest, "--json", dir.str("report.json")});
    ASSERT_EQ(r.status, 0) << r.out << r.err;
    int rows = 0;
    const json report = readJson(dir.path() / "report.json");  // outlives the loop
    for (const json& row : report["golden"]["images"])
        rows += row["scene"] == "meshes/sphere_with_hole.stl";
    EXPECT_EQ(rows, 2 * 3);  // two views x (linear, compact, embree)
    // Options that only --regression-add reads, without it, are refused.
    r = run({"validate", "--regression", manifest, "--layouts", "hash"});
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_TRUE(octtest::isOneLineError(r));
    r = run({"validate", "--regression", manifest, "--regression-add",
             OCT_SOURCE_DIR "/meshes/teapot.obj"});
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("relative to the repository root"), std::string::npos) << r.err;
    r = run({"validate", "--regression", manifest, "--update", "--backend", "cpu"});
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("host backend"), std::string::npos) << r.err;
    r = run({"validate", "--regression", manifest, "--regression-add", "meshes/teapot.obj",
             "--views", "sideways"});
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("sideways"), std::string::npos) << r.err;
}

// --backend: every backend of our kernel in the list renders each image; one that cannot run
// here is reported as skipped and the verdict is INCOMPLETE (exit 3), never a pass. An altered
// image fails on every backend present.
TEST_F(RegressionCli, EveryBackendAskedForIsCheckedAndAnAbsentOneIsSkippedNotPassed) {
    octtest::TempDir dir("regression_cli_backends");
    const std::string manifest = copyOne(dir.path(), "cube_binary.ply");
    std::string list;
    std::vector<std::string> present, absent;
    for (const oct::BackendDesc& b : oct::backends()) {
        if (!b.usesLayouts) continue;
        list += (list.empty() ? "" : ",") + std::string(b.name);
        std::string why;
        (b.available(why) ? present : absent).push_back(b.name);
    }
    auto check = [&](bool altered) {
        RunResult r = run({"validate", "--regression", manifest, "--backend", list, "--json",
                           dir.str("report.json")});
        const json j = readJson(dir.path() / "report.json");
        EXPECT_EQ(r.status, altered ? 1 : absent.empty() ? 0 : 3) << r.out << r.err;
        EXPECT_FALSE(j["pass"].get<bool>() && !absent.empty());
        for (const std::string& name : present) {
            int rows = 0, failing = 0;
            for (const json& row : j["golden"]["images"])
                if (row["backend"] == name) {
                    ++rows;
                    failing += !row["pass"].get<bool>();
                }
            EXPECT_EQ(rows, int(oct::layouts().size())) << name;
            EXPECT_EQ(failing, altered ? rows : 0) << name;
        }
        ASSERT_EQ(j["skipped_backends"].size(), absent.size()) << j.dump(2);
        for (size_t i = 0; i < absent.size(); ++i) {
            EXPECT_EQ(j["skipped_backends"][i]["backend"], absent[i]);
            EXPECT_NE(r.out.find("skipped  backend " + absent[i]), std::string::npos) << r.out;
        }
    };
    check(false);
    int w = 0, h = 0;
    std::vector<uint8_t> rgb = oct::readPngRgb(dir.str("cube_binary.ply.png"), w, h);
    for (size_t i = 0; i < rgb.size(); i += 3 * 7) rgb[i] = uint8_t(rgb[i] ^ 0x40);
    oct::writePng(dir.str("cube_binary.ply.png"), w, h, rgb);
    check(true);
}

// --artifacts DIR: a failing image leaves the frame, the golden and a diff for each failing
// comparison, and index.html naming them; a pass writes nothing (unless --artifacts-always).
TEST_F(RegressionCli, AFailingImageLeavesItsFramesAndAPageAPassNothing) {
    octtest::TempDir dir("regression_cli_artifacts");
    const std::string golden = copyOne(dir.path() / "golden", "teapot.obj");
    RunResult r = run({"validate", "--regression", golden, "--artifacts", dir.str("pass")});
    ASSERT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_FALSE(fs::exists(dir.path() / "pass")) << "a pass wrote artefacts";
    r = run({"validate", "--regression", golden, "--artifacts", dir.str("asked"),
             "--artifacts-always"});
    ASSERT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_TRUE(fs::exists(dir.path() / "asked" / "index.html"));

    int w = 0, h = 0;
    const std::string teapotPng = (dir.path() / "golden" / "teapot.obj.png").string();
    std::vector<uint8_t> rgb = oct::readPngRgb(teapotPng, w, h);
    for (int y = 40; y < 50; ++y)
        for (int x = 40; x < 50; ++x) rgb[3 * size_t(y * w + x)] ^= 0x80;  // 100 pixels off
    oct::writePng(teapotPng, w, h, rgb);
    r = run({"validate", "--regression", golden, "--artifacts", dir.str("fail")});
    ASSERT_EQ(r.status, 1) << r.out << r.err;
    std::ifstream in(dir.path() / "fail" / "index.html");
    const std::string page((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (const oct::LayoutDesc& l : oct::layouts()) {
        const std::string stem = std::string("teapot.obj.png-") + l.name + "-cpu-";
        for (const char* kind : {"actual", "golden", "diff"}) {
            const fs::path png = dir.path() / "fail" / (stem + kind + ".png");
            EXPECT_TRUE(fs::exists(png)) << png;
            EXPECT_NE(page.find(stem + kind + ".png"), std::string::npos) << stem << kind;
        }
        // The diff marks exactly the pixels the rule counts, in red.
        int dw = 0, dh = 0;
        const std::vector<uint8_t> diff =
            oct::readPngRgb((dir.path() / "fail" / (stem + "diff.png")).string(), dw, dh);
        size_t red = 0;
        for (size_t p = 0; p + 2 < diff.size(); p += 3)
            red += diff[p] == 255 && diff[p + 1] == 0 && diff[p + 2] == 0;
        EXPECT_EQ(red, 100u) << l.name;
    }
    // Our kernel's rule: no pixel over 0/255.
    EXPECT_NE(page.find("100 over 0/255"), std::string::npos) << page.substr(0, 600);
}

TEST_F(RegressionCli, NothingToDoIsRefused) {
    RunResult r = run({"validate", "--update"});
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(octtest::isOneLineError(r));
    EXPECT_NE(r.err.find("--regression"), std::string::npos) << r.err;
}

}  // namespace
