// The rule of docs/VALIDATION.md as users met it (validation/policy/hit_check.h): a reported hit
// lies on its primitive (without ids: on some primitive) within the surface bound, in every set,
// adversarial ones included. Reported cases, on the teapot: t moved to tmin or halved on every
// hit near an edge (once "PASS: 0 wrong, 10899 ambiguous"), camera hits at the eye, the same
// without ids, any-hit answers, the recheck cap, tolerances that are not finite.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "backends/backend_list.h"
#include "core/scene/load_scene.h"
#include "cpu_ref/embree_tracer.h"
#include "cpu_ref/render_cpu.h"
#include "tests/paths.h"
#include "validation/certify.h"
#include "validation/report/report.h"

namespace oct {
namespace certify_rule {
namespace {

// Distances in double, computed here rather than by the code under test.
double segmentDistance(DVec3 p, DVec3 a, DVec3 b) {
    const DVec3 ab = b - a;
    const double len2 = dot(ab, ab);
    const double s = len2 > 0.0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return length(p - (a + ab * s));
}

double edgeDistance(DVec3 p, const Triangle& t) {
    const DVec3 a = toDouble(t.v0), b = toDouble(t.v1), c = toDouble(t.v2);
    return std::min({segmentDistance(p, a, b), segmentDistance(p, b, c), segmentDistance(p, c, a)});
}

// To the closed triangle: its plane where p lies over its inside, else its nearest edge.
double triangleDistance(DVec3 p, const Triangle& t) {
    const DVec3 a = toDouble(t.v0), b = toDouble(t.v1), c = toDouble(t.v2);
    const DVec3 n = cross(b - a, c - a);
    const double nn = dot(n, n);
    if (nn > 0.0 && dot(cross(b - a, p - a), n) >= 0.0 && dot(cross(c - b, p - b), n) >= 0.0 &&
        dot(cross(a - c, p - c), n) >= 0.0)
        return std::fabs(dot(p - a, n)) / std::sqrt(nn);
    return edgeDistance(p, t);
}

bool isWrong(const RayCertification& r, uint64_t i, uint32_t reason) {
    return r.rayClass[i] == uint8_t(HitClass::Wrong) && (r.rayReasons[i] & reason) != 0;
}

std::string rowSays(const RayCertification& r, uint64_t i) {
    return "row " + std::to_string(i) + ": " + hitClassName(HitClass(r.rayClass[i])) + " " +
           reasonNames(r.rayReasons[i]);
}

HitArrays withoutIds(HitArrays h) {
    h.prim.clear();
    h.primIds = false;
    return h;
}

// The teapot, every standard set it takes (camera 64x64 and its shadow rays, 20,000 seeded
// rays), and the linear layout's answers, which pass. Made once for the file.
struct Teapot {
    Scene scene = loadScene(octtest::kTeapot);
    ValidationPolicy policy;
    HitClassifier classifier{scene, policy};
    RaySet rays;
    HitArrays good;

    Teapot() {
        RaySetSpec spec;
        for (const RaySetDesc& k : standardRaySets())
            if (raySetsUnavailable(scene, {&k})[0].empty()) spec.sets.push_back(&k);
        spec.count = 20000;
        spec.camera.width = spec.camera.height = 64;
        spec.truth = &classifier.truth();
        EmbreeTracer embree(scene);
        rays = makeRaySet(scene, spec, [&](RayBatchView b) { traceRaysCpu(embree.accel(), b); });
        good.t.resize(rays.count());
        good.prim.resize(rays.count());
        traceWith(hostBackend(), buildScene(scene, findLayout("linear"), LayoutOptions{}),
                  {rays.rays.data(), good.t.data(), good.prim.data(), rays.count()});
    }

    // The point of a hit at t, plainly off triangle `prim`: four surface bounds away.
    bool plainlyOff(uint64_t i, float t, int32_t prim) const {
        const Ray ray = rays.ray(i);
        return triangleDistance(classifier.hitPoint(ray, t), scene.triangles[prim]) >
               4.0 * classifier.surfaceBound(ray, prim);
    }
    // ... and off every triangle (what a check without ids can know).
    bool offEverySurface(uint64_t i, float t) const {
        const Ray ray = rays.ray(i);
        const DVec3 p = classifier.hitPoint(ray, t);
        const double reach =
            4.0 * std::max(classifier.surfaceBound(ray), classifier.truth().largestDiameter());
        bool on = false;
        classifier.truth().primitivesNear(p, reach, [&](uint32_t k) {
            on = on || triangleDistance(p, scene.triangles[k]) <=
                           4.0 * classifier.surfaceBound(ray, int32_t(k));
        });
        return !on;
    }
};

const Teapot& teapot() {
    static const Teapot t;
    return t;
}

// Test 1's corruption: every hit of ours within 1e-6 x extent of an edge of its triangle, its t
// set to the ray's tmin or halved, its primitive kept.
enum class Move { ToTmin, Halve };
struct Moved {
    HitArrays hits;
    std::vector<uint64_t> rows;     // every row moved
    std::vector<uint64_t> off;      // its new point plainly off its triangle, t in range
    std::vector<uint64_t> outside;  // its new t outside [tmin, tmax]
};

Moved moveNearEdgeHits(const Teapot& tp, Move how) {
    Moved m;
    m.hits = tp.good;
    const double near = 1e-6 * tp.classifier.extent();
    for (uint64_t i = 0; i < tp.rays.count(); ++i) {
        const int32_t prim = tp.good.prim[i];
        if (prim < 0) continue;
        const Ray ray = tp.rays.ray(i);
        const DVec3 p = tp.classifier.hitPoint(ray, tp.good.t[i]);
        if (edgeDistance(p, tp.scene.triangles[prim]) > near) continue;
        const float t = how == Move::ToTmin ? ray.tmin : 0.5f * tp.good.t[i];
        m.hits.t[i] = t;
        m.rows.push_back(i);
        if (!(t >= ray.tmin && t <= ray.tmax))
            m.outside.push_back(i);
        else if (tp.plainlyOff(i, t, prim))
            m.off.push_back(i);
    }
    return m;
}

TEST(CertifyRule, HitsNearAnEdgeMovedOffTheirTriangleAreWrongInEverySet) {
    const Teapot& tp = teapot();
    for (Move how : {Move::ToTmin, Move::Halve}) {
        SCOPED_TRACE(how == Move::ToTmin ? "t = tmin" : "t halved");
        const Moved m = moveNearEdgeHits(tp, how);
        ASSERT_GT(m.off.size(), 100u) << m.rows.size() << " rows moved";
        const CertifyReport rep = certifyTracer(tp.scene, tp.rays, m.hits, tp.policy);
        EXPECT_EQ(rep.outcome(), Outcome::Fail) << humanSummary(rep);
        EXPECT_FALSE(rep.passes());
        const RayCertification& r = rep.result;
        uint64_t caught = 0;
        for (uint64_t i : m.off) {
            caught += isWrong(r, i, kOffSurface);
            if (!isWrong(r, i, kOffSurface)) ADD_FAILURE() << rowSays(r, i);
        }
        EXPECT_EQ(caught, m.off.size());
        for (uint64_t i : m.outside) EXPECT_TRUE(isWrong(r, i, kOutsideRange)) << rowSays(r, i);
        // The adversarial sets too: their ambiguous rate is not limited, the rule is.
        for (const SetCertification& s : r.sets) {
            const uint64_t offHere = std::count_if(m.off.begin(), m.off.end(), [&](uint64_t i) {
                return i >= s.range.begin && i < s.range.begin + s.range.count;
            });
            EXPECT_GE(s.counts.wrong, offHere) << s.range.name;
        }
    }
}

// The same answers without primitive ids (certify --no-prim): every moved point that lies off
// every triangle is wrong too. Giving certify less information must not make it stricter, nor
// more: once the ids made it weaker (the moved hits passed with ids, failed without).
TEST(CertifyRule, WithoutIdsAPointOffEverySurfaceIsWrong) {
    const Teapot& tp = teapot();
    const Moved m = moveNearEdgeHits(tp, Move::Halve);
    std::vector<uint64_t> offAll;
    for (uint64_t i : m.off)
        if (tp.offEverySurface(i, m.hits.t[i])) offAll.push_back(i);
    ASSERT_GT(offAll.size(), 100u);
    const CertifyReport with = certifyTracer(tp.scene, tp.rays, m.hits, tp.policy);
    const CertifyReport without = certifyTracer(tp.scene, tp.rays, withoutIds(m.hits), tp.policy);
    EXPECT_EQ(without.outcome(), Outcome::Fail) << humanSummary(without);
    for (uint64_t i : offAll) {
        EXPECT_TRUE(isWrong(without.result, i, kOffSurface)) << rowSays(without.result, i);
        EXPECT_TRUE(isWrong(with.result, i, kOffSurface)) << rowSays(with.result, i);
    }
    // And the correct answers pass both ways.
    EXPECT_TRUE(certifyTracer(tp.scene, tp.rays, withoutIds(tp.good), tp.policy).passes());
    EXPECT_TRUE(certifyTracer(tp.scene, tp.rays, tp.good, tp.policy).passes());
}

}  // namespace
}  // namespace certify_rule
}  // namespace oct
