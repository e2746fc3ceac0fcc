// Each ray set's own bound on ambiguous answers (validation/ambiguity_bound.h), as issue 24 met
// it: a tracer that turns right answers at a range end into excused ones passed every ray, and
// certify with it (62 % more ambiguous answers in tmin-tmax on the Cornell box). Here the faults
// are made on octrace's own answers to the standard rays of octrace rays (whose manifest records
// what octrace's kernel scores on them): a hit exactly at tmax dropped, tmin taken as exclusive.
// Every corrupted row alone is ambiguous, none wrong: only the set's count can fail them.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "backends/backend_list.h"
#include "core/octree/built_scene.h"
#include "core/octree/layout_registry.h"
#include "core/scene/load_scene.h"
#include "tests/paths.h"
#include "validation/certify.h"
#include "validation/rays/standard_rays.h"
#include "validation/report/report.h"

namespace oct {
namespace certify_bound {
namespace {

using octtest::meshPath;

// The standard rays of `octrace rays SCENE --count COUNT --size 32x32`, small enough for a test.
StandardRays smallStandardRays(const Scene& scene, uint64_t count = 4000) {
    RaySetSpec spec;
    std::vector<std::string> notes;
    spec.sets = chooseRaySets("all", scene, notes);
    spec.count = count;
    spec.seed = 1;
    spec.camera.width = spec.camera.height = 32;
    return makeStandardRays(scene, spec, "the test's rays", "fewer rays");
}

HitArrays trace(const Scene& scene, const LayoutDesc& layout, const std::vector<float>& rows) {
    const BuiltScene built = buildScene(scene, layout, LayoutOptions{});
    HitArrays h;
    const uint64_t n = rows.size() / 8;
    h.t.resize(n);
    h.prim.resize(n);
    traceWith(hostBackend(), built, {rows.data(), h.t.data(), h.prim.data(), n});
    return h;
}

struct TminTmaxFaults : ::testing::Test {
    Scene scene = loadScene(meshPath("cornell_box.obj"));  // the mesh
    StandardRays made = smallStandardRays(scene, 9000);    // 1000 rows a seeded set
    const RaySet& rays = made.rays;
    HitArrays good = trace(scene, findLayout(kDefaultLayout), rays.rays);
    ValidationPolicy policy;
    CertifyReport base = certifyTracer(scene, rays, good, policy);
    const RaySetRange& set = *rays.find("tmin-tmax");

    // The tmin-tmax rows octrace answers right (agree with the reference) with a hit at `end`
    // of the ray's range (6 tmin, 7 tmax) exactly.
    std::vector<uint64_t> rightAtRangeEnd(int end) const {
        std::vector<uint64_t> rows;
        for (uint64_t i = set.begin; i < set.begin + set.count; ++i)
            if (base.result.rayClass[i] == uint8_t(HitClass::Agree) && good.prim[i] >= 0 &&
                good.t[i] == rays.rays[8 * i + end])
                rows.push_back(i);
        return rows;
    }
    const SetCertification& tminTmax(const CertifyReport& r) const {
        for (const SetCertification& s : r.result.sets)
            if (s.range.name == "tmin-tmax") return s;
        throw std::logic_error("no tmin-tmax set");
    }
};

TEST_F(TminTmaxFaults, OctracesOwnAnswersPass) { EXPECT_TRUE(base.passes()) << humanSummary(base); }

// A tracer testing t < tmax where the format says t <= tmax: every right hit exactly at tmax
// becomes a miss, which the policy excuses ray by ray (range_end).
TEST_F(TminTmaxFaults, RightHitsExactlyAtTmaxDroppedFail) {
    ASSERT_TRUE(base.passes()) << humanSummary(base);
    const std::vector<uint64_t> rows = rightAtRangeEnd(7);
    // A fault the count can see: a third more ambiguous answers than octrace's own.
    ASSERT_GT(rows.size(), tminTmax(base).counts.ambiguous / 3);
    HitArrays bad = good;
    for (uint64_t i : rows) {
        bad.t[i] = INFINITY;
        bad.prim[i] = -1;
    }
    const CertifyReport rep = certifyTracer(scene, rays, bad, policy);
    EXPECT_EQ(rep.result.all.wrong, 0u);  // each row alone is excused
    EXPECT_EQ(tminTmax(rep).counts.ambiguous, tminTmax(base).counts.ambiguous + rows.size());
    EXPECT_EQ(rep.result.correct(policy.maxAmbiguousRate), Outcome::Fail) << humanSummary(rep);
    EXPECT_FALSE(rep.passes());
}

// A tracer taking tmin as exclusive: a right hit exactly at tmin is replaced by the next one
// beyond it (or a miss), as that tracer would report it.
TEST_F(TminTmaxFaults, RightHitsExactlyAtTminSkippedFail) {
    ASSERT_TRUE(base.passes()) << humanSummary(base);
    const std::vector<uint64_t> rows = rightAtRangeEnd(6);
    ASSERT_GT(rows.size(), tminTmax(base).counts.ambiguous / 3);
    std::vector<float> beyond;
    for (uint64_t i : rows) {
        const float* r = &rays.rays[8 * i];
        beyond.insert(beyond.end(), r, r + 8);
        beyond[beyond.size() - 2] = std::nextafter(good.t[i], INFINITY);
    }
    const HitArrays next = trace(scene, findLayout(kDefaultLayout), beyond);
    HitArrays bad = good;
    for (size_t k = 0; k < rows.size(); ++k) {
        bad.t[rows[k]] = next.t[k];
        bad.prim[rows[k]] = next.prim[k];
    }
    const CertifyReport rep = certifyTracer(scene, rays, bad, policy);
    EXPECT_EQ(rep.result.all.wrong, 0u) << humanSummary(rep);
    EXPECT_EQ(rep.result.correct(policy.maxAmbiguousRate), Outcome::Fail) << humanSummary(rep);
    EXPECT_FALSE(rep.passes());
}

// What the bound must not do: fail a correct tracer. octrace's answers, with every layout, on
// every committed mesh (and the bunny when fetched), pass with the standard rays.
TEST(CertifyBound, CorrectAnswersPassOnEveryCommittedMeshEveryLayout) {
    std::vector<std::string> paths;
    for (const std::string& name : octtest::committedMeshes()) paths.push_back(meshPath(name));
    if (std::filesystem::exists(meshPath("cache/bunny.obj")))
        paths.push_back(meshPath("cache/bunny.obj"));
    for (const std::string& path : paths) {
        const Scene scene = loadScene(path);
        const StandardRays made = smallStandardRays(scene);
        for (const LayoutDesc& layout : layouts()) {
            SCOPED_TRACE(path + " " + layout.name);
            const CertifyReport rep =
                certifyTracer(scene, made.rays, trace(scene, layout, made.rays.rays), {});
            EXPECT_TRUE(rep.passes()) << humanSummary(rep);
        }
    }
}

}  // namespace
}  // namespace certify_bound
}  // namespace oct
