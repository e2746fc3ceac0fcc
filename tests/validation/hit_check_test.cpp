// The per-ray policy (validation/hit_check.h) on hand-made configurations whose right answer
// is known: a unit quad of two triangles in the plane z = 0 and a sphere.
#include "validation/hit_check.h"

#include <gtest/gtest.h>

#include <cmath>

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
    EXPECT_EQ(c.compare({INFINITY, -1}, {INFINITY, -1}), HitClass::Agree);
    EXPECT_EQ(c.compare({1.0f, 0}, {1.0f, 0}), HitClass::Agree);
    float tol = float(policy.tTolerance * c.extent());
    EXPECT_EQ(c.compare({1.0f, 0}, {1.0f + 0.5f * tol, 0}), HitClass::Agree);
    EXPECT_EQ(c.compare({1.0f, 0}, {1.0f + 0.5f * tol, 1}), HitClass::Tie);
    EXPECT_EQ(c.compare({1.0f, 0}, {1.0f + 2.0f * tol, 0}), HitClass::Wrong);  // mismatch
    EXPECT_EQ(c.compare({1.0f, 0}, {INFINITY, -1}), HitClass::Wrong);
}

TEST_F(HitCheck, MissingAClearHitIsWrong) {
    Verdict v = c.closest(down(0.7f, 0.2f), {INFINITY, -1}, {1.0f, 0});
    EXPECT_EQ(v.cls, HitClass::Wrong);
    EXPECT_TRUE(v.rechecked);
    EXPECT_EQ(v.truth.prim, 0);
    EXPECT_FLOAT_EQ(v.truth.t, 1.0f);
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
    // Through the diagonal: either triangle is right at the same t.
    EXPECT_EQ(c.closest(down(0.5f, 0.5f), {1.0f, 0}, {1.0f, 1}).cls, HitClass::Tie);
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

TEST_F(HitCheck, OursRightReferenceOffIsAmbiguous) {
    Verdict v = c.closest(down(0.7f, 0.2f), {1.0f, 0}, {INFINITY, -1});
    EXPECT_EQ(v.cls, HitClass::Ambiguous);
    EXPECT_EQ(v.reasons, uint32_t(kReferenceOff));
}

TEST_F(HitCheck, GrazingRayIsAmbiguous) {
    // Nearly parallel to the quad (cos 1e-4): a tiny offset of the plane moves t a lot.
    Vec3 d = normalize(Vec3{1.0f, 0.0f, -1e-4f});
    Ray r = {{-0.5f, 0.3f, 1e-4f * 0.7f}, d, 0, INFINITY};
    float tTruth = c.truth().closest(toDoubleRay(r)).t;
    ASSERT_TRUE(std::isfinite(tTruth));
    float tOff = tTruth + 0.05f;  // our hit point is 5e-6 off the plane: a grazing t
    Verdict v = c.closest(r, {tOff, 0}, {tTruth, 0});
    EXPECT_EQ(v.cls, HitClass::Ambiguous) << reasonNames(v.reasons);
    EXPECT_TRUE(v.reasons & kGrazing);
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

}  // namespace
}  // namespace oct
