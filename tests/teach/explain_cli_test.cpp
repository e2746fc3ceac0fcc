// `octrace explain` and render's teaching images through the real binary: the costs explain
// reports equal the ones `render --cost` writes for the same pixels, for every layout; bad
// pixels, rays and option combinations are one-line errors; the images are PNGs with a legend.
#include <gtest/gtest.h>
#include <stb_image.h>

#include <array>
#include <cmath>
#include <cstdio>
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
            EXPECT_EQ(j["cost"]["boxes_tested"].get<int64_t>(), c[2 * i]) << x << "," << y;
            EXPECT_EQ(j["cost"]["prims_tested"].get<int64_t>(), c[2 * i + 1]) << x << "," << y;
        }
    }
}

TEST(ExplainCli, TextNamesTheStepsTheHitAndTheCost) {
    TempDir dir("explain_text");
    RunResult r = runOctrace({"explain", kTeapot, "--size", "32x32"}, dir.path());
    ASSERT_EQ(r.status, 0) << show(r);
    EXPECT_NE(r.out.find("pixel (16, 16) of 32x32"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("  box    1 "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("  enter  1 "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(" nodes entered, "), std::string::npos) << r.out;
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

// Item (hostile input, third round): explain took rays trace refuses and answered them wrong
// in silence. A direction of 1.9e19 overflowed its float normalisation (a miss with NaN points,
// exit 0, where the ray hits primitive 156 at t 50.92); origins beyond +-8e11 were traced (z =
// 1e12 "hit" at the point (0,0,0)); 1e-25 was refused as a zero direction, not by trace's rule.
TEST(ExplainCli, RaysTraceRefusesAreRefusedByTracesRule) {
    TempDir dir("explain_range");
    struct Bad {
        const char* ray;
        const char* says;
    };
    const Bad cases[] = {
        {"0,0,60,0,0,-1.9e19",
         "the direction's largest component 1.9e+19 is outside [1e-19, 1e+19]"},
        {"0,0,60,0,0,-1e30", "the direction's largest component 1e+30 is outside"},
        {"0,0,1e12,0,0,-1", "origin component 1e+12 is not finite or beyond +-8e+11"},
        {"0,0,1e30,0,0,-1", "origin component 1e+30 is not finite or beyond +-8e+11"},
        {"0,0,60,0,0,-1e-25", "the direction's largest component 1e-25 is outside [1e-19, 1e+19]"},
    };
    for (const Bad& b : cases) {
        RunResult r = runOctrace({"explain", kTeapot, "--ray", b.ray}, dir.path());
        EXPECT_TRUE(isOneLineError(r)) << b.ray;
        EXPECT_NE(r.err.find("--ray"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find(std::string("'") + b.ray + "'"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find(b.says), std::string::npos) << r.err;
    }
}

// A number numpy.float32 would not read is not read here either: a trailing comma (one more,
// empty, number) and hexadecimal floats were accepted; "inf" for tmax stays, as numpy reads it.
TEST(ExplainCli, RayTextNumpyWouldNotReadIsRefused) {
    TempDir dir("explain_text");
    for (const char* ray : {"0,0,60,0,0,-1,", "0,0,60,0,0,-0x1p0", ",0,0,60,0,0,-1"}) {
        RunResult r = runOctrace({"explain", kTeapot, "--ray", ray}, dir.path());
        EXPECT_TRUE(isOneLineError(r)) << ray;
        EXPECT_NE(r.err.find("six or eight numbers"), std::string::npos) << r.err;
    }
    RunResult r = runOctrace({"explain", kTeapot, "--ray", "0,0,60,0,0,-1,0,inf"}, dir.path());
    EXPECT_EQ(r.status, 0) << show(r);
}

// The band's ends are explained as trace traces them: the same hit, t a distance.
TEST(ExplainCli, DirectionsAtTheBandsEndsHitAsAUnitDirectionDoes) {
    TempDir dir("explain_band");
    for (const char* dz : {"-1e-19", "-1", "-1e19"}) {
        RunResult r = runOctrace(
            {"explain", kTeapot, "--ray", std::string("0,0,60,0,0,") + dz, "--json", "-"},
            dir.path());
        ASSERT_EQ(r.status, 0) << show(r);
        const nlohmann::json hit = nlohmann::json::parse(r.out)["rays"][0]["hit"];
        ASSERT_TRUE(hit.is_object()) << dz << ": a miss\n" << r.out.substr(0, 2000);
        EXPECT_EQ(hit["prim"].get<int>(), 156) << dz;
        EXPECT_NEAR(hit["t"].get<double>(), 50.92, 0.01) << dz;
        for (const auto& c : hit["point"]) EXPECT_TRUE(c.is_number()) << dz << ": " << hit;
    }
}

// A float as the text trace's numpy rows and explain's --ray share: "inf", "nan", or %.9g
// (which reads back as the same float).
std::string floatText(float v) {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char b[32];
    std::snprintf(b, sizeof b, "%.9g", double(v));
    return b;
}

// explain refuses a ray iff trace refuses the one-row ray file holding it, with trace's words,
// and where both take it they hit the same primitive, explain's t (a distance) being trace's
// (in units of the direction) times the direction's length. The rows sit on both sides of each
// bound of the rule (core/io/ray_file.h, rayRowProblem).
TEST(ExplainCli, RefusesExactlyWhatTraceRefusesAndHitsWhatTraceHits) {
    TempDir dir("explain_as_trace");
    const float inf = INFINITY, nan = NAN;
    const std::vector<std::array<float, 8>> rows = {
        {0, 0, 60, 0, 0, -1, 0, inf},          // hits 156 at 50.92
        {0, 0, 8e11f, 0, 0, -1, 0, inf},       // the origin's bound
        {0, 0, 8.0001e11f, 0, 0, -1, 0, inf},  //   just past it
        {-8e11f, 0.5f, 1, 1, 0, 0, 0, inf},    //   and on the negative side
        {-8.0001e11f, 0.5f, 1, 1, 0, 0, 0, inf},
        {0, 0, 60, 0, 0, -1e-19f, 0, inf},       // the direction's lower bound
        {0, 0, 60, 0, 0, -0.99e-19f, 0, inf},    //   just below it
        {0, 0, 60, 0, 1e-21f, -1e-19f, 0, inf},  //   a tiny component beside it
        {0, 0, 60, 0, 0, -1e19f, 0, inf},        // the upper bound
        {0, 0, 60, 0, 0, -1.01e19f, 0, inf},     //   just above it
        {0, 0, 60, 0, 0, -2, 0, inf},            // t in units of the direction
        {0, 0, 60, 0, 0, -2, 27.5f, inf},        // tmin past the first hit (distance 55)
        {0, 0, 60, 0, 0, -1, -0.0f, inf},        // tmin -0 is 0
        {0, 0, 60, 0, 0, -1, -1e-30f, inf},      // tmin < 0
        {0, 0, 60, 0, 0, -1, 10, 10},            // tmax = tmin
        {0, 0, 60, 0, 0, -1, 10, 9.99f},         // tmax < tmin
        {0, 0, 60, 0, 0, -2, 0, 25},             // tmax before the hit (distance 50)
        {nan, 0, 60, 0, 0, -1, 0, inf},          // NaN anywhere
        {0, 0, 60, 0, nan, -1, 0, inf},
        {0, 0, 60, 0, 0, -1, nan, inf},
        {0, 0, 60, 0, 0, -1, 0, nan},
        {0, 0, inf, 0, 0, -1, 0, inf},  // infinities
        {0, 0, 60, 0, 0, -inf, 0, inf},
        {0, 0, 60, 0, 0, -1, inf, inf},
    };
    int accepted = 0, refused = 0;
    for (const std::array<float, 8>& row : rows) {
        // The six-number form where tmin and tmax are its defaults, 0 and +inf.
        const bool defaults = row[6] == 0.0f && !std::signbit(row[6]) && row[7] == inf;
        std::string text;
        for (int k = 0; k < (defaults ? 6 : 8); ++k)
            text += (k ? "," : "") + floatText(row[size_t(k)]);
        SCOPED_TRACE(text);
        const std::string npy = dir.str("row.npy");
        writeNpy(npy, "<f4", {1, 8}, row.data(), 4);
        const RunResult t = runOctrace({"trace", kTeapot, "--rays", npy, "--out", dir.str("hits"),
                                        "--backend", "cpu", "--accel", "linear"},
                                       dir.path());
        const RunResult e = runOctrace(
            {"explain", kTeapot, "--accel", "linear", "--ray", text, "--json", "-"}, dir.path());
        if ((t.status == 0) != (e.status == 0)) {
            ADD_FAILURE() << "trace: " << show(t) << "explain: " << show(e);
            continue;
        }
        if (t.status != 0) {
            ++refused;
            EXPECT_TRUE(isOneLineError(e));
            const size_t rule = t.err.find("row 0: ");
            ASSERT_NE(rule, std::string::npos) << t.err;
            EXPECT_NE(e.err.find(t.err.substr(rule + 7)), std::string::npos)
                << "trace: " << t.err << "explain: " << e.err;
            continue;
        }
        ++accepted;
        const NpyArray tFile = readNpy(dir.str("hits.t.npy"));
        const NpyArray primFile = readNpy(dir.str("hits.prim.npy"));
        float traceT;
        int32_t tracePrim;
        std::memcpy(&traceT, tFile.data.data(), 4);
        std::memcpy(&tracePrim, primFile.data.data(), 4);
        const nlohmann::json hit = nlohmann::json::parse(e.out)["rays"][0]["hit"];
        const int explainPrim = hit.is_null() ? -1 : hit["prim"].get<int>();
        EXPECT_EQ(explainPrim, tracePrim);
        if (tracePrim < 0 || explainPrim < 0) continue;
        const double length =
            std::sqrt(double(row[3]) * row[3] + double(row[4]) * row[4] + double(row[5]) * row[5]);
        EXPECT_NEAR(hit["t"].get<double>(), double(traceT) * length,
                    1e-5 * double(traceT) * length);
    }
    EXPECT_GE(accepted, 8);  // both sides of every bound were met
    EXPECT_GE(refused, 12);
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
