// The kernel's rays against their definitions (validation/policy/ray_definitions.h, validate's
// camera, shadow-ray and ray-scaling checks): the definitions on cases worked by hand, and the
// kernel held to them on every committed mesh and a cloud, with the margin measured.
#include <gtest/gtest.h>

#include <cmath>

#include "core/render/camera.h"
#include "core/scene/load_scene.h"
#include "tests/validation/fixtures.h"
#include "validation/policy/ray_definitions.h"

namespace oct {
namespace {

using octtest::meshPath;

constexpr double kU = kFloatUnitRoundoff;

void expectNear(DVec3 a, DVec3 b, double tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

DVec3 unit(DVec3 v) { return v * (1.0 / std::sqrt(dot(v, v))); }

TEST(RayDefinitions, PinholeRayThroughAPixelCentreByHand) {
    // Eye at the origin looking down -z, up +y, 90 degrees: tan(fov/2) = 1. A 4x2 image has
    // aspect 2: pixel (0, 0), top left, has sx = 2 * 0.5 / 4 - 1 = -0.75 (x -0.75 * 1 * 2) and
    // sy = 1 - 2 * 0.5 / 2 = 0.5, right = forward x up = (1, 0, 0).
    CameraOptions o;
    o.width = 4;
    o.height = 2;
    o.fovDegrees = 90.0f;
    o.eye = Vec3{0.0f, 0.0f, 0.0f};
    o.target = Vec3{0.0f, 0.0f, -1.0f};
    const ReferenceFrame f = referenceFrame({{-1, -1, -1}, {1, 1, 1}}, o);
    expectNear(f.right, {1, 0, 0}, 1e-15);
    expectNear(f.up, {0, 1, 0}, 1e-15);
    const DoubleRay r = referencePrimaryRay(f, 0, 0);
    expectNear(r.org, {0, 0, 0}, 0.0);
    expectNear(r.dir, unit({-1.5, 0.5, -1.0}), 1e-15);
    EXPECT_EQ(r.tmin, 0.0);
    EXPECT_EQ(r.tmax, INFINITY);
    // The bottom right pixel (3, 1): sx = 0.75, sy = -0.5.
    expectNear(referencePrimaryRay(f, 3, 1).dir, unit({1.5, -0.5, -1.0}), 1e-15);
}

TEST(RayDefinitions, DefaultFramingByHand) {
    // The box [-1, 1]^3 (bounding sphere radius sqrt 3) in a 200x100 frame at 60 degrees: the
    // smaller half angle is the vertical 30 degrees, so the eye sits at 1.05 sqrt(3) / sin 30 on
    // +z; the light one radius above and to the right of it; the lift 1e-5 of the diagonal.
    CameraOptions o;
    o.width = 200;
    o.height = 100;
    o.fovDegrees = 60.0f;
    const ReferenceFrame f = referenceFrame({{-1, -1, -1}, {1, 1, 1}}, o);
    const double r = std::sqrt(3.0), d = 1.05 * r / 0.5;
    expectNear(f.eye, {0, 0, d}, 1e-12);
    expectNear(f.forward, {0, 0, -1}, 1e-15);
    expectNear(f.light, {r, r, d}, 1e-12);
    EXPECT_NEAR(f.shadowBias, 1e-5 * 2.0 * r, 1e-18);
    EXPECT_NEAR(f.aspect, 2.0, 0.0);
    // A tall frame fits the horizontal half angle: atan(tan 30 / 2).
    o.width = 100;
    o.height = 200;
    const ReferenceFrame tall = referenceFrame({{-1, -1, -1}, {1, 1, 1}}, o);
    EXPECT_NEAR(tall.eye.z, 1.05 * r / std::sin(std::atan(std::tan(std::acos(-1.0) / 6.0) / 2.0)),
                1e-12);
}

TEST(RayDefinitions, ShadowRayFromAHitByHand) {
    // A triangle in z = 0 seen from (0, 0, 5) straight down, hit at t = 5: the lift is along
    // +z (the normal turned to face the ray), towards a light at (3, 0, 4) + the lift.
    Scene scene;
    scene.kind = PrimKind::Triangles;
    scene.triangles = {{{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}}};  // normal +z: faces the eye
    CameraOptions o;
    o.eye = Vec3{0.0f, 0.0f, 5.0f};
    o.target = Vec3{0.0f, 0.0f, 0.0f};
    o.light = Vec3{3.0f, 0.0f, 4.0f};
    const ReferenceFrame f = referenceFrame({{-1, -1, 0}, {1, 1, 0}}, o);
    const ReferenceShadowRay s =
        referenceShadowRay(f, scene, {{0, 0, 5}, {0, 0, -1}, 0.0, INFINITY}, 5.0, 0);
    const double bias = 1e-5 * std::sqrt(8.0);
    EXPECT_NEAR(f.shadowBias, bias, 1e-18);
    expectNear(s.normal, {0, 0, 1}, 0.0);
    expectNear(s.ray.org, {0, 0, bias}, 1e-18);
    const DVec3 toLight = {3.0, 0.0, 4.0 - bias};
    expectNear(s.ray.dir, unit(toLight), 1e-15);
    EXPECT_NEAR(s.ray.tmax, std::sqrt(dot(toLight, toLight)), 1e-15);
    EXPECT_EQ(s.ray.tmin, 0.0);
    EXPECT_GT(s.lightCos, 0.0);                                                // the lit side: cast
    EXPECT_NEAR(s.normalError, 8.0 * kU * 2.0 * std::sqrt(5.0) / 4.0, 1e-20);  // |e1| |e2| / |n|
}

TEST(RayDefinitions, PowerOfTwoScalingByHand) {
    // Largest |component| 3 = 0.75 * 2^2: e = 2, the direction / 4, tmin and tmax * 4.
    const float row[8] = {1, 2, 3, 3.0f, -1.0f, 0.5f, 1.0f, 3e38f};
    const ReferenceScaling s = referenceScaledRow(row);
    EXPECT_EQ(s.e, 2);
    EXPECT_EQ(s.dir[0], 0.75f);
    EXPECT_EQ(s.dir[1], -0.25f);
    EXPECT_EQ(s.dir[2], 0.125f);
    EXPECT_EQ(s.tmin, 4.0f);
    EXPECT_EQ(s.tmax, INFINITY);  // 1.2e39 is past float: the nearest is +inf
    EXPECT_EQ(referenceUnscaledT(2.0f, s.e), 0.5f);
    // t on the scaled ray is t * 2^-e on the row's: rounded once where it leaves the normals.
    EXPECT_EQ(referenceUnscaledT(0x1p-147f, s.e), 0x1p-149f);  // the smallest subnormal
    EXPECT_EQ(referenceUnscaledT(0x1p-148f, s.e), 0.0f);       // half of it: ties to even, 0
    // A subnormal largest component, 2^-140 = 0.5 * 2^-139: e = -139, the direction becomes
    // 0.5, and a t goes back times 2^139: 2^-20 to 2^119, 1 past float's range to +inf.
    const float tiny[8] = {0, 0, 0, 0x1p-140f, 0, 0, 0, INFINITY};
    const ReferenceScaling t = referenceScaledRow(tiny);
    EXPECT_EQ(t.e, -139);
    EXPECT_EQ(t.dir[0], 0.5f);
    EXPECT_EQ(referenceUnscaledT(0x1p-20f, t.e), 0x1p119f);
    EXPECT_EQ(referenceUnscaledT(1.0f, t.e), INFINITY);
}

TEST(RayDefinitions, RoundToFloatOverflowsAtTheLargestFloatsHalfUlp) {
    EXPECT_EQ(roundToFloat(0x1.fffffep127), 0x1.fffffep127f);
    EXPECT_EQ(roundToFloat(std::nextafter(0x1.ffffffp127, 0.0)), 0x1.fffffep127f);
    EXPECT_EQ(roundToFloat(0x1.ffffffp127), INFINITY);  // the tie goes to even: +inf
    EXPECT_EQ(roundToFloat(-1e300), -INFINITY);
    EXPECT_EQ(roundToFloat(0x1p-150), 0.0f);         // the tie below the smallest subnormal: 0
    EXPECT_EQ(roundToFloat(0x1.8p-149), 0x1p-148f);  // above it: rounds up to 2 ulps
}

// The kernel's rays held to their definitions on `scene`: every check passes with the largest
// error at most `margin` of its tolerance, and at most 1 % of the shadow rays left unjudged.
void expectKernelRaysPass(const Scene& scene, double margin) {
    SCOPED_TRACE(scene.name);
    ValidateOptions o = octtest::smallOptions(48, 600);
    o.replication = false;
    o.boxContractRays = 0;
    const ValidationReport rep = validateScene(scene, {}, nullptr, o);
    for (const auto* r : {&rep.camera, &rep.shadowRays, &rep.rayScaling}) {
        ASSERT_TRUE(r->has_value());
        const RayDefinitionReport& d = **r;
        EXPECT_TRUE(d.passes()) << (d.errors.empty() ? d.scope : d.errors[0]);
        EXPECT_LE(d.worstRatio, margin) << d.scope;
        EXPECT_LE(d.unjudged, d.compared / 100) << d.scope;
    }
    // Every pixel of both views and of the check's two frames of 97x61, each eye, each
    // frame's placement; every shadow ray of a hit; every ray row and the extreme ones.
    EXPECT_EQ(rep.camera->compared, 2u * 48 * 48 + 2u * 97 * 61 + 4 + 2);
    EXPECT_GT(rep.shadowRays->compared, 4u) << "no hit in either view";
    EXPECT_EQ(rep.rayScaling->compared + rep.rayScaling->unjudged, 600u + 831u);
}

TEST(KernelRays, HoldToTheirDefinitionsOnEveryCommittedMeshAndACloud) {
    // Measured: worst 0.27 (camera), 0.31 (shadow rays) of the tolerance; the scaling is exact.
    for (const std::string& name : octtest::committedMeshes())
        expectKernelRaysPass(loadScene(meshPath(name)), 0.5);
    expectKernelRaysPass(makeGridCloud(2000, 3), 0.5);
}

// certify's camera set (checkCameraRows): rows the camera made hold to the definition; rows of
// the camera's classic slips (the height divided by the width, a pixel's corner for its centre,
// the image transposed) and a count that is not width x height do not, named by row and pixel.
namespace camera_rows {

std::vector<float> rowsOf(const FrameParams& f, int width, int height, float dx, bool transpose) {
    std::vector<float> rows;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            Camera c = f.camera;
            const int px = transpose ? y : x, py = transpose ? x : y;
            const float sx = 2.0f * (float(px) + 0.5f + dx) / float(width) - 1.0f;
            const float sy = 1.0f - 2.0f * (float(py) + 0.5f) / float(height);
            const Vec3 d = normalize(c.forward + c.right * sx + c.up * sy);
            const Ray r = dx == 0.0f && !transpose ? primaryRay(c, x, y, width, height)
                                                   : Ray{c.eye, d, 0.0f, INFINITY};
            rows.insert(rows.end(),
                        {r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax});
        }
    return rows;
}

TEST(CameraRows, TheCamerasRowsHoldAndItsSlipsAreNamed) {
    const Scene scene = loadScene(meshPath("teapot.obj"));
    CameraOptions o;
    o.width = 37;
    o.height = 23;
    const FrameParams f = makeFrame(scene.bounds(), o);
    const std::vector<float> good = rowsOf(f, o.width, o.height, 0.0f, false);
    RayDefinitionReport r = checkCameraRows(scene.bounds(), o, good.data(), good.size() / 8);
    EXPECT_TRUE(r.passes()) << (r.errors.empty() ? "" : r.errors[0]);
    EXPECT_EQ(r.compared, uint64_t(o.width * o.height));
    EXPECT_LT(r.worstRatio, 0.5);  // a margin, measured: well inside the tolerance
    // The pixel's corner (half a pixel off in x): every row off.
    std::vector<float> corner = rowsOf(f, o.width, o.height, -0.5f, false);
    r = checkCameraRows(scene.bounds(), o, corner.data(), corner.size() / 8);
    EXPECT_EQ(r.failures, r.compared);
    ASSERT_FALSE(r.errors.empty());
    EXPECT_NE(r.errors[0].find("pixel 0,0"), std::string::npos) << r.errors[0];
    // A frame of the wrong shape rowed as this one (the transposed image, 23 x 37 read as 37 x
    // 23): most rows off.
    std::vector<float> transposed = rowsOf(f, o.width, o.height, 0.0f, true);
    r = checkCameraRows(scene.bounds(), o, transposed.data(), transposed.size() / 8);
    EXPECT_GT(r.failures, r.compared / 2);
    // One row's origin moved by one float step: that row alone.
    std::vector<float> moved = good;
    moved[8 * 5] = std::nextafter(moved[8 * 5], INFINITY);
    r = checkCameraRows(scene.bounds(), o, moved.data(), moved.size() / 8);
    EXPECT_EQ(r.failures, 1u);
    // Rows for another size are off as a whole.
    r = checkCameraRows(scene.bounds(), o, good.data(), good.size() / 8 - 1);
    EXPECT_FALSE(r.passes());
}

}  // namespace camera_rows

}  // namespace
}  // namespace oct
