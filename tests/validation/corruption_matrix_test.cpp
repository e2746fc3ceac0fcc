// One corrupted ray in an otherwise correct answer makes certify FAIL (validation/certify.h), for
// every ray set and every kind of corruption a tracer commits, on a closed mesh, an open one and
// a point cloud: t a few per cent short or long on the same primitive, a primitive far away at
// the right t, a hit lost, a miss turned into a hit. In each set the row corrupted is one where
// the corruption is plainly wrong (a point four surface bounds off its primitive, a t outside
// [tmin, tmax], a clean primitive or a sealed target left behind, a miss with nothing touchy
// near), chosen by the double truth, not by the code under test; the count of such
// (set, kind) pairs is asserted so that the test cannot pass by finding none. And 1M rays of
// octrace's own answers PASS, every mismatch rechecked (no budget turns a ray wrong).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "backends/backend_list.h"
#include "core/scene/grid_cloud.h"
#include "core/scene/load_scene.h"
#include "cpu_ref/embree_tracer.h"
#include "cpu_ref/render_cpu.h"
#include "tests/paths.h"
#include "validation/certify.h"
#include "validation/report/report.h"

namespace oct {
namespace {

// A closed mesh: an icosahedron subdivided twice (320 triangles), every vertex on the unit
// sphere, shared vertices bit-identical (a vertex per edge midpoint, made once).
Scene closedIcosphere() {
    const float a = 0.525731112f, b = 0.850650808f;
    std::vector<Vec3> v = {{-a, 0, b}, {a, 0, b},  {-a, 0, -b}, {a, 0, -b},
                           {0, b, a},  {0, b, -a}, {0, -b, a},  {0, -b, -a},
                           {b, a, 0},  {-b, a, 0}, {b, -a, 0},  {-b, -a, 0}};
    std::vector<std::array<uint32_t, 3>> f = {
        {0, 4, 1}, {0, 9, 4},  {9, 5, 4},  {4, 5, 8},  {4, 8, 1},  {8, 10, 1}, {8, 3, 10},
        {5, 3, 8}, {5, 2, 3},  {2, 7, 3},  {7, 10, 3}, {7, 6, 10}, {7, 11, 6}, {11, 0, 6},
        {0, 1, 6}, {6, 1, 10}, {9, 0, 11}, {9, 11, 2}, {9, 2, 5},  {7, 2, 11}};
    for (int level = 0; level < 2; ++level) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
        auto midpoint = [&](uint32_t i, uint32_t j) {
            const auto key = std::minmax(i, j);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            v.push_back(normalize((v[i] + v[j]) * 0.5f));
            return mid[key] = uint32_t(v.size() - 1);
        };
        std::vector<std::array<uint32_t, 3>> next;
        for (const auto& t : f) {
            const uint32_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]),
                           ca = midpoint(t[2], t[0]);
            next.push_back({t[0], ab, ca});
            next.push_back({t[1], bc, ab});
            next.push_back({t[2], ca, bc});
            next.push_back({ab, bc, ca});
        }
        f = next;
    }
    Scene s;
    s.name = "icosphere";
    s.kind = PrimKind::Triangles;
    for (const auto& t : f) {
        s.triangles.push_back({v[t[0]], v[t[1]], v[t[2]]});
        s.sourceFace.push_back(uint32_t(s.sourceFace.size()));
    }
    return s;
}

enum class Corruption { Short, Long, FarPrimitive, Lost, Phantom };
const char* name(Corruption k) {
    switch (k) {
        case Corruption::Short:
            return "t 4% short";
        case Corruption::Long:
            return "t 4% long";
        case Corruption::FarPrimitive:
            return "a far primitive";
        case Corruption::Lost:
            return "a hit lost";
        case Corruption::Phantom:
            return "a miss turned into a hit";
    }
    return "?";
}

struct Matrix {
    Scene scene;
    ValidationPolicy policy;
    HitClassifier classifier;
    RaySet rays;
    HitArrays good, ref;

    explicit Matrix(Scene s, int cameraSide = 20) : scene(std::move(s)), classifier(scene, policy) {
        RaySetSpec spec;
        for (const RaySetDesc& k : standardRaySets())
            if (raySetsUnavailable(scene, {&k})[0].empty()) spec.sets.push_back(&k);
        spec.count = 2400;
        spec.seed = 4;
        spec.camera.width = spec.camera.height = cameraSide;
        EmbreeTracer embree(scene);
        rays = makeRaySet(scene, spec, [&](RayBatchView b) { traceRaysCpu(embree.accel(), b); });
        ref.t.resize(rays.count());
        ref.prim.resize(rays.count());
        traceRaysCpu(embree.accel(),
                     {rays.rays.data(), ref.t.data(), ref.prim.data(), rays.count()});
        good = ref;
        traceWith(hostBackend(), buildScene(scene, findLayout(kDefaultLayout), LayoutOptions{}),
                  {rays.rays.data(), good.t.data(), good.prim.data(), rays.count()});
    }

    // The primitive farthest from a point.
    int32_t farthestFrom(DVec3 p) const {
        int32_t best = 0;
        double far = -1.0;
        for (uint32_t k = 0; k < scene.primitiveCount(); ++k) {
            const double d = classifier.truth().distanceTo(k, p);
            if (d > far) far = d, best = int32_t(k);
        }
        return best;
    }

    // A row that is a sealed edge, vertex or slivers target: a miss there is a leak.
    bool sealedTarget(uint64_t row) const {
        for (const RayTarget& t : rays.targets)
            if (t.row == row) return t.sealed;
        return false;
    }

    // A point plainly off a primitive, or a t outside the ray's range: wrong whatever else is
    // touchy about the ray.
    bool plainlyOff(const Ray& ray, Hit h) const {
        if (!(h.t >= ray.tmin && h.t <= ray.tmax)) return true;
        return classifier.surfaceDistance(ray, h) > 4.0 * classifier.surfaceBound(ray, h.prim);
    }

    // The corrupted answer of row i, or false when this row is not one where the corruption is
    // plainly wrong (the double truth says, with margin).
    bool corrupt(uint64_t i, Corruption k, Hit& out) const {
        const Ray ray = rays.ray(i);
        const DoubleRay dr = toDoubleRay(ray);
        const Hit g = {good.t[i], good.prim[i]};
        const DoubleTracer& truth = classifier.truth();
        switch (k) {
            case Corruption::Short:
            case Corruption::Long:
                if (g.prim < 0) return false;
                out = {g.t * (k == Corruption::Short ? 0.96f : 1.04f), g.prim};
                return plainlyOff(ray, out);
            case Corruption::FarPrimitive:
                if (g.prim < 0) return false;
                out = {g.t, farthestFrom(classifier.hitPoint(ray, g.t))};
                return plainlyOff(ray, out);
            case Corruption::Lost: {
                if (g.prim < 0) return false;
                out = {INFINITY, -1};
                if (sealedTarget(i)) return true;
                // A hit no configuration excuses missing: one clean primitive the truth meets.
                const double touch = classifier.surfaceBound(ray);
                for (const auto& [t, p] : truth.allHits(dr))
                    if (truth.touchiness(p, dr, touch) == 0) return true;
                return false;
            }
            case Corruption::Phantom: {
                if (truth.closest(dr).prim >= 0 ||
                    truth.touchinessNear(dr, classifier.surfaceBound(ray)) != 0)
                    return false;
                const float t = std::isfinite(ray.tmax) ? 0.5f * (ray.tmin + ray.tmax)
                                                        : ray.tmin + float(sceneExtent(scene));
                out = {t, 0};
                return true;
            }
        }
        return false;
    }
};

void expectEveryCorruptionFails(const Scene& scene, int minPairs) {
    Matrix m(scene);
    const RayCertification base = certifyRays(m.classifier, m.rays, m.good, m.ref);
    ASSERT_TRUE(base.passes(m.policy.maxAmbiguousRate)) << scene.name;
    int pairs = 0;
    for (const RaySetRange& s : m.rays.sets)
        for (Corruption k : {Corruption::Short, Corruption::Long, Corruption::FarPrimitive,
                             Corruption::Lost, Corruption::Phantom}) {
            Hit bad;
            uint64_t row = s.begin;
            while (row < s.begin + s.count && !m.corrupt(row, k, bad)) ++row;
            if (row == s.begin + s.count) continue;  // no row of this set fits the corruption
            HitArrays ours = m.good;
            ours.t[row] = bad.t;
            ours.prim[row] = bad.prim;
            const RayCertification r = certifyRays(m.classifier, m.rays, ours, m.ref);
            EXPECT_FALSE(r.passes(m.policy.maxAmbiguousRate))
                << scene.name << ", set " << s.name << ", row " << row << ": " << name(k);
            EXPECT_TRUE(r.rayClass[row] == uint8_t(HitClass::Wrong) ||
                        r.rayLeak[row] == uint8_t(LeakState::Leak))
                << scene.name << ", set " << s.name << ", row " << row << ": " << name(k) << ": "
                << hitClassName(HitClass(r.rayClass[row])) << " " << reasonNames(r.rayReasons[row]);
            if (k == Corruption::FarPrimitive) {
                // The right point with the wrong id: wrong, but the ray stopped on the surface,
                // so no leak (watertightness does not judge ids; the per-ray check does).
                EXPECT_EQ(r.rayClass[row], uint8_t(HitClass::Wrong)) << s.name;
                EXPECT_NE(r.rayReasons[row] & kOffSurface, 0u) << s.name;
                EXPECT_NE(r.rayLeak[row], uint8_t(LeakState::Leak)) << s.name;
            }
            // Only this row: a wrong hit on a sealed target is a leak there too, one row.
            uint64_t flagged = 0;
            for (uint64_t i = 0; i < m.rays.count(); ++i)
                flagged += r.rayClass[i] == uint8_t(HitClass::Wrong) ||
                           r.rayLeak[i] == uint8_t(LeakState::Leak);
            EXPECT_EQ(flagged, 1u) << scene.name << " " << s.name << " " << name(k);
            ++pairs;
        }
    EXPECT_GE(pairs, minPairs) << scene.name << ": too few (set, corruption) pairs tried";
}

TEST(CorruptionMatrix, ClosedMesh) { expectEveryCorruptionFails(closedIcosphere(), 36); }

TEST(CorruptionMatrix, OpenMesh) { expectEveryCorruptionFails(loadScene(octtest::kTeapot), 36); }

TEST(CorruptionMatrix, PointCloud) { expectEveryCorruptionFails(loadScene("grid:1500:3"), 24); }

// The campaign of issue 39: many rows of every set, one corrupted at a time, each one certify
// run. A t made 2 % longer or shorter on the same primitive must FAIL wherever it leaves the
// stated tolerance: outside [tmin, tmax], or farther from where the ray crosses that triangle's
// plane (in double) than the t tolerance and the float test's error bound allow. A grazing
// ray's point stays within the surface bound of its plane for a long way along the ray, so the
// point's distance alone cannot see this; the bound along the ray can. Rows where 2 % is within
// the tolerance (a hit at t ~ 0, a t the float test cannot pin down) are counted apart; every
// set with hits must have some judged, and each scene 60 corruptions a set, so the campaign
// cannot pass by skipping. A far primitive at the right t and a lost hit the truth clearly
// makes are tried on the same rows, and misses made hits where nothing near is touchy.
struct CampaignCounts {
    int judged = 0;   // corruptions that must fail (and did, or the test failed)
    int excused = 0;  // 2 % within the stated tolerance: not a wrong answer
    int nearZero = 0, illConditioned = 0;  // the excused: t ~ 0; t's float error bound > 2 %
};

// One set's rows as a ray set of their own (its targets renumbered), and the answers to them:
// certify judges each row alone, so a campaign of many runs need not re-judge the other sets.
struct OneSet {
    RaySet rays;
    HitArrays good, ref;
};
OneSet oneSet(const Matrix& m, const RaySetRange& s) {
    OneSet o;
    o.rays.rays.assign(m.rays.rays.begin() + 8 * s.begin,
                       m.rays.rays.begin() + 8 * (s.begin + s.count));
    o.rays.sets = {{s.name, 0, s.count}};
    for (RayTarget t : m.rays.targets)
        if (t.row >= s.begin && t.row < s.begin + s.count) {
            t.row -= s.begin;
            o.rays.targets.push_back(t);
        }
    for (auto [from, to] : {std::pair{&m.good, &o.good}, std::pair{&m.ref, &o.ref}}) {
        to->t.assign(from->t.begin() + s.begin, from->t.begin() + s.begin + s.count);
        to->prim.assign(from->prim.begin() + s.begin, from->prim.begin() + s.begin + s.count);
    }
    return o;
}

// `illConditioned`: a set whose rows' t the float test may get wrong by more than 2 % on every
// row tried (its error bound, hitTError, is larger), so that none need be judged there.
void expectEveryRowCorruptionFails(const Scene& scene, int rowsPerSet, uint64_t seed,
                                   const std::string& illConditioned = "") {
    Matrix m(scene, 48);
    std::mt19937_64 rng(seed);
    const DoubleTracer& truth = m.classifier.truth();
    int judged = 0;
    for (const RaySetRange& s : m.rays.sets) {
        const OneSet one = oneSet(m, s);
        ASSERT_EQ(certifyRays(m.classifier, one.rays, one.good, one.ref).all.wrong, 0u) << s.name;
        auto mustFail = [&](uint64_t row, Hit bad, const char* what) {
            HitArrays ours = one.good;
            ours.t[row - s.begin] = bad.t;
            ours.prim[row - s.begin] = bad.prim;
            const RayCertification r = certifyRays(m.classifier, one.rays, ours, one.ref);
            const uint64_t k = row - s.begin;
            EXPECT_FALSE(r.passes(m.policy.maxAmbiguousRate)) << scene.name << ", " << s.name;
            EXPECT_TRUE(r.rayClass[k] == uint8_t(HitClass::Wrong) ||
                        r.rayLeak[k] == uint8_t(LeakState::Leak))
                << scene.name << ", set " << s.name << ", row " << row << ": " << what << ": "
                << hitClassName(HitClass(r.rayClass[k])) << " " << reasonNames(r.rayReasons[k]);
            ++judged;
        };
        std::vector<uint64_t> hits, misses;
        for (uint64_t i = s.begin; i < s.begin + s.count; ++i)
            (m.good.prim[i] >= 0 ? hits : misses).push_back(i);
        std::shuffle(hits.begin(), hits.end(), rng);
        std::shuffle(misses.begin(), misses.end(), rng);
        hits.resize(std::min(hits.size(), size_t(rowsPerSet)));
        misses.resize(std::min(misses.size(), size_t(rowsPerSet / 2)));
        CampaignCounts scale;
        for (uint64_t row : hits) {
            const Ray ray = m.rays.ray(row);
            const Hit g = {m.good.t[row], m.good.prim[row]};
            // Where the ray crosses the primitive, and how far a correct float t may lie from it.
            const double tq = truth.planeCrossing(uint32_t(g.prim), toDoubleRay(ray));
            const double allowed =
                std::max(m.classifier.tTolerance(ray), m.classifier.hitTError(ray, g.prim));
            for (float f : {1.02f, 0.98f}) {
                const Hit bad = {g.t * f, g.prim};
                const bool outside = !(bad.t >= ray.tmin && bad.t <= ray.tmax);
                if (!outside && !(std::fabs(double(bad.t) - tq) > allowed)) {
                    ++scale.excused;
                    // Why: a t of about 0 (the policy's t tolerance), or a t the float test
                    // cannot pin down to 2 % (its error bound).
                    (allowed > m.classifier.tTolerance(ray) ? scale.illConditioned
                                                            : scale.nearZero)++;
                    continue;
                }
                ++scale.judged;
                mustFail(row, bad, f > 1.0f ? "t 2% long" : "t 2% short");
            }
            Hit bad;
            for (Corruption k : {Corruption::FarPrimitive, Corruption::Lost})
                if (m.corrupt(row, k, bad)) mustFail(row, bad, name(k));
        }
        for (uint64_t row : misses) {
            Hit bad;
            if (m.corrupt(row, Corruption::Phantom, bad))
                mustFail(row, bad, name(Corruption::Phantom));
        }
        // Every set with hits has t corruptions judged; those within the tolerance are rows
        // whose t the float test cannot pin to 2 % (grazing, slivers) or a t of about 0.
        if (!hits.empty() && s.name != illConditioned) {
            EXPECT_GT(scale.judged, 0) << scene.name << " " << s.name;
        }
        std::printf(
            "%s %-10s %zu hit rows: t +-2%% judged %d, within the tolerance %d (t ~ 0: %d, "
            "ill-conditioned: %d)\n",
            scene.name.c_str(), s.name.c_str(), hits.size(), scale.judged, scale.excused,
            scale.nearZero, scale.illConditioned);
    }
    EXPECT_GE(judged, 60 * int(m.rays.sets.size())) << scene.name << ": too few corruptions";
    std::printf("%s: %d corruptions, each one certify run, each FAIL\n", scene.name.c_str(),
                judged);
}

TEST(CorruptionCampaign, CornellBox) {
    expectEveryRowCorruptionFails(loadScene(octtest::meshPath("cornell_box.obj")), 24, 39);
}

TEST(CorruptionCampaign, Teapot) {
    expectEveryRowCorruptionFails(loadScene(octtest::kTeapot), 24, 39);
}

TEST(CorruptionCampaign, ClosedMesh) { expectEveryRowCorruptionFails(closedIcosphere(), 24, 39); }

// slivers:2000's grazing rows meet triangles down to 1e-9 thin at |cos| down to 5e-7: their t is
// ill-conditioned far beyond 2 % (hitTError), so a t 2 % off is within the tolerance there.
TEST(CorruptionCampaign, Slivers) {
    expectEveryRowCorruptionFails(loadScene("slivers:2000:1"), 24, 39, "grazing");
}

// A million and more rays of octrace's own answers, every mismatch rechecked: PASS. (The budget
// of 20,000 rechecks a set once turned the ones past it wrong.)
TEST(CorruptionMatrix, AMillionRaysOfOctracesOwnAnswersPass) {
    const Scene scene = loadScene(octtest::kTeapot);
    RaySetSpec spec;
    for (const char* n : {"camera", "around", "inside", "axis", "grazing", "tmin-tmax"})
        spec.sets.push_back(findRaySet(n));
    spec.count = 600000;
    spec.camera.width = spec.camera.height = 640;
    const RaySet rays = makeRaySet(scene, spec);
    ASSERT_GE(rays.count(), 1000000u);
    HitArrays ours;
    ours.t.resize(rays.count());
    ours.prim.resize(rays.count());
    traceWith(hostBackend(), buildScene(scene, findLayout("compact"), LayoutOptions{}),
              {rays.rays.data(), ours.t.data(), ours.prim.data(), rays.count()});
    const CertifyReport rep = certifyTracer(scene, rays, ours, ValidationPolicy{});
    EXPECT_TRUE(rep.passes()) << humanSummary(rep);
    EXPECT_EQ(rep.result.all.unverified, 0u);
    EXPECT_GT(rep.result.all.rechecked, 20000u) << "the old budget would have run out";
}

}  // namespace
}  // namespace oct
