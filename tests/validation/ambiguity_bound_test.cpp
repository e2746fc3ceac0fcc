// Each set's bound on ambiguous answers (validation/ambiguity_bound.h): the limit's arithmetic,
// the baseline octrace rays records in the manifest and certify reads back, and when it does not
// apply.
#include "validation/ambiguity_bound.h"

#include <gtest/gtest.h>

#include "backends/backend_list.h"
#include "core/io/output_file.h"
#include "core/octree/built_scene.h"
#include "core/octree/layout_registry.h"
#include "core/scene/load_scene.h"
#include "tests/paths.h"
#include "validation/certify.h"
#include "validation/rays/ray_manifest.h"
#include "validation/rays/standard_rays.h"
#include "validation/report/report.h"

namespace oct {
namespace ambiguity_bound {
namespace {

TEST(AmbiguityBound, LimitIsTheBaselinePlusItsSlackPlusTheRate) {
    ValidationPolicy p;  // rate 1e-3
    EXPECT_EQ(ambiguousLimit(4000, 800, true, p), 800u + 200u + 4u);
    EXPECT_EQ(ambiguousLimit(4000, 800, true, p, ambiguousSlack("grazing")), 800u + 800u + 4u);
    EXPECT_EQ(ambiguousSlack("tmin-tmax"), kAmbiguousSlack);
    EXPECT_EQ(ambiguousLimit(4000, 0, false, p), 4u);  // an ordinary set: the rate of its rows
    EXPECT_EQ(ambiguousLimit(4000, std::nullopt, true, p), 2000u);  // no baseline: the share
    EXPECT_FALSE(ambiguousLimit(4000, std::nullopt, false, p));     // the pooled rate only
}

struct MadeRays : ::testing::Test {
    Scene scene = loadScene(octtest::kTeapot);
    StandardRays made = make();
    HitArrays ours = trace();

    StandardRays make() const {
        RaySetSpec spec;
        std::vector<std::string> notes;
        spec.sets = chooseRaySets("around,grazing,tmin-tmax", scene, notes);
        spec.count = 1500;
        return makeStandardRays(scene, spec, "the test's rays", "fewer rays");
    }
    HitArrays trace() const {
        const BuiltScene built = buildScene(scene, findLayout(kDefaultLayout), LayoutOptions{});
        const uint64_t n = made.rays.count();
        HitArrays h;
        h.t.resize(n);
        h.prim.resize(n);
        traceWith(hostBackend(), built, {made.rays.rays.data(), h.t.data(), h.prim.data(), n});
        return h;
    }
};

TEST_F(MadeRays, OctracesOwnAnswersScoreTheBaselineExactly) {
    ASSERT_TRUE(made.rays.baseline);
    const AmbiguityBaseline& b = *made.rays.baseline;
    ASSERT_EQ(b.ambiguous.size(), made.rays.sets.size());
    EXPECT_GT(b.ambiguous[2], 0u);  // tmin-tmax: range ends decided otherwise than Embree
    const CertifyReport rep = certifyTracer(scene, made.rays, ours, ValidationPolicy{});
    EXPECT_TRUE(rep.passes()) << humanSummary(rep);
    for (size_t i = 0; i < rep.result.sets.size(); ++i) {
        const SetCertification& s = rep.result.sets[i];
        EXPECT_EQ(s.expectedAmbiguous, b.ambiguous[i]) << s.range.name;
        EXPECT_EQ(s.ambiguousCounted, b.ambiguous[i]) << s.range.name;
        EXPECT_EQ(s.ambiguousLimit,
                  ambiguousLimit(s.range.count, b.ambiguous[i], s.adversarial, ValidationPolicy{},
                                 ambiguousSlack(s.range.name)));
    }
}

TEST_F(MadeRays, TheManifestKeepsTheBaselineAndRefusesACountAboveItsSet) {
    const nlohmann::json j = toJson(made.manifest);
    ASSERT_TRUE(j.contains("expected_ambiguous"));
    const RayManifest back = manifestFromJson(j, "R.json");
    ASSERT_TRUE(back.baseline);
    EXPECT_EQ(back.baseline->ambiguous, made.rays.baseline->ambiguous);
    EXPECT_EQ(back.baseline->tracer, made.rays.baseline->tracer);
    nlohmann::json tooMany = j;
    tooMany["expected_ambiguous"]["by_set"]["grazing"] = made.rays.find("grazing")->count + 1;
    EXPECT_THROW(manifestFromJson(tooMany, "R.json"), IoError);
    nlohmann::json missing = j;
    missing["expected_ambiguous"]["by_set"].erase("around");
    EXPECT_THROW(manifestFromJson(missing, "R.json"), IoError);
    nlohmann::json older = j;  // written before the field: no baseline, still a manifest
    older.erase("expected_ambiguous");
    EXPECT_FALSE(manifestFromJson(older, "R.json").baseline);
}

// Counts judged by other tolerances do not bound this run: the adversarial sets fall back to
// the fixed share, and the report says so.
TEST_F(MadeRays, ABaselineOfOtherTolerancesIsNotApplied) {
    ValidationPolicy wider;
    wider.edgeTolerance = 4e-6;
    const CertifyReport rep = certifyTracer(scene, made.rays, ours, wider);
    EXPECT_TRUE(rep.result.baselineIgnored);
    for (const SetCertification& s : rep.result.sets) {
        EXPECT_FALSE(s.expectedAmbiguous) << s.range.name;
        EXPECT_EQ(s.ambiguousLimit.has_value(), s.adversarial) << s.range.name;
    }
}

}  // namespace
}  // namespace ambiguity_bound
}  // namespace oct
