// Cost baselines of the regression set (validation/regression/cost_baseline.h,
// regression_run.h): the committed baselines are reproduced exactly by this build for every
// frame and every layout of its entry; an inflated cost fails, a small change passes, a drop is
// reported and passes, a layout without a baseline fails, one no longer listed is stale.
#include "validation/regression/cost_baseline.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <set>

#include "core/octree/layout_registry.h"
#include "tests/cli_harness.h"
#include "tests/paths.h"
#include "tests/validation/regression_fixture.h"
#include "validation/regression/regression_run.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using oct::CostReport;
using oct::CostRow;
using oct::CostTotals;
using oct::CostVerdict;
using oct::RegressionMode;

using octtest::kRoot;
using octtest::readJson;

CostReport checkCost(const std::string& manifest) {
    return *oct::runRegression(manifest, RegressionMode::Check, kRoot).cost;
}

TEST(CostBaseline, CommittedBaselinesAreReproducedExactly) {
    const CostReport r = checkCost(octtest::kRegressionManifest);
    EXPECT_TRUE(r.passes()) << oct::humanSummary(r);
    std::set<std::string> scenes, views;
    for (const CostRow& row : r.rows) {
        scenes.insert(row.scene);
        views.insert(row.view);
        // Traversal is deterministic: an unchanged build gives the same totals, not just ones
        // within the tolerance. A change here needs --update and a reason in the commit.
        EXPECT_EQ(row.verdict, CostVerdict::Same)
            << row.scene << " " << row.view << " " << row.layout << ": " << oct::humanSummary(r);
    }
    EXPECT_GE(scenes.size(), 11u);
    EXPECT_GE(views.size(), 7u);  // the traversal's order shows along each axis
}

TEST(CostBaseline, JudgeRule) {
    const CostTotals base{16384, 1000000, 200000};
    auto judge = [&](uint64_t nodes, uint64_t prims) {
        return oct::judgeCost("s", "l", base, CostTotals{16384, nodes, prims}, 0.05).verdict;
    };
    EXPECT_EQ(judge(1000000, 200000), CostVerdict::Same);
    EXPECT_EQ(judge(1050000, 200000), CostVerdict::Within);     // +5 % exactly
    EXPECT_EQ(judge(1050001, 200000), CostVerdict::Increased);  // just above
    EXPECT_EQ(judge(1000000, 210001), CostVerdict::Increased);  // prims count too
    EXPECT_EQ(judge(900000, 200000), CostVerdict::Dropped);
    EXPECT_EQ(judge(900000, 230000), CostVerdict::Increased);  // an increase outranks a drop
    EXPECT_FALSE(oct::judgeCost("s", "l", base, CostTotals{16384, 1060000, 200000}, 0.05).passes());
    EXPECT_TRUE(oct::judgeCost("s", "l", base, CostTotals{16384, 500000, 100000}, 0.05).passes());
    // No baseline for a layout of the registry fails; a baseline for none is only reported.
    EXPECT_FALSE(oct::judgeCost("s", "l", std::nullopt, base, 0.05).passes());
    EXPECT_TRUE(oct::judgeCost("s", "l", base, std::nullopt, 0.05).passes());
    // A zero baseline that became positive is an infinite increase.
    const CostRow z = oct::judgeCost("s", "l", CostTotals{16384, 0, 5}, base, 0.05);
    EXPECT_EQ(z.verdict, CostVerdict::Increased);
    EXPECT_TRUE(std::isinf(z.nodesChange));
    // Another image size is not comparable: missing.
    EXPECT_EQ(oct::judgeCost("s", "l", base, CostTotals{100, 1, 1}, 0.05).verdict,
              CostVerdict::Missing);
}

// The teapot's default frame alone, with `edit` applied to its cost baselines (by layout).
template <class Edit>
std::string teapotManifest(const octtest::TempDir& dir, Edit edit) {
    return octtest::copyRegression(dir.path(), {"teapot.obj"}, [&](json& m) {
        json& e = m["scenes"][0];
        e.erase("views");
        json f = e["frames"][0];
        ASSERT_EQ(f["view"], "default");
        edit(f["cost"]);
        e["frames"] = json::array({f});
    });
}

TEST(CostBaseline, InflatedCostFails) {
    octtest::TempDir dir("cost_inflated");
    // The build now costs 10 % more than this baseline says for the first layout of the list
    // with an octree (a deflated baseline is an inflated cost).
    std::string victim;
    for (const oct::LayoutDesc& l : oct::layouts())
        if (l.usesOctree && victim.empty()) victim = l.name;
    const std::string path = teapotManifest(dir, [&](json& layouts) {
        json& v = layouts[victim];
        v["boxes_tested"] = uint64_t(std::floor(v["boxes_tested"].get<uint64_t>() / 1.10));
    });
    const CostReport r = checkCost(path);
    EXPECT_FALSE(r.passes());
    EXPECT_EQ(r.failures(), 1u) << oct::humanSummary(r);
    for (const CostRow& row : r.rows)
        EXPECT_EQ(row.verdict, row.layout == victim ? CostVerdict::Increased : CostVerdict::Same)
            << row.layout;
    EXPECT_NE(oct::humanSummary(r).find("increased"), std::string::npos);
    EXPECT_FALSE(oct::toJson(r)["pass"].get<bool>());
}

TEST(CostBaseline, DropIsReportedAndMissingLayoutFails) {
    octtest::TempDir dir("cost_drop");
    std::string first, last;
    for (const oct::LayoutDesc& l : oct::layouts()) (first.empty() ? first : last) = l.name;
    const std::string path = teapotManifest(dir, [&](json& layouts) {
        json& v = layouts[first];
        v["prims_tested"] = v["prims_tested"].get<uint64_t>() * 2;  // now half the work
        layouts.erase(last);
        layouts["retired"] = {{"boxes_tested", 1}, {"prims_tested", 1}};
    });
    const CostReport r = checkCost(path);
    int dropped = 0, missing = 0, stale = 0;
    for (const CostRow& row : r.rows) {
        dropped += row.verdict == CostVerdict::Dropped;
        missing += row.verdict == CostVerdict::Missing;
        stale += row.verdict == CostVerdict::Stale;
    }
    EXPECT_EQ(dropped, 1);
    EXPECT_EQ(missing, 1);
    EXPECT_EQ(stale, 1);
    EXPECT_EQ(r.failures(), 1u) << oct::humanSummary(r);  // only the missing one
}

TEST(CostBaseline, UpdateRewritesTheManifest) {
    octtest::TempDir dir("cost_update");
    const std::string path = teapotManifest(dir, [](json& layouts) { layouts.clear(); });
    const CostReport u = *oct::runRegression(path, RegressionMode::Update, kRoot).cost;
    EXPECT_TRUE(u.passes());
    EXPECT_EQ(u.rows.size(), oct::layouts().size());
    for (const CostRow& row : u.rows) EXPECT_EQ(row.verdict, CostVerdict::Missing);
    const CostReport again = checkCost(path);
    EXPECT_TRUE(again.passes()) << oct::humanSummary(again);
    for (const CostRow& row : again.rows) EXPECT_EQ(row.verdict, CostVerdict::Same);
    // The same numbers as the committed manifest.
    const json mine = readJson(path)["scenes"][0]["frames"][0]["cost"];
    const json committed = readJson(octtest::kRegressionManifest);  // outlives the loop
    for (const json& s : committed["scenes"])
        if (s["scene"] == "meshes/teapot.obj" && !s.contains("name")) {
            EXPECT_EQ(mine, s["frames"][0]["cost"]);
        }
}

}  // namespace
