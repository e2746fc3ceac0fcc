// The seeded ray sets of `octrace validate --rays` (validation/ray_sets.h).
#include "validation/ray_sets.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/octree/octree.h"
#include "tests/validation/fixtures.h"

namespace oct {
namespace {

TEST(RaySets, SplitReproducibleAndWellFormed) {
    Scene scene = loadScene(octtest::meshPath("teapot.obj"));
    ValidationRays a = makeValidationRays(scene, 3001, 42);
    ValidationRays b = makeValidationRays(scene, 3001, 42);
    ValidationRays c = makeValidationRays(scene, 3001, 43);
    ASSERT_EQ(a.count(), 3001u);
    ASSERT_EQ(a.rays.size(), 8u * 3001u);
    EXPECT_EQ(a.rays, b.rays);
    EXPECT_NE(a.rays, c.rays);
    int kinds[kRayKindCount] = {};
    for (RayKind k : a.kind) ++kinds[int(k)];
    EXPECT_EQ(kinds[0], 1001);
    EXPECT_EQ(kinds[1], 1000);
    EXPECT_EQ(kinds[2], 1000);

    Aabb root = rootCube(scene);
    Aabb bounds = scene.bounds();
    int onPlane = 0, finiteTmax = 0;
    for (uint64_t i = 0; i < a.count(); ++i) {
        const float* r = &a.rays[8 * i];
        Vec3 o = {r[0], r[1], r[2]}, d = {r[3], r[4], r[5]};
        ASSERT_TRUE(isFinite(o));
        EXPECT_NEAR(length(d), 1.0f, 1e-6f);
        EXPECT_EQ(r[6], 0.0f);
        finiteTmax += std::isfinite(r[7]);
        switch (a.kind[i]) {
            case RayKind::Around:
                EXPECT_FALSE(bounds.contains(o));
                break;
            case RayKind::Inside:
                EXPECT_TRUE(root.contains(o));
                break;
            case RayKind::Axis: {
                EXPECT_TRUE(root.contains(o));
                int nonZero = (d.x != 0) + (d.y != 0) + (d.z != 0);
                EXPECT_EQ(nonZero, 1);
                // On a node boundary plane of depth <= 3: (o - lo) / edge * 8 is an integer
                // (the float midpoints of a cube are exact here).
                for (int ax = 0; ax < 3; ++ax) {
                    if (d[ax] != 0) continue;
                    double f =
                        (double(o[ax]) - root.lo[ax]) / (double(root.hi[ax]) - root.lo[ax]) * 8.0;
                    if (std::fabs(f - std::round(f)) < 1e-5) {
                        ++onPlane;
                        break;
                    }
                }
                break;
            }
        }
    }
    EXPECT_GE(onPlane, 450);     // every other axis ray
    EXPECT_GT(finiteTmax, 150);  // a quarter of the inside rays
    EXPECT_LT(finiteTmax, 350);
}

TEST(RaySets, ZeroRaysIsEmpty) {
    Scene scene = loadScene(octtest::meshPath("cube_binary.ply"));
    EXPECT_EQ(makeValidationRays(scene, 0, 1).count(), 0u);
}

}  // namespace
}  // namespace oct
