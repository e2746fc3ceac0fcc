// Report fields (validation/report/report.h).
#include "validation/report/report.h"

#include <gtest/gtest.h>

#include "tests/validation/fixtures.h"

namespace oct {
namespace {

TEST(Report, JsonHasThePlainFields) {
    Scene scene = loadScene(octtest::meshPath("cube_binary.ply"));
    auto t = octtest::cpuTracers(scene, {"linear"});
    ValidationReport rep =
        validateScene(scene, t.tracers, t.canonical, octtest::smallOptions(16, 300));
    nlohmann::json j = toJson(rep);
    EXPECT_EQ(j["wrong"], 0);
    EXPECT_EQ(j["ambiguous"], 0);
    EXPECT_TRUE(j["pass"].get<bool>());
    EXPECT_EQ(j["replication"]["false_negatives"], 0);
    EXPECT_EQ(j["replication"]["octree_faces"], rep.replication->octreeFaces);
    EXPECT_EQ(j["replication"]["range_errors"], 0);
    EXPECT_TRUE(j["replication"]["structural_errors"].empty());
    EXPECT_EQ(j["runs"][0]["layout"], "linear");
    EXPECT_EQ(j["runs"][0]["primary"]["compared"], 256);
    EXPECT_EQ(j["runs"][0]["rays"]["compared"], 300);
    EXPECT_TRUE(j["runs"][0]["rays"]["by_set"].contains("axis"));
    EXPECT_EQ(j["runs"][0]["rays"]["by_set"]["axis"]["rows"], 100);
    EXPECT_EQ(j["ray_set"]["around"], 100);
    EXPECT_EQ(j["policy"]["max_ambiguous_rate"], rep.policy.maxAmbiguousRate);
    EXPECT_NE(humanSummary(rep).find("PASS"), std::string::npos);
}

}  // namespace
}  // namespace oct
