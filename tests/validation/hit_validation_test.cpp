// validateFilm (validation/policy/hit_validation.h) on Films that differ from Embree's in one
// chosen way: a malformed hit, a wrong primitive at the right distance, a flood of primary
// mismatches next to one false shadow. Each must be found and classed as the policy says.
#include "validation/policy/hit_validation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "cpu_ref/embree_tracer.h"
#include "tests/validation/fixtures.h"

namespace oct {
namespace {

struct FilmChecks : ::testing::Test {
    Scene scene = loadScene(octtest::meshPath("teapot.obj"));
    ValidationPolicy policy;
    HitClassifier classifier{scene, policy};
    EmbreeTracer embree{scene};
    FrameParams frame;
    Film reference;

    void SetUp() override {
        CameraOptions cam;
        cam.width = cam.height = 64;
        frame = makeFrame(scene.bounds(), cam);
        reference = Film(frame.width, frame.height);
        renderFrameCpu(frame, embree.accel(), primitivesView(scene), reference.view());
    }
    OcclusionQuery embreeOccluded() {
        EmbreeTracer* e = &embree;
        return [e](const Ray& r) {
            TraceCost c = {0, 0};
            return anyHit(e->accel(), r, c);
        };
    }
    // Pixels whose primary ray hits and whose shadow ray is lit, in scan order.
    std::vector<size_t> litPixels() const {
        std::vector<size_t> out;
        for (size_t i = 0; i < reference.pixelCount(); ++i)
            if (reference.prim[i] >= 0 && reference.shadow[i] == kLit) out.push_back(i);
        return out;
    }
    DVec3 hitPoint(size_t i) const {
        int x = int(i % size_t(frame.width)), y = int(i / size_t(frame.width));
        DoubleRay r = toDoubleRay(primaryRay(frame.camera, x, y, frame.width, frame.height));
        double t = reference.t[i];
        return {r.org.x + r.dir.x * t, r.org.y + r.dir.y * t, r.org.z + r.dir.z * t};
    }
    void expectOneInvalidHit(const FilmValidation& v, size_t i) {
        EXPECT_EQ(v.primary.wrong, 1u);
        EXPECT_EQ(v.primary.ties, 0u);
        EXPECT_EQ(v.primary.reasons[8], 1u) << "invalid_hit";
        EXPECT_FALSE(v.passes(policy.maxAmbiguousRate));
        ASSERT_FALSE(v.worstPixels.empty());
        EXPECT_EQ(v.worstPixels[0].index, i);
        EXPECT_EQ(v.worstPixels[0].cls, HitClass::Wrong);
        EXPECT_TRUE(v.worstPixels[0].reasons & kInvalidHit)
            << reasonNames(v.worstPixels[0].reasons);
    }
};

TEST_F(FilmChecks, NaNDistanceIsWrongAndShowsInTheMaximum) {
    std::vector<size_t> lit = litPixels();
    ASSERT_FALSE(lit.empty());
    Film ours = reference;
    ours.t[lit[0]] = NAN;
    FilmValidation v = validateFilm(classifier, frame, ours, reference, embreeOccluded());
    expectOneInvalidHit(v, lit[0]);
    EXPECT_EQ(v.primary.maxRelativeDt, INFINITY);
}

TEST_F(FilmChecks, OutOfRangePrimitiveIsWrong) {
    std::vector<size_t> lit = litPixels();
    ASSERT_FALSE(lit.empty());
    Film ours = reference;
    ours.prim[lit[0]] = int32_t(scene.primitiveCount()) + 999;
    ours.shadow[lit[0]] = kNoShadowRay;  // would send the bad id into the shadow-ray rebuild
    FilmValidation v = validateFilm(classifier, frame, ours, reference, embreeOccluded());
    expectOneInvalidHit(v, lit[0]);
    EXPECT_EQ(v.shadow.ambiguous + v.shadow.wrong, 0u);
}

TEST_F(FilmChecks, WrongPrimitiveAtTheRightDistanceIsWrongAndExcusesNoShadow) {
    std::vector<size_t> lit = litPixels();
    ASSERT_FALSE(lit.empty());
    const size_t i = lit[lit.size() / 2];
    // A triangle far (5% of the extent) from the hit point: shading it uses the wrong normal.
    const DVec3 p = hitPoint(i);
    int32_t far = -1;
    for (uint32_t q = 0; q < scene.primitiveCount() && far < 0; ++q)
        if (classifier.truth().distanceTo(q, p) > 0.05 * classifier.extent()) far = int32_t(q);
    ASSERT_GE(far, 0);
    Film ours = reference;
    ours.prim[i] = far;
    ours.shadow[i] = kNoShadowRay;  // as if that triangle faced away from the light
    FilmValidation v = validateFilm(classifier, frame, ours, reference, embreeOccluded());
    EXPECT_EQ(v.primary.ties, 0u);
    EXPECT_EQ(v.primary.wrong, 1u);
    EXPECT_EQ(v.primary.mismatches, 1u);
    EXPECT_EQ(v.shadow.ambiguous, 0u) << "no terminator excuse for a wrong primitive";
    EXPECT_EQ(v.shadow.reasons[6], 0u) << "terminator";
    EXPECT_FALSE(v.passes(policy.maxAmbiguousRate));
    ASSERT_FALSE(v.worstPixels.empty());
    EXPECT_EQ(v.worstPixels[0].index, i);
    EXPECT_EQ(v.worstPixels[0].truth.prim, reference.prim[i]);
}

// A cap the user sets leaves work unverified, never wrong: past it a mismatch is neither right
// nor wrong, and the cap of one check does not spend another's.
TEST_F(FilmChecks, PrimaryAndShadowRechecksHaveTheirOwnCaps) {
    ValidationPolicy tight = policy;
    tight.maxRechecks = 1;
    HitClassifier c(scene, tight);
    std::vector<size_t> lit = litPixels();
    ASSERT_GE(lit.size(), 3u);
    Film ours = reference;
    ours.shadow[lit[0]] = kOccluded;       // a false shadow where the light is clearly visible
    for (size_t k : {lit[1], lit.back()})  // two primary mismatches: 1% of the extent behind
        ours.t[k] += float(0.01 * c.extent());
    FilmValidation v = validateFilm(c, frame, ours, reference, embreeOccluded());
    EXPECT_EQ(v.primary.wrong, 1u);
    EXPECT_EQ(v.primary.unverified, 1u);
    EXPECT_FALSE(v.primary.complete());
    EXPECT_EQ(v.primary.rechecked, 1u);
    EXPECT_EQ(v.primary.reasons[7], 1u) << "not_rechecked";
    // The primary flood used the primary budget only: the shadow ray is still rechecked.
    EXPECT_EQ(v.shadow.wrong, 1u);
    EXPECT_EQ(v.shadow.rechecked, 1u);
    EXPECT_EQ(v.shadow.reasons[7], 0u) << "not_rechecked";
    ASSERT_FALSE(v.worstShadows.empty());
    EXPECT_EQ(v.worstShadows[0].truthOccluded, 0);
}

}  // namespace
}  // namespace oct
