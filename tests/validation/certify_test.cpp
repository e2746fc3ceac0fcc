// The certification of any tracer's hits (validation/certify.h): octrace's own answers pass on
// every committed mesh with every layout; corrupted answers are named one for one; a faulty
// tracer's output (NaN, negative t, ids out of range) is reported, never crashes; a cracked
// tracer leaks, and the leaks name their edge.
#include "validation/certify.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "backends/backend_list.h"
#include "cpu_ref/embree_tracer.h"
#include "cpu_ref/render_cpu.h"
#include "tests/validation/fixtures.h"
#include "validation/report/report.h"

namespace oct {
namespace {

using octtest::meshPath;

// Every standard set the scene takes, small: camera 24x24 with its shadow rays, 2800 seeded rays.
RaySet standardRays(const Scene& scene, uint64_t count = 2800) {
    RaySetSpec spec;
    for (const RaySetDesc& k : standardRaySets())
        if (raySetMisfit(k, scene).empty()) spec.sets.push_back(&k);
    spec.count = count;
    spec.seed = 9;
    spec.camera.width = spec.camera.height = 24;
    EmbreeTracer embree(scene);
    return makeRaySet(scene, spec, [&](RayBatchView b) { traceRaysCpu(embree.accel(), b); });
}

HitArrays traceWithLayout(const Scene& scene, const LayoutDesc& layout, const RaySet& rays) {
    BuiltScene bs = buildScene(scene, layout, LayoutOptions{});
    HitArrays h;
    h.t.resize(rays.count());
    h.prim.resize(rays.count());
    traceWith(hostBackend(), bs, {rays.rays.data(), h.t.data(), h.prim.data(), rays.count()});
    return h;
}

TEST(Certify, OctracesOwnHitsPassOnEveryCommittedMeshEveryLayout) {
    for (const std::string& name : octtest::committedMeshes()) {
        Scene scene = loadScene(meshPath(name));
        const RaySet rays = standardRays(scene);
        for (const LayoutDesc& layout : layouts()) {
            SCOPED_TRACE(name + " " + layout.name);
            CertifyReport rep = certifyTracer(scene, rays, traceWithLayout(scene, layout, rays),
                                              ValidationPolicy{});
            EXPECT_TRUE(rep.passes()) << humanSummary(rep);
            EXPECT_EQ(rep.result.all.wrong, 0u);
            EXPECT_EQ(rep.result.leaks, 0u);
            EXPECT_EQ(rep.result.all.compared, rays.count());
            EXPECT_EQ(rep.result.sets.size(), rays.sets.size());
            EXPECT_GT(rep.result.leakChecked, 0u);
        }
    }
}

TEST(Certify, AGeneratedCloudPassesToo) {
    Scene scene = makeGridCloud(2000, 3);
    const RaySet rays = standardRays(scene, 900);
    EXPECT_FALSE(rays.find("edges"));  // triangle-only sets are left out for points
    CertifyReport rep =
        certifyTracer(scene, rays, traceWithLayout(scene, findLayout("hash"), rays), {});
    EXPECT_TRUE(rep.passes()) << humanSummary(rep);
    EXPECT_FALSE(rep.topology);
}

// The fixture of the corruption tests: the teapot, its standard rays, linear's answers (which
// pass), the reference's, and rays whose answer is a clean hit: far from any edge, not grazing,
// in a non-adversarial set, the same primitive in every tracer.
struct CorruptedHits : ::testing::Test {
    Scene scene = loadScene(meshPath("teapot.obj"));
    RaySet rays = standardRays(scene);
    HitArrays good = traceWithLayout(scene, findLayout("linear"), rays);
    ValidationPolicy policy;
    HitClassifier classifier{scene, policy};

    std::vector<uint64_t> cleanHits(size_t want) {
        std::vector<uint64_t> out;
        for (const char* set : {"camera", "around"}) {
            const RaySetRange* s = rays.find(set);
            for (uint64_t i = s->begin; i < s->begin + s->count && out.size() < want; ++i) {
                if (good.prim[i] < 0) continue;
                const DoubleRay dr = toDoubleRay(rays.ray(i));
                if (classifier.truth().touchiness(uint32_t(good.prim[i]), dr) != 0) continue;
                if (classifier.truth().touchinessNear(dr) != 0) continue;
                out.push_back(i);
                i += 37;  // spread them out
            }
        }
        return out;
    }
    // A primitive far from the hit point of ray i.
    int32_t farPrimitive(uint64_t i) const {
        const Ray r = rays.ray(i);
        const Vec3 p = r.org + r.dir * good.t[i];
        int32_t best = 0;
        float far = -1.0f;
        for (uint32_t k = 0; k < scene.triangles.size(); ++k) {
            float d = length(scene.triangles[k].v0 - p);
            if (d > far) {
                far = d;
                best = int32_t(k);
            }
        }
        return best;
    }
    // The wrong findings, by row.
    std::map<uint64_t, uint32_t> wrongRows(const RayCertification& r) const {
        std::map<uint64_t, uint32_t> m;
        for (const SetCertification& s : r.sets)
            for (const Finding& f : s.worst)
                if (f.cls == HitClass::Wrong) m[f.index] = f.reasons;
        return m;
    }
};

TEST_F(CorruptedHits, EachCorruptionIsOneWrongRayNamedByRow) {
    CertifyReport base = certifyTracer(scene, rays, good, policy);
    ASSERT_TRUE(base.passes()) << humanSummary(base);
    const std::vector<uint64_t> pick = cleanHits(3);
    ASSERT_EQ(pick.size(), 3u);
    HitArrays bad = good;
    bad.t[pick[0]] = INFINITY;  // a hit turned into a miss
    bad.prim[pick[0]] = -1;
    bad.t[pick[1]] *= 1.01f;                    // t moved by 1 %
    bad.prim[pick[2]] = farPrimitive(pick[2]);  // a far primitive id at the right t
    CertifyReport rep = certifyTracer(scene, rays, bad, policy);
    EXPECT_FALSE(rep.passes());
    EXPECT_EQ(rep.result.all.wrong, 3u) << humanSummary(rep);
    EXPECT_EQ(rep.result.all.ambiguous, base.result.all.ambiguous);
    std::map<uint64_t, uint32_t> wrong = wrongRows(rep.result);
    ASSERT_EQ(wrong.size(), 3u);
    EXPECT_EQ(wrong.count(pick[0]) + wrong.count(pick[1]) + wrong.count(pick[2]), 3u);
    EXPECT_TRUE(wrong[pick[0]] & kMissedHit) << reasonNames(wrong[pick[0]]);
    // The rule: a reported point off its primitive is off_surface, whatever else holds.
    EXPECT_TRUE(wrong[pick[1]] & kOffSurface) << reasonNames(wrong[pick[1]]);
    EXPECT_TRUE(wrong[pick[2]] & kOffSurface) << reasonNames(wrong[pick[2]]);
    // The report names expected and got for each.
    nlohmann::json j = toJson(rep);
    EXPECT_FALSE(j["pass"].get<bool>());
    EXPECT_EQ(j["wrong"], 3);
    for (const nlohmann::json& f : j["result"]["by_set"]["camera"]["worst"])
        if (f["index"] == pick[0]) {
            EXPECT_EQ(f["class"], "wrong");
            EXPECT_EQ(f["ours"]["prim"], -1);
            EXPECT_EQ(f["expected"]["prim"], good.prim[pick[0]]);
        }
    EXPECT_NE(humanSummary(rep).find("FAIL"), std::string::npos);
}

TEST_F(CorruptedHits, AFaultyTracersOutputIsReportedNeverCrashes) {
    const std::vector<uint64_t> pick = cleanHits(6);
    ASSERT_EQ(pick.size(), 6u);
    HitArrays bad = good;
    bad.t[pick[0]] = NAN;
    bad.t[pick[1]] = -bad.t[pick[1]];  // negative t: outside [tmin, tmax]
    bad.prim[pick[2]] = 1000000000;    // beyond the scene
    bad.prim[pick[3]] = -7;            // below -1
    bad.prim[pick[4]] = -1;            // a "miss" that keeps its finite t
    bad.t[pick[5]] = INFINITY;         // a "hit" at +inf
    // And misses turned into garbage.
    uint64_t miss = 0;
    while (good.prim[miss] >= 0) ++miss;
    bad.t[miss] = NAN;
    bad.prim[miss] = INT32_MIN;
    CertifyReport rep = certifyTracer(scene, rays, bad, policy);
    EXPECT_EQ(rep.result.all.wrong, 7u) << humanSummary(rep);
    std::map<uint64_t, uint32_t> wrong = wrongRows(rep.result);
    for (uint64_t i : {pick[0], pick[2], pick[3], pick[4], pick[5], miss})
        EXPECT_EQ(wrong[i], uint32_t(kInvalidHit)) << i << " " << reasonNames(wrong[i]);
    EXPECT_EQ(wrong[pick[1]], uint32_t(kOutsideRange)) << reasonNames(wrong[pick[1]]);
    EXPECT_NO_THROW(toJson(rep).dump());
}

TEST_F(CorruptedHits, DistancesOnlyCertifyWithoutPrimitiveIds) {
    HitArrays noPrim = good;
    noPrim.prim.clear();
    noPrim.primIds = false;
    CertifyReport rep = certifyTracer(scene, rays, noPrim, policy);
    EXPECT_TRUE(rep.passes()) << humanSummary(rep);
    const std::vector<uint64_t> pick = cleanHits(2);
    noPrim.t[pick[0]] = INFINITY;
    noPrim.t[pick[1]] *= 1.01f;
    rep = certifyTracer(scene, rays, noPrim, policy);
    EXPECT_EQ(rep.result.all.wrong, 2u) << humanSummary(rep);
    std::map<uint64_t, uint32_t> wrong = wrongRows(rep.result);
    EXPECT_EQ(wrong.count(pick[0]) + wrong.count(pick[1]), 2u);
}

TEST_F(CorruptedHits, WrongLengthsAreRefused) {
    HitArrays shortHits = good;
    shortHits.t.pop_back();
    EXPECT_THROW(certifyTracer(scene, rays, shortHits, policy), std::invalid_argument);
    RaySet badSets = rays;
    badSets.sets.push_back({"beyond", rays.count(), 5});
    EXPECT_THROW(certifyTracer(scene, badSets, good, policy), std::invalid_argument);
}

// A closed mesh and a deliberately cracked tracer: every ray aimed at one edge comes back as a
// miss (or passes through to a later hit). Exactly those rays leak, each naming the edge.
TEST(CertifyLeaks, ACrackAtOneEdgeLeaksAndNamesTheEdge) {
    Scene scene = loadScene(meshPath("cube_binary.ply"));
    ASSERT_TRUE(meshTopology(scene).closed());
    RaySetSpec spec;
    spec.sets = {findRaySet("edges"), findRaySet("vertices")};
    spec.count = 600;
    spec.seed = 4;
    const RaySet rays = makeRaySet(scene, spec);
    HitArrays good = traceWithLayout(scene, findLayout("linear"), rays);
    CertifyReport base = certifyTracer(scene, rays, good, {});
    ASSERT_TRUE(base.passes()) << humanSummary(base);
    EXPECT_EQ(base.result.leakChecked, 600u);
    ASSERT_TRUE(base.topology && base.topology->closed);

    const RayTarget first = rays.targets[0];
    ASSERT_FALSE(first.vertex());
    HitArrays cracked = good;
    std::set<uint64_t> rows;
    for (const RayTarget& t : rays.targets)
        if (t.a == first.a && t.b == first.b) {
            rows.insert(t.row);
            cracked.t[t.row] = INFINITY;
            cracked.prim[t.row] = -1;
        }
    ASSERT_GE(rows.size(), 2u);
    // One of them goes on to a later hit instead: the far side of the cube, also a leak.
    const uint64_t through = *rows.rbegin();
    cracked.t[through] = float(rays.targets[0].t) + 1.0f;
    cracked.prim[through] = good.prim[through];

    CertifyReport rep = certifyTracer(scene, rays, cracked, {});
    EXPECT_FALSE(rep.passes());
    EXPECT_EQ(rep.result.leaks, rows.size()) << humanSummary(rep);
    EXPECT_EQ(rep.result.unsealed, 0u);
    const SetCertification& edges = rep.result.sets[0];
    ASSERT_EQ(edges.range.name, "edges");
    EXPECT_EQ(edges.leaks, rows.size());
    EXPECT_EQ(rep.result.sets[1].leaks, 0u);
    for (const LeakFinding& f : edges.leakList) {
        EXPECT_TRUE(rows.count(f.index)) << f.index;
        EXPECT_EQ(f.target.a, first.a);
        EXPECT_EQ(f.target.b, first.b);
        EXPECT_GE(f.truth.prim, 0);
    }
    nlohmann::json j = toJson(rep);
    EXPECT_EQ(j["leaks"], rows.size());
    const nlohmann::json& leak = j["result"]["by_set"]["edges"]["leak_list"][0];
    EXPECT_EQ(leak["edge"][0], first.a);
    EXPECT_EQ(leak["edge"][1], first.b);
    EXPECT_NE(humanSummary(rep).find(std::to_string(first.a) + "-" + std::to_string(first.b)),
              std::string::npos);
}

TEST(Certify, CameraSetGivesTheDiffImage) {
    Scene scene = loadScene(meshPath("cube_binary.ply"));
    RaySetSpec spec;
    spec.sets = {findRaySet("camera"), findRaySet("around")};
    spec.count = 50;
    spec.camera.width = 12;
    spec.camera.height = 8;
    const RaySet rays = makeRaySet(scene, spec);
    HitArrays hits = traceWithLayout(scene, findLayout("hash"), rays);
    uint64_t i = 0;
    while (hits.prim[i] < 0) ++i;
    hits.t[i] = INFINITY;
    hits.prim[i] = -1;
    CertifyReport rep = certifyTracer(scene, rays, hits, {});
    FilmValidation film = cameraDiff(rep.result, rays);
    EXPECT_EQ(film.width, 12);
    EXPECT_EQ(film.height, 8);
    EXPECT_EQ(film.primaryClass[i], uint8_t(HitClass::Wrong));
    RaySet noCamera = rays;
    noCamera.sets = {{"all", 0, rays.count()}};
    EXPECT_THROW(cameraDiff(certifyTracer(scene, noCamera, hits, {}).result, noCamera),
                 std::invalid_argument);
}

}  // namespace
// Camera rows off their definition (RaySet::cameraRows: a faulty camera made the file and
// rebuilds the same rows) fail the outcome whatever the answers and the --require.
TEST(Certify, CameraRowsOffTheirDefinitionFailWhateverIsRequired) {
    CertifyReport r;
    r.result.all.compared = 10;  // a correct, watertight-untested result
    for (Require q : {Require::Correct, Require::All}) {
        r.require = q;
        r.cameraRows.reset();
        EXPECT_NE(r.outcome(), Outcome::Fail);
        r.cameraRows = RayDefinitionReport{};
        r.cameraRows->judge(0.5, [] { return std::string(); });
        EXPECT_NE(r.outcome(), Outcome::Fail);
        r.cameraRows->judge(3.0, [] { return std::string("camera row 1 (pixel 1,0): off"); });
        EXPECT_EQ(r.outcome(), Outcome::Fail);
        EXPECT_TRUE(r.cameraRowsOff());
    }
}

}  // namespace oct
