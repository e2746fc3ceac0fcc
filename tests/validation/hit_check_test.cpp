// The per-ray policy (validation/policy/hit_check.h) on hand-made configurations whose right answer
// is known: a unit quad of two triangles in the plane z = 0 and a sphere.
#include "validation/policy/hit_check.h"

#include <gtest/gtest.h>

#include <cmath>

#include "validation/certify.h"

namespace oct {
namespace {

// Two triangles sharing the diagonal (0,0)-(1,1) of the unit square, plus a far small triangle
// that sets the scene's extent to about 10.
Scene quadScene() {
    Scene s;
    s.name = "quad";
    s.triangles = {{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}},
                   {{0, 0, 0}, {1, 1, 0}, {0, 1, 0}},
                   {{6, 6, -5}, {6.1f, 6, -5}, {6, 6.1f, -5}}};
    return s;
}

Ray down(float x, float y) { return {{x, y, 1}, {0, 0, -1}, 0, INFINITY}; }

struct HitCheck : ::testing::Test {
    Scene scene = quadScene();
    ValidationPolicy policy;
    HitClassifier c{scene, policy};
};

TEST_F(HitCheck, FirstStepFollowsThePolicy) {
    const Ray inside = down(0.7f, 0.2f), diagonal = down(0.5f, 0.5f);
    EXPECT_EQ(c.compare(inside, {INFINITY, -1}, {INFINITY, -1}), HitClass::Agree);
    EXPECT_EQ(c.compare(inside, {1.0f, 0}, {1.0f, 0}), HitClass::Agree);
    float tol = float(policy.tTolerance * c.extent());
    EXPECT_EQ(c.compare(inside, {1.0f, 0}, {1.0f + 0.5f * tol, 0}), HitClass::Agree);
    EXPECT_EQ(c.compare(diagonal, {1.0f, 0}, {1.0f + 0.5f * tol, 1}), HitClass::Tie);
    // The same pair of answers where triangle 1 is nowhere near the hit point: not a tie.
    EXPECT_EQ(c.compare(inside, {1.0f, 1}, {1.0f + 0.5f * tol, 0}), HitClass::Wrong);
    EXPECT_EQ(c.compare(inside, {1.0f, 0}, {1.0f + 2.0f * tol, 0}), HitClass::Wrong);  // mismatch
    EXPECT_EQ(c.compare(inside, {1.0f, 0}, {INFINITY, -1}), HitClass::Wrong);
}

TEST_F(HitCheck, MalformedHitsOfOursAreWrong) {
    const Ray inside = down(0.7f, 0.2f);
    // A NaN distance: |dt| is NaN, which a plain `> tolerance` let through as an agreement.
    Verdict v = c.closest(inside, {NAN, 0}, {1.0f, 0});
    EXPECT_EQ(v.cls, HitClass::Wrong);
    EXPECT_EQ(v.reasons, uint32_t(kInvalidHit)) << reasonNames(v.reasons);
    EXPECT_EQ(c.relativeDt({NAN, 0}, {1.0f, 0}), INFINITY) << "a NaN must not hide in a max";
    // A primitive id the scene does not have (3 primitives), at the right distance: it was a
    // tie; against a miss it reached the double tracer's arrays.
    v = c.closest(inside, {1.0f, 999}, {1.0f, 0});
    EXPECT_EQ(v.cls, HitClass::Wrong);
    EXPECT_EQ(v.reasons, uint32_t(kInvalidHit));
    EXPECT_EQ(c.closest(inside, {1.0f, 999}, {INFINITY, -1}).cls, HitClass::Wrong);
    EXPECT_EQ(c.closest(down(2.0f, 0.5f), {NAN, 2}, {INFINITY, -1}).cls, HitClass::Wrong);
    EXPECT_EQ(c.closest(inside, {INFINITY, 0}, {1.0f, 0}).cls, HitClass::Wrong);
    EXPECT_EQ(c.closest(inside, {1.0f, 3}, {1.0f, 0}).reasons, uint32_t(kInvalidHit));
    // The truth never indexes a primitive it does not have.
    double t = 0.0;
    EXPECT_FALSE(c.truth().hit(999, toDoubleRay(inside), t));
    EXPECT_EQ(c.truth().touchiness(999, toDoubleRay(inside)), 0u);
    EXPECT_EQ(c.truth().distanceTo(999, {0.7, 0.2, 0.0}), INFINITY);
}

TEST_F(HitCheck, AMalformedReferenceIsNoTie) {
    // Embree naming a primitive we do not have: ours is rechecked, found right, and the
    // reference is the one off.
    Verdict v = c.closest(down(0.7f, 0.2f), {1.0f, 0}, {1.0f, 999});
    EXPECT_EQ(v.cls, HitClass::Ambiguous);
    EXPECT_TRUE(v.reasons & kReferenceOff) << reasonNames(v.reasons);
    v = c.closest(down(0.7f, 0.2f), {1.0f, 0}, {NAN, 0});
    EXPECT_EQ(v.cls, HitClass::Ambiguous);
    EXPECT_TRUE(v.reasons & kReferenceOff) << reasonNames(v.reasons);
}

TEST_F(HitCheck, MissingAClearHitIsWrong) {
    Verdict v = c.closest(down(0.7f, 0.2f), {INFINITY, -1}, {1.0f, 0});
    EXPECT_EQ(v.cls, HitClass::Wrong);
    EXPECT_TRUE(v.rechecked);
    EXPECT_EQ(v.reasons, uint32_t(kMissedHit));
    const Hit truth = c.truthOf(down(0.7f, 0.2f), v);  // found when a report asks for it
    EXPECT_EQ(truth.prim, 0);
    EXPECT_FLOAT_EQ(truth.t, 1.0f);
    // Without the reference's hit to try first, the search finds it: the same verdict.
    Verdict alone = c.recheckClosest(down(0.7f, 0.2f), {INFINITY, -1});
    EXPECT_EQ(alone.cls, HitClass::Wrong);
    EXPECT_EQ(alone.reasons, uint32_t(kMissedHit));
}

TEST_F(HitCheck, AHitTheTruthDoesNotConfirmIsWrong) {
    Verdict v = c.closest(down(2.0f, 0.5f), {1.0f, 0}, {INFINITY, -1});  // beside the quad
    EXPECT_EQ(v.cls, HitClass::Wrong);
    EXPECT_EQ(v.truth.prim, -1);
    // Hitting the right triangle at the wrong distance is wrong too.
    v = c.closest(down(0.7f, 0.2f), {1.5f, 0}, {1.0f, 0});
    EXPECT_EQ(v.cls, HitClass::Wrong);
}

TEST_F(HitCheck, TheSharedEdgeIsATie) {
    // Through the diagonal: either triangle is right at the same t, whichever one is ours.
    Verdict v = c.closest(down(0.5f, 0.5f), {1.0f, 0}, {1.0f, 1});
    EXPECT_EQ(v.cls, HitClass::Tie);
    EXPECT_FALSE(v.rechecked);
    EXPECT_EQ(c.closest(down(0.5f, 0.5f), {1.0f, 1}, {1.0f, 0}).cls, HitClass::Tie);
    // Within float noise of the diagonal (1 ulp off it) still a tie.
    float off = std::nextafter(0.5f, 1.0f);
    EXPECT_EQ(c.closest(down(off, 0.5f), {1.0f, 1}, {1.0f, 0}).cls, HitClass::Tie);
}

TEST_F(HitCheck, AWrongPrimitiveAtTheRightDistanceIsWrong) {
    // (0.7, 0.2) is 0.35 from the diagonal, deep inside triangle 0: triangle 1 at the same t is
    // a wrong answer (it would be shaded with triangle 1's normal), not a tie.
    Verdict v = c.closest(down(0.7f, 0.2f), {1.0f, 1}, {1.0f, 0});
    EXPECT_EQ(v.cls, HitClass::Wrong) << hitClassName(v.cls) << " " << reasonNames(v.reasons);
    EXPECT_TRUE(v.rechecked);
    EXPECT_EQ(c.truthOf(down(0.7f, 0.2f), v).prim, 0);  // found when a report asks for it
    // The far triangle: the same.
    EXPECT_EQ(c.closest(down(0.7f, 0.2f), {1.0f, 2}, {1.0f, 0}).cls, HitClass::Wrong);
}

TEST_F(HitCheck, SilhouetteEdgeMismatchIsAmbiguous) {
    // A ray 1e-7 outside the quad's outer edge x = 1: we say hit, the reference says miss.
    float x = std::nextafter(1.0f, 2.0f);
    Verdict v = c.closest(down(x, 0.5f), {1.0f, 0}, {INFINITY, -1});
    EXPECT_EQ(v.cls, HitClass::Ambiguous);
    EXPECT_TRUE(v.reasons & kEdgeOrVertex) << reasonNames(v.reasons);
    // And the other way round: we miss a ray just inside the edge.
    float xi = std::nextafter(1.0f, 0.0f);
    v = c.closest(down(xi, 0.5f), {INFINITY, -1}, {1.0f, 0});
    EXPECT_EQ(v.cls, HitClass::Ambiguous);
    EXPECT_TRUE(v.reasons & kEdgeOrVertex);
    // Far enough inside the edge it is a plain miss: wrong.
    v = c.closest(down(0.99f, 0.5f), {INFINITY, -1}, {1.0f, 0});
    EXPECT_EQ(v.cls, HitClass::Wrong);
}

TEST_F(HitCheck, ClearlyOutsideAnEdgeIsWrongNotGrazing) {
    // A perpendicular ray 5e-5 outside the quad's edge x = 1 (extent about 10: the edge
    // tolerance is 2e-5, the t tolerance 1e-4). Our hit point is 5e-5 off the triangle, which
    // is sideways, not along the ray: no grazing excuse.
    ASSERT_NEAR(c.extent(), 9.97, 0.01);
    for (float dx : {3e-5f, 5e-5f, 9e-5f}) {
        Verdict v = c.closest(down(1.0f + dx, 0.5f), {1.0f, 0}, {INFINITY, -1});
        EXPECT_EQ(v.cls, HitClass::Wrong) << dx << " " << reasonNames(v.reasons);
    }
    // Within the edge tolerance it stays an edge case.
    Verdict v = c.closest(down(1.0f + 1e-5f, 0.5f), {1.0f, 0}, {INFINITY, -1});
    EXPECT_EQ(v.cls, HitClass::Ambiguous);
    EXPECT_TRUE(v.reasons & kEdgeOrVertex) << reasonNames(v.reasons);
}

TEST_F(HitCheck, OursRightReferenceOffIsAmbiguous) {
    Verdict v = c.closest(down(0.7f, 0.2f), {1.0f, 0}, {INFINITY, -1});
    EXPECT_EQ(v.cls, HitClass::Ambiguous);
    EXPECT_EQ(v.reasons, uint32_t(kReferenceOff));
}

TEST_F(HitCheck, GrazingRayIsAmbiguous) {
    // Nearly parallel to the quad (cos 1e-4): a tiny offset of the plane moves t a lot.
    Vec3 d = normalize(Vec3{1.0f, 0.0f, -1e-4f});
    Ray r = {{-0.5f, 0.3f, 1e-4f * 0.7f}, d, 0, INFINITY};
    const Hit truth = c.truth().closest(toDoubleRay(r));
    ASSERT_TRUE(std::isfinite(truth.t));
    // Our hit on the same triangle, off the truth's t by half what a float test's t may be off
    // by for this ray (hitTError), yet beyond the t tolerance: ambiguous, a grazing t.
    const double bound = c.hitTError(r, truth.prim);
    ASSERT_GT(0.5 * bound, 2.0 * c.tTolerance(r));
    Verdict v = c.closest(r, {float(truth.t + 0.5 * bound), truth.prim}, {truth.t, truth.prim});
    EXPECT_EQ(v.cls, HitClass::Ambiguous) << reasonNames(v.reasons);
    EXPECT_TRUE(v.reasons & kGrazing);
    // 0.05 along the ray, beyond that bound: the point is only 5e-6 off the plane, within the
    // surface bound across it, but not where the ray meets the triangle (issue 39: a grazing t
    // made a few per cent longer passed as ambiguous).
    const float tOff = truth.t + 0.05f;
    ASSERT_GT(0.05, 1.5 * bound);
    v = c.closest(r, {tOff, truth.prim}, {truth.t, truth.prim});
    EXPECT_EQ(v.cls, HitClass::Wrong) << reasonNames(v.reasons);
    EXPECT_EQ(v.reasons, uint32_t(kOffSurface));
    // The same point reported on the other triangle, 0.035 across the diagonal from it: off its
    // surface, whatever is touchy about the ray.
    v = c.closest(r, {tOff, 1 - truth.prim}, {truth.t, truth.prim});
    EXPECT_EQ(v.cls, HitClass::Wrong) << reasonNames(v.reasons);
    EXPECT_EQ(v.reasons, uint32_t(kOffSurface));
}

TEST_F(HitCheck, OcclusionRecheck) {
    Ray shadow = {{0.7f, 0.2f, 1}, {0, 0, -1}, 0, 2};                   // crosses the quad at t = 1
    EXPECT_EQ(c.recheckOcclusion(shadow, false).cls, HitClass::Wrong);  // we saw through it
    Verdict v = c.recheckOcclusion(shadow, true);                       // reference was off
    EXPECT_EQ(v.cls, HitClass::Ambiguous);
    EXPECT_EQ(v.reasons, uint32_t(kReferenceOff));
    Ray clear = {{2, 2, 1}, {0, 0, -1}, 0, 2};
    EXPECT_EQ(c.recheckOcclusion(clear, true).cls, HitClass::Wrong);  // a phantom occluder
    // Ending exactly on the quad: either answer is defensible.
    Ray ends = {{0.7f, 0.2f, 1}, {0, 0, -1}, 0, 1};
    v = c.recheckOcclusion(ends, false);
    EXPECT_EQ(v.cls, HitClass::Ambiguous);
    EXPECT_TRUE(v.reasons & kRangeEnd) << reasonNames(v.reasons);
}

// The same policy through the full per-ray classification (certifyRays, shared by validate and
// certify): counts, reasons and the maximum |dt|, not just the first step.
TEST_F(HitCheck, RaySetClassifiesTiesWrongPrimitivesAndMalformedHits) {
    struct Case {
        Ray ray;
        Hit ours, reference;
    };
    const std::vector<Case> cases = {
        {down(0.5f, 0.5f), {1.0f, 1}, {1.0f, 0}},  // through the shared diagonal: a tie
        {down(0.7f, 0.2f), {1.0f, 1}, {1.0f, 0}},  // the wrong triangle at the right t: wrong
        {down(0.7f, 0.2f), {NAN, 0}, {1.0f, 0}},   // a NaN distance: wrong, invalid_hit
        {down(0.3f, 0.6f), {1.0f, 1}, {1.0f, 1}},  // the same answer: agree
    };
    RaySet rays;
    HitArrays ours, ref;
    for (const Case& k : cases) {
        const Ray& r = k.ray;
        rays.rays.insert(rays.rays.end(),
                         {r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax});
        ours.t.push_back(k.ours.t);
        ours.prim.push_back(k.ours.prim);
        ref.t.push_back(k.reference.t);
        ref.prim.push_back(k.reference.prim);
    }
    rays.sets = {{"around", 0, cases.size()}};
    RayCertification v = certifyRays(c, rays, ours, ref);
    EXPECT_EQ(v.all.compared, 4u);
    EXPECT_EQ(v.all.ties, 1u);
    EXPECT_EQ(v.all.agree, 1u);
    EXPECT_EQ(v.all.wrong, 2u);
    EXPECT_EQ(v.all.ambiguous, 0u);
    EXPECT_EQ(v.all.reasons[8], 1u) << reasonName(8);  // invalid_hit
    EXPECT_STREQ(reasonName(8), "invalid_hit");
    EXPECT_EQ(v.all.maxRelativeDt, INFINITY) << "the NaN must show in max_relative_dt";
    EXPECT_FALSE(v.passes(policy.maxAmbiguousRate));
    ASSERT_GE(v.worst.size(), 2u);
    EXPECT_EQ(v.worst[0].cls, HitClass::Wrong);
    EXPECT_EQ(v.worst[1].cls, HitClass::Wrong);
}

TEST(HitCheckSpheres, TangentRayIsAmbiguousCentralMissIsWrong) {
    Scene s;
    s.name = "sphere";
    s.kind = PrimKind::Spheres;
    s.spheres = {{{0, 0, 0}, 1}, {{5, 5, 5}, 0.1f}};
    ValidationPolicy policy;
    HitClassifier c(s, policy);
    Ray tangent = {{1, 0, -3}, {0, 0, 1}, 0, INFINITY};  // touches the sphere at (1, 0, 0)
    Verdict v = c.closest(tangent, {INFINITY, -1}, {3.0f, 0});
    EXPECT_EQ(v.cls, HitClass::Ambiguous);
    EXPECT_TRUE(v.reasons & kTangent) << reasonNames(v.reasons);
    Ray central = {{0, 0, -3}, {0, 0, 1}, 0, INFINITY};
    EXPECT_EQ(c.closest(central, {INFINITY, -1}, {2.0f, 0}).cls, HitClass::Wrong);
    EXPECT_EQ(c.closest(central, {2.0f, 0}, {2.0f, 0}).cls, HitClass::Agree);
}

// A tracer returning the far root (t = 4, the back of the sphere) instead of the near one
// (t = 2): its point is on the sphere's surface, so step 1 alone cannot tell, but the truth's
// nearer hit on the same sphere is one we missed, nothing touchy about it: wrong, missed_hit.
TEST(HitCheckSpheres, FarRootIsWrongNotAmbiguous) {
    Scene s;
    s.name = "sphere";
    s.kind = PrimKind::Spheres;
    s.spheres = {{{0, 0, 0}, 1}, {{5, 5, 5}, 0.1f}};
    HitClassifier c(s, ValidationPolicy{});
    Ray central = {{0, 0, -3}, {0, 0, 1}, 0, INFINITY};
    Verdict v = c.closest(central, {4.0f, 0}, {2.0f, 0});
    EXPECT_EQ(v.cls, HitClass::Wrong) << reasonNames(v.reasons);
    EXPECT_TRUE(v.reasons & kMissedHit) << reasonNames(v.reasons);
    // From inside the sphere the far side is the right answer (the only crossing ahead).
    Ray inside = {{0, 0, 0.5f}, {0, 0, 1}, 0, INFINITY};
    EXPECT_EQ(c.closest(inside, {0.5f, 0}, {0.5f, 0}).cls, HitClass::Agree);
    EXPECT_EQ(c.recheckClosest(inside, {0.5f, 0}).cls, HitClass::Ambiguous);
}

// Far from the origin the surface bound grows with the magnitudes (kSurfaceUlps x 2^-24 x
// (|o| + M)), but no further than one unit roundoff of them: at 1e8, where an ulp is 8, a hit
// reported 12 ulps (96) off its triangle is wrong. octrace's kernel once reported this very
// one: a ray lying in the triangle's plane to within its rounding, "hit" at the plane's
// crossing (t = 0, its origin) outside the triangle. With 64 unit roundoffs (a bound of 763)
// it passed.
TEST(HitCheckFar, AHitTwelveUlpsOffItsTriangleAt1e8IsWrong) {
    auto at = [](float x, float y, float z) {
        return Vec3{1e8f + 8.0f * x, 1e8f + 8.0f * y, 1e8f + 8.0f * z};
    };
    Scene s;
    s.name = "ulp-grid";
    s.triangles = {{at(9, 6, 2), at(10, 7, 2), at(9, 7, 1)}};
    HitClassifier c(s, ValidationPolicy{});
    const Ray inPlane = {at(1, 8, -8), {0.662084699f, -0.0827605873f, 0.744845271f}, 0, INFINITY};
    const Verdict v = c.closest(inPlane, {0.0f, 0}, {INFINITY, -1});
    EXPECT_EQ(v.cls, HitClass::Wrong) << reasonNames(v.reasons);
    EXPECT_TRUE(v.reasons & kOffSurface) << reasonNames(v.reasons);
    EXPECT_GT(c.surfaceDistance(inPlane, {0.0f, 0}), 90.0);
    EXPECT_LT(c.surfaceBound(inPlane, 0), 90.0);
}

}  // namespace
}  // namespace oct
