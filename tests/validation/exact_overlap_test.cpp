// The replication check's references (validation/exact/exact_overlap.h): CGAL's exact test against
// hand-made touching cases, and against our float and double Akenine-Möller tests on seeded
// random cases away from touching configurations, where all of them must agree.
#include "validation/exact/exact_overlap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/geometry/tri_box.h"

namespace oct {
namespace {

const Aabb kUnit = {{0, 0, 0}, {1, 1, 1}};

TEST(ExactOverlap, TouchingCasesCountAsOverlap) {
    // In the face x = 1 shared with the next box: both boxes.
    Triangle inFace = {{1, 0.2f, 0.2f}, {1, 0.8f, 0.2f}, {1, 0.5f, 0.9f}};
    EXPECT_TRUE(exactTriangleBoxOverlap(inFace, kUnit));
    EXPECT_TRUE(exactTriangleBoxOverlap(inFace, {{1, 0, 0}, {2, 1, 1}}));
    // Only a vertex on the corner (1, 1, 1).
    Triangle corner = {{1, 1, 1}, {2, 1, 1}, {1, 2, 1}};
    EXPECT_TRUE(exactTriangleBoxOverlap(corner, kUnit));
    // The same triangle one float step away does not touch.
    float up = std::nextafter(1.0f, 2.0f);
    Triangle apart = {{up, up, up}, {2, up, up}, {up, 2, up}};
    EXPECT_FALSE(exactTriangleBoxOverlap(apart, kUnit));
    EXPECT_GT(triangleBoxGap(apart, kUnit), 0.0);
    EXPECT_LT(triangleBoxGap(apart, kUnit), 1e-6);
    // A triangle whose plane cuts off the corner just outside it: every box-normal axis
    // overlaps, only the triangle's normal separates.
    float k = 3.0f + 1e-6f;  // the plane x + y + z = k passes outside the corner (sum 3)
    Triangle cut = {{k, 0, 0}, {0, k, 0}, {0, 0, k}};
    EXPECT_FALSE(exactTriangleBoxOverlap(cut, kUnit));
    Triangle through = {{3, 0, 0}, {0, 3, 0}, {0, 0, 3}};
    EXPECT_TRUE(exactTriangleBoxOverlap(through, kUnit));
}

TEST(ExactOverlap, DegenerateTrianglesAreSegmentsOrPoints) {
    Triangle seg = {{-1, 0.5f, 0.5f}, {2, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}};  // collinear
    EXPECT_TRUE(exactTriangleBoxOverlap(seg, kUnit));
    Triangle segOut = {{-1, 1.5f, 0.5f}, {2, 1.5f, 0.5f}, {0.5f, 1.5f, 0.5f}};
    EXPECT_FALSE(exactTriangleBoxOverlap(segOut, kUnit));
    Triangle pointIn = {{0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}};
    EXPECT_TRUE(exactTriangleBoxOverlap(pointIn, kUnit));
    Triangle pointOut = {{1.5f, 0.5f, 0.5f}, {1.5f, 0.5f, 0.5f}, {1.5f, 0.5f, 0.5f}};
    EXPECT_FALSE(exactTriangleBoxOverlap(pointOut, kUnit));
    // The middle vertex is the extreme one: the segment still spans it.
    Triangle seg2 = {{0.5f, 0.5f, 0.5f}, {3, 3, 3}, {2, 2, 2}};
    EXPECT_TRUE(exactTriangleBoxOverlap(seg2, kUnit));
}

TEST(ExactOverlap, SpheresTouchAtTheirRadius) {
    EXPECT_TRUE(exactSphereBoxOverlap({{1.5f, 0.5f, 0.5f}, 0.5f}, kUnit));  // touching a face
    EXPECT_FALSE(exactSphereBoxOverlap({{1.5f, 0.5f, 0.5f}, 0.49999997f}, kUnit));
    EXPECT_TRUE(exactSphereBoxOverlap({{2, 2, 1}, std::sqrt(2.0f)}, kUnit) ==
                (double(std::sqrt(2.0f)) * std::sqrt(2.0f) >= 2.0));  // corner edge, exact
    EXPECT_NEAR(sphereBoxGap({{3, 0.5f, 0.5f}, 1}, kUnit), 1.0, 1e-12);
}

// Random float triangles and boxes of many scales, kept only when they are clearly apart (gap
// above 1e-4 of the box) or clearly overlapping (the box shrunk by 1e-4 still overlaps).
TEST(ExactOverlap, AgreesWithFloatAndDoubleTestsAwayFromTouching) {
    std::mt19937_64 rng(20240611);
    auto u = [&] { return double(rng() >> 11) * 0x1p-53; };
    int apart = 0, overlapping = 0, touchy = 0, tested = 0;
    for (int i = 0; i < 20000; ++i) {
        double s = std::pow(10.0, -2.0 + 4.0 * u());
        double off = (rng() % 3 == 0) ? 50.0 * s : 0.0;
        Vec3 c = {float(off + s * (u() - 0.5)), float(s * (u() - 0.5)), float(s * (u() - 0.5))};
        Vec3 h = {float(s * (0.1 + u())), float(s * (0.1 + u())), float(s * (0.1 + u()))};
        Aabb box = {c - h, c + h};
        double spread = (rng() % 2) ? 1.5 : 3.0;
        Vec3 v[3];
        for (Vec3& p : v)
            for (int a = 0; a < 3; ++a) p[a] = float(c[a] + spread * h[a] * (2.0 * u() - 1.0));
        Triangle tri = {v[0], v[1], v[2]};
        Vec3 e = box.extent();
        double edge = std::max({double(e.x), double(e.y), double(e.z)});
        Aabb shrunk = {box.lo + e * 1e-4f, box.hi - e * 1e-4f};
        bool exact = exactTriangleBoxOverlap(tri, box);
        bool clearlyApart = triangleBoxGap(tri, box) > 1e-4 * edge;
        bool clearlyIn = exactTriangleBoxOverlap(tri, shrunk);
        ++tested;
        if (!clearlyApart && !clearlyIn) {
            ++touchy;
            continue;
        }
        EXPECT_EQ(exact, clearlyIn) << "case " << i;
        (clearlyIn ? overlapping : apart)++;
        Vec3 bc = box.center(), bh = box.extent() * 0.5f;
        bool f =
            triBoxOverlap<float>({bc.x, bc.y, bc.z}, {bh.x, bh.y, bh.z}, {v[0].x, v[0].y, v[0].z},
                                 {v[1].x, v[1].y, v[1].z}, {v[2].x, v[2].y, v[2].z});
        EXPECT_EQ(f, exact) << "float test, case " << i;
        EXPECT_EQ(doubleTriangleBoxOverlap(tri, box), exact) << "double test, case " << i;
        EXPECT_EQ(exact, triangleBoxGap(tri, box) == 0.0) << "gap, case " << i;
    }
    // Both outcomes well represented, and the filter leaves almost everything in.
    EXPECT_GT(apart, tested / 10);
    EXPECT_GT(overlapping, tested / 10);
    EXPECT_LT(touchy, tested / 20);
}

// Cases built to touch: a triangle vertex placed exactly on a box face, corner or edge. The
// exact test says yes for every one; the unpadded double test may differ only by rounding, so
// it is counted, not required.
TEST(ExactOverlap, VerticesOnTheBoxAreOverlaps) {
    std::mt19937_64 rng(99);
    auto u = [&] { return double(rng() >> 11) * 0x1p-53; };
    for (int i = 0; i < 5000; ++i) {
        Aabb box = {{float(u()), float(u()), float(u())}, {0, 0, 0}};
        box.hi = box.lo + Vec3{float(0.1 + u()), float(0.1 + u()), float(0.1 + u())};
        Vec3 p;
        for (int a = 0; a < 3; ++a) p[a] = float(box.lo[a] + (box.hi[a] - box.lo[a]) * u());
        int axis = int(rng() % 3);
        p[axis] = (rng() & 1) ? box.hi[axis] : box.lo[axis];
        Vec3 out = p;
        out[axis] += (p[axis] == box.hi[axis] ? 1.0f : -1.0f);
        Triangle tri = {p, out + Vec3{0.3f, 0.2f, 0.1f}, out - Vec3{0.1f, 0.3f, 0.2f}};
        EXPECT_TRUE(exactTriangleBoxOverlap(tri, box)) << "case " << i;
        EXPECT_LE(triangleBoxGap(tri, box), 1e-12) << "case " << i;
    }
}

}  // namespace
}  // namespace oct
