// The figure options of `octrace explain` through the real binary: --svg (with --svg-plane),
// --svg --quadtree and --layouts-svg write standalone SVG, the same bytes on every run; their
// refusals are one-line errors naming the option, the value and what to do, and write nothing
// (neither the figure nor the other outputs of the same command).
#include <gtest/gtest.h>

#include "tests/cli_harness.h"
#include "tests/paths.h"

namespace oct {
namespace {

using namespace octtest;

using octtest::kTeapot;

bool isSvg(const std::string& text) {
    return text.rfind("<?xml", 0) == 0 &&
           text.find("<svg xmlns=\"http://www.w3.org/2000/svg\"") != std::string::npos &&
           text.size() > 7 && text.substr(text.size() - 7) == "</svg>\n";
}

TEST(SvgCli, SvgWritesTheSameFigureEveryRun) {
    TempDir dir("svg_cli");
    for (const char* plane : {"", "xz"}) {
        std::vector<std::string> args = {"explain", kTeapot, "--size", "32x24",
                                         "--pixel", "16,12", "--svg",  dir.str("a.svg")};
        if (*plane) args.insert(args.end(), {"--svg-plane", plane});
        RunResult r = runOctrace(args, dir.path());
        ASSERT_EQ(r.status, 0) << show(r);
        EXPECT_NE(r.out.find("wrote   " + dir.str("a.svg")), std::string::npos) << r.out;
        const std::string a = readFile(dir.str("a.svg"));
        EXPECT_TRUE(isSvg(a));
        EXPECT_NE(a.find("class=\"visit-number\""), std::string::npos);
        if (*plane) {
            EXPECT_NE(a.find("plane xz"), std::string::npos);
        }
        args[7] = dir.str("b.svg");
        r = runOctrace(args, dir.path());
        ASSERT_EQ(r.status, 0) << show(r);
        EXPECT_EQ(a, readFile(dir.str("b.svg"))) << "the figure is deterministic";
    }
}

TEST(SvgCli, QuadtreeDrawsAFlatScenesQuadtree) {
    TempDir dir("svg_quad");
    RunResult r = runOctrace({"explain", "slivers:8", "--ray", "-0.2,0.3,0,1,0.25,0", "--max-prims",
                              "1", "--max-depth", "4", "--svg", dir.str("q.svg"), "--quadtree"},
                             dir.path());
    ASSERT_EQ(r.status, 0) << show(r);
    EXPECT_NE(r.out.find("quadtree of"), std::string::npos) << r.out;
    const std::string q = readFile(dir.str("q.svg"));
    EXPECT_TRUE(isSvg(q));
    EXPECT_NE(q.find("class=\"qcell internal\" data-key=\"1\""), std::string::npos);
    EXPECT_NE(q.find("class=\"qvisit\""), std::string::npos);
    EXPECT_NE(q.find("keys in base 4"), std::string::npos);
}

TEST(SvgCli, LayoutsSvgDrawsTheThreeLayouts) {
    TempDir dir("svg_layouts");
    RunResult r = runOctrace({"explain", "grid:20", "--max-prims", "1", "--accel", "hash",
                              "--layouts-svg", dir.str("l.svg")},
                             dir.path());
    ASSERT_EQ(r.status, 0) << show(r);
    const std::string l = readFile(dir.str("l.svg"));
    EXPECT_TRUE(isSvg(l));
    for (const char* panel : {"(a) linear", "(b) hash", "(c) compact"})
        EXPECT_NE(l.find(panel), std::string::npos) << panel;
    EXPECT_NE(l.find("as the explained traversal made them"), std::string::npos);
}

TEST(SvgCli, RefusalsNameTheOptionAndWriteNothing) {
    TempDir dir("svg_bad");
    struct Bad {
        std::vector<std::string> args;
        std::vector<const char*> says;
    };
    const std::string svg = dir.str("f.svg"), json = dir.str("f.json");
    const Bad cases[] = {
        {{kTeapot, "--svg", svg, "--svg-plane", "xw"}, {"--svg-plane 'xw'", "xy, xz or yz"}},
        {{kTeapot, "--svg-plane", "xy"}, {"--svg-plane", "give --svg F.svg"}},
        {{kTeapot, "--quadtree"}, {"--quadtree", "give --svg F.svg"}},
        {{kTeapot, "--svg", "-"}, {"--svg", "not stdout"}},
        {{kTeapot, "--layouts-svg", "-"}, {"--layouts-svg", "not stdout"}},
        {{kTeapot, "--svg", svg, "--quadtree"}, {"--quadtree", "is not flat", "x ", "z "}},
        {{"slivers:8", "--svg", svg, "--quadtree", "--svg-plane", "yz"},
         {"--svg-plane yz", "xy plane", "give --svg-plane xy"}},
        {{"slivers:8", "--svg", svg, "--quadtree", "--ray", "0.5,0.5,1,0,0,-1"},
         {"--quadtree", "runs along z", "--ray"}},
        {{kTeapot, "--layouts-svg", svg}, {"--layouts-svg", "nodes", "lower --max-depth (now 7)"}},
    };
    for (const Bad& b : cases) {
        std::vector<std::string> args = {"explain"};
        args.insert(args.end(), b.args.begin(), b.args.end());
        args.insert(args.end(), {"--json", json});
        RunResult r = runOctrace(args, dir.path());
        EXPECT_TRUE(isOneLineError(r)) << b.says[0];
        for (const char* s : b.says) EXPECT_NE(r.err.find(s), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(svg)) << r.err;
        EXPECT_FALSE(fs::exists(json)) << "nothing written on a refusal: " << r.err;
    }
}

}  // namespace
}  // namespace oct
