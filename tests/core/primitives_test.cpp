// The triangle test of core/geometry/primitives.h on rays that lie in the triangle's plane.
#include "core/geometry/primitives.h"

#include <gtest/gtest.h>

#include <cmath>

namespace oct {
namespace {

// Whether p lies in the triangle's bounding box grown by `slack` on every side.
bool inBox(Vec3 p, const Triangle& t, float slack) {
    for (int k = 0; k < 3; ++k) {
        const float lo = fminf(fminf(t.v0[k], t.v1[k]), t.v2[k]) - slack;
        const float hi = fmaxf(fmaxf(t.v0[k], t.v1[k]), t.v2[k]) + slack;
        if (!(p[k] >= lo && p[k] <= hi)) return false;
    }
    return true;
}

// Met in certify's "around" rays on a heightfield whose vertices sit on the float grid at 1e8
// (and at 1e6, the same shape 128 times smaller): the ray starts exactly in the triangle's
// plane and its direction lies in that plane to within its rounding (n.d / |n||d| ~ 1e-8), so
// the triangle projects onto a segment through the origin and every float edge function is
// rounding noise. The plane is crossed at t = 0, at the origin, 12 ulps outside the triangle:
// the kernel once reported that point as a hit. A miss is right; so is a point on the
// triangle, which the ray grazes within its rounding; a point off it is not.
TEST(IntersectTriangle, ARayInThePlaneIsNeverHitOffTheTriangle) {
    struct Case {
        float scale;  // the grid step: 8 at 1e8, 1/16 at 1e6: one ulp at each
        float base;
    };
    for (const Case c : {Case{8.0f, 1e8f}, Case{0.0625f, 1e6f}}) {
        SCOPED_TRACE(c.base);
        // Offsets in grid steps from the base (all exact floats).
        auto at = [&](float x, float y, float z) {
            return Vec3{c.base + c.scale * x, c.base + c.scale * y, c.base + c.scale * z};
        };
        const Triangle tri{at(9, 6, 2), at(10, 7, 2), at(9, 7, 1)};
        const Vec3 org = at(1, 8, -8);
        const Vec3 dir{0.662084699f, -0.0827605873f, 0.744845271f};
        // The origin is in the plane: n = (-1, 1, 1) in grid steps, n.(org - v0) = 0.
        ASSERT_EQ(-(org.x - tri.v0.x) + (org.y - tri.v0.y) + (org.z - tri.v0.z), 0.0f);
        float t = -1.0f;
        const bool hit = intersectTriangle(makeShearedRay(org, dir), tri, 0.0f, INFINITY, t);
        if (hit) {
            const Vec3 p{float(double(org.x) + double(dir.x) * t),
                         float(double(org.y) + double(dir.y) * t),
                         float(double(org.z) + double(dir.z) * t)};
            EXPECT_TRUE(inBox(p, tri, c.scale)) << "hit at t = " << t << ", off the triangle";
        }
    }
}

}  // namespace
}  // namespace oct
