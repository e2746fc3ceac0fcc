// `octrace explain` and render's teaching images through the real binary: the costs explain
// reports equal the ones `render --cost` writes for the same pixels, for every layout; bad
// pixels, rays and option combinations are one-line errors; the images are PNGs with a legend.
#include <gtest/gtest.h>
#include <stb_image.h>

#include <cstring>
#include <nlohmann/json.hpp>

#include "core/io/npy.h"
#include "core/octree/layout_registry.h"
#include "tests/cli_harness.h"
#include "tests/paths.h"

namespace oct {
namespace {

using namespace octtest;

using octtest::kTeapot;

TEST(ExplainCli, CostsEqualRenderCostForEveryLayout) {
    TempDir dir("explain_cost");
    for (const LayoutDesc& layout : layouts()) {
        SCOPED_TRACE(layout.name);
        const std::string npy = dir.str(std::string(layout.name) + ".npy");
        RunResult r =
            runOctrace({"render", kTeapot, "--accel", layout.name, "--backend", "cpu", "--size",
                        "24x20", "--eye", "50,8,20", "--out", dir.str("r.png"), "--cost", npy},
                       dir.path());
        ASSERT_EQ(r.status, 0) << show(r);
        const NpyArray cost = readNpy(npy);
        ASSERT_EQ(cost.elementCount(), 24u * 20 * 2);
        std::vector<int32_t> c(cost.elementCount());
        std::memcpy(c.data(), cost.data.data(), cost.data.size());
        for (auto [x, y] : {std::pair{0, 0}, {12, 10}, {11, 9}, {23, 19}, {5, 14}, {17, 3}}) {
            RunResult e = runOctrace(
                {"explain", kTeapot, "--accel", layout.name, "--size", "24x20", "--eye", "50,8,20",
                 "--pixel", std::to_string(x) + "," + std::to_string(y), "--json", "-"},
                dir.path());
            ASSERT_EQ(e.status, 0) << show(e);
            const nlohmann::json j = nlohmann::json::parse(e.out);
            const size_t i = size_t(y) * 24 + x;
            EXPECT_EQ(j["cost"]["nodes"].get<int64_t>(), c[2 * i]) << x << "," << y;
            EXPECT_EQ(j["cost"]["prims"].get<int64_t>(), c[2 * i + 1]) << x << "," << y;
        }
    }
}

TEST(ExplainCli, TextNamesTheStepsTheHitAndTheCost) {
    TempDir dir("explain_text");
    RunResult r = runOctrace({"explain", kTeapot, "--size", "32x32"}, dir.path());
    ASSERT_EQ(r.status, 0) << show(r);
    EXPECT_NE(r.out.find("pixel (16, 16) of 32x32"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("  visit  1 "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("hit   primitive"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("pixel cost"), std::string::npos) << r.out;
}

TEST(ExplainCli, ARayThatMissesSaysWhere) {
    TempDir dir("explain_miss");
    RunResult r = runOctrace({"explain", kTeapot, "--ray", "100,100,100,1,0,0"}, dir.path());
    ASSERT_EQ(r.status, 0) << show(r);
    EXPECT_NE(r.out.find("misses the root box"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("Closest approach"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("slab"), std::string::npos) << r.out;
}

TEST(ExplainCli, BadPixelsRaysAndCombinationsAreOneLineErrors) {
    TempDir dir("explain_bad");
    struct Bad {
        std::vector<std::string> args;
        const char* says;
    };
    const Bad cases[] = {
        {{"--size", "64x48", "--pixel", "64,0"}, "--pixel 64,0 is outside the 64x48 image"},
        {{"--pixel", "-1,3"}, "outside"},
        {{"--pixel", "3"}, "--pixel"},
        {{"--pixel", "a,b"}, "--pixel"},
        {{"--ray", "1,2,3"}, "--ray"},
        {{"--ray", "0,0,9,0,0,0"}, "direction"},
        {{"--ray", "0,0,9,0,0,nan"}, "--ray"},
        {{"--ray", "0,0,9,0,0,-1", "--pixel", "1,1"}, "not both"},
        {{"--accel", "linear,hash"}, "--accel"},
        {{"--html", "-"}, "--html"},
    };
    for (const Bad& b : cases) {
        std::vector<std::string> args = {"explain", kTeapot};
        args.insert(args.end(), b.args.begin(), b.args.end());
        RunResult r = runOctrace(args, dir.path());
        EXPECT_TRUE(isOneLineError(r)) << b.says;
        EXPECT_NE(r.err.find(b.says), std::string::npos) << r.err;
    }
}

TEST(RenderTeach, HeatmapAndOverlayAreLabelledPngs) {
    TempDir dir("render_teach");
    const std::string heat = dir.str("heat.png"), over = dir.str("over.png");
    RunResult r = runOctrace({"render", kTeapot, "--backend", "cpu", "--size", "96x64", "--out",
                              dir.str("r.png"), "--heatmap", "prims", "--heatmap-max", "40",
                              "--heatmap-out", heat, "--overlay-out", over, "--overlay-depth", "2"},
                             dir.path());
    ASSERT_EQ(r.status, 0) << show(r);
    for (const std::string& f : {heat, over}) {
        int w = 0, h = 0, n = 0;
        ASSERT_TRUE(stbi_info(f.c_str(), &w, &h, &n)) << f;
        EXPECT_GE(w, 96);  // the legend band may be wider than the render
        EXPECT_GT(h, 64 + 30) << "no legend band under the picture";
        EXPECT_NE(r.out.find("wrote   " + f), std::string::npos) << r.out;
    }
}

TEST(RenderTeach, BadCombinationsAreRefusedBeforeRendering) {
    TempDir dir("render_teach_bad");
    const std::string out = dir.str("r.png");
    struct Bad {
        std::vector<std::string> args;
        const char* says;
    };
    const Bad cases[] = {
        {{"--heatmap", "prims"}, "--heatmap-out"},
        {{"--heatmap-out", dir.str("h.png"), "--heatmap", "rays"}, "--heatmap 'rays'"},
        {{"--heatmap-out", dir.str("h.png"), "--backend", "embree"}, "embree"},
        {{"--overlay-depth", "2"}, "--overlay-out"},
        {{"--overlay-out", dir.str("o.png"), "--overlay-depth", "21", "--max-depth", "3"},
         "--overlay-depth 21"},
        {{"--heatmap-out", dir.str("h.png"), "--heatmap-max", "0"}, "--heatmap-max"},
    };
    for (const Bad& b : cases) {
        std::vector<std::string> args = {"render", kTeapot, "--size", "32x32", "--out", out};
        args.insert(args.end(), b.args.begin(), b.args.end());
        RunResult r = runOctrace(args, dir.path());
        EXPECT_TRUE(isOneLineError(r)) << b.says;
        EXPECT_NE(r.err.find(b.says), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(out)) << "no output after an error: " << b.says;
    }
}

}  // namespace
}  // namespace oct
