// The Akenine-Möller triangle/box test (core/geometry/tri_box.h), in float and in double, and
// the builder's padded overlap test (core/octree/octree.h), against an independent brute-force
// separating-axis test in double precision (brute_sat.h).
#include "core/geometry/tri_box.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "core/octree/octree.h"
#include "tests/core/brute_sat.h"

namespace oct {
namespace {

using octtest::bruteSat;
using octtest::SatResult;

// A box given as the float test receives it (centre and half size) and a float triangle.
struct Pair {
    Vec3T<float> c, h;
    Vec3T<float> v[3];
    int mode = -1;  // how randomPairs made it (-1: by hand)
};

glm::dvec3 d3(Vec3T<float> v) { return {double(v.x), double(v.y), double(v.z)}; }
glm::dvec3 d3(Vec3 v) { return {double(v.x), double(v.y), double(v.z)}; }
Vec3T<double> v3d(Vec3T<float> v) { return {double(v.x), double(v.y), double(v.z)}; }
Vec3 toVec3(Vec3T<float> v) { return {v.x, v.y, v.z}; }

// Exact box of a pair: centre +- half size, each a float, so the sums are exact in double.
SatResult bruteOfPair(const Pair& p, double eps) {
    glm::dvec3 c = d3(p.c), h = d3(p.h);
    return bruteSat(c - h, c + h, d3(p.v[0]), d3(p.v[1]), d3(p.v[2]), eps);
}

bool floatTest(const Pair& p) { return triBoxOverlap<float>(p.c, p.h, p.v[0], p.v[1], p.v[2]); }
bool doubleTest(const Pair& p) {
    return triBoxOverlap<double>(v3d(p.c), v3d(p.h), v3d(p.v[0]), v3d(p.v[1]), v3d(p.v[2]));
}

// Random pairs of many kinds: scales from 1e-3 to 1e3, boxes of random aspect, triangles
// through, near, grazing and outside the box, slivers and exactly degenerate triangles.
std::vector<Pair> randomPairs(size_t count, uint64_t seed) {
    std::mt19937_64 rng(seed);
    // Raw engine bits (std distributions are implementation-defined): the same pairs everywhere.
    auto u01 = [&](std::mt19937_64& r) { return double(r() >> 11) * 0x1p-53; };
    auto sym = [&] { return 2.0 * u01(rng) - 1.0; };
    std::vector<Pair> out;
    out.reserve(count);
    while (out.size() < count) {
        double s = std::pow(10.0, -3.0 + 6.0 * u01(rng));
        double c[3], h[3];
        double offset = (rng() % 4 == 0) ? 100.0 : 1.0;  // sometimes far from the origin
        for (int a = 0; a < 3; ++a) {
            c[a] = s * offset * sym();
            h[a] = s * std::pow(10.0, -2.0 * u01(rng));
        }
        double hmax = std::max({h[0], h[1], h[2]});
        double v[3][3];
        int mode = static_cast<int>(rng() % 8);
        if (mode == 0 || mode == 1) {  // vertices around the box: through or outside
            double spread = mode == 0 ? 2.0 : 4.0;
            for (auto& vi : v)
                for (int a = 0; a < 3; ++a) vi[a] = c[a] + spread * h[a] * sym();
        } else if (mode == 2) {  // small triangle near a random point of the box's surface
            double p[3];
            int axis = static_cast<int>(rng() % 3);
            for (int a = 0; a < 3; ++a) p[a] = c[a] + h[a] * sym();
            p[axis] = c[axis] + ((rng() & 1) ? h[axis] : -h[axis]);
            double r = hmax * std::pow(10.0, -3.0 + 2.5 * u01(rng));
            for (auto& vi : v)
                for (int a = 0; a < 3; ++a) vi[a] = p[a] + r * sym();
        } else if (mode == 3) {  // large triangle through the box region
            double p[3];
            for (int a = 0; a < 3; ++a) p[a] = c[a] + 1.5 * h[a] * sym();
            for (auto& vi : v)
                for (int a = 0; a < 3; ++a) vi[a] = p[a] + 20.0 * hmax * sym();
        } else if (mode == 4) {  // near a box edge or corner
            double p[3];
            for (int a = 0; a < 3; ++a) p[a] = c[a] + ((rng() & 1) ? h[a] : -h[a]);
            if (rng() & 1) {  // a point on an edge rather than the corner
                int axis = static_cast<int>(rng() % 3);
                p[axis] = c[axis] + h[axis] * sym();
            }
            double r = hmax * std::pow(10.0, -2.0 + 2.0 * u01(rng));
            for (auto& vi : v)
                for (int a = 0; a < 3; ++a) vi[a] = p[a] + r * sym();
        } else if (mode == 5) {  // sliver: third vertex almost on the first edge
            for (int i = 0; i < 2; ++i)
                for (int a = 0; a < 3; ++a) v[i][a] = c[a] + 2.0 * h[a] * sym();
            double t = u01(rng);
            for (int a = 0; a < 3; ++a)
                v[2][a] = v[0][a] + t * (v[1][a] - v[0][a]) + 1e-4 * hmax * sym();
        } else if (mode == 6) {  // segment: two equal vertices
            for (int i = 0; i < 2; ++i)
                for (int a = 0; a < 3; ++a) v[i][a] = c[a] + 2.0 * h[a] * sym();
            const int twin = static_cast<int>(rng() & 1);
            for (int a = 0; a < 3; ++a) v[2][a] = v[twin][a];
        } else {  // point: three equal vertices
            for (int a = 0; a < 3; ++a) v[0][a] = c[a] + 1.5 * h[a] * sym();
            for (int a = 0; a < 3; ++a) v[1][a] = v[2][a] = v[0][a];
        }
        Pair p;
        p.c = {float(c[0]), float(c[1]), float(c[2])};
        p.h = {float(h[0]), float(h[1]), float(h[2])};
        for (int i = 0; i < 3; ++i) p.v[i] = {float(v[i][0]), float(v[i][1]), float(v[i][2])};
        p.mode = mode;
        out.push_back(p);
    }
    return out;
}

std::string describe(const Pair& p) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "centre (%.9g %.9g %.9g) half (%.9g %.9g %.9g) tri (%.9g %.9g %.9g) "
                  "(%.9g %.9g %.9g) (%.9g %.9g %.9g)",
                  p.c.x, p.c.y, p.c.z, p.h.x, p.h.y, p.h.z, p.v[0].x, p.v[0].y, p.v[0].z, p.v[1].x,
                  p.v[1].y, p.v[1].z, p.v[2].x, p.v[2].y, p.v[2].z);
    return buf;
}

constexpr size_t kRandomPairs = 200000;
// Borderline band of the float comparison, relative to the pair's scale (brute_sat.h). Float
// rounds at 6e-8, and the error bounds of the 13 axis tests are a few units of that; 1e-6 keeps
// a margin of over 10x while leaving well under 1% of the random pairs out of the comparison.
constexpr double kEps = 1e-6;

TEST(TriBox, FloatAgreesWithBruteForceOnRandomPairs) {
    std::vector<Pair> pairs = randomPairs(kRandomPairs, 1);
    size_t borderline = 0, overlaps = 0, mismatches = 0;
    size_t borderlineByMode[8] = {};
    size_t borderFlips = 0;
    for (const Pair& p : pairs) {
        SatResult ref = bruteOfPair(p, kEps);
        overlaps += ref.overlap;
        if (ref.borderline) {
            ++borderline;
            ++borderlineByMode[p.mode];
            borderFlips += floatTest(p) != ref.overlap;
            continue;
        }
        if (floatTest(p) != ref.overlap) {
            if (++mismatches <= 10)
                ADD_FAILURE() << "float test says " << floatTest(p) << ", brute force "
                              << ref.overlap << " (scaled gap " << ref.maxScaledGap
                              << "): " << describe(p);
        }
    }
    std::printf("[tri_box] %zu pairs: %zu overlap, %zu borderline (%.3f%%)\n", pairs.size(),
                overlaps, borderline, 100.0 * borderline / pairs.size());
    std::printf("[tri_box] borderline by kind:");
    for (int m = 0; m < 8; ++m) std::printf(" %zu", borderlineByMode[m]);
    std::printf("; float differs from brute force on %zu of them\n", borderFlips);
    EXPECT_EQ(mismatches, 0u);
    EXPECT_LT(borderline, pairs.size() / 100);
    // Both outcomes well represented, or the comparison says little.
    EXPECT_GT(overlaps, pairs.size() / 5);
    EXPECT_LT(overlaps, pairs.size() * 4 / 5);
}

TEST(TriBox, DoubleAgreesWithBruteForceOnRandomPairs) {
    std::vector<Pair> pairs = randomPairs(kRandomPairs, 2);
    size_t borderline = 0, mismatches = 0;
    for (const Pair& p : pairs) {
        // Double rounding is ~1e-16, so a much tighter borderline band applies.
        SatResult ref = bruteOfPair(p, 1e-10);
        if (ref.borderline) {
            ++borderline;
            continue;
        }
        if (doubleTest(p) != ref.overlap && ++mismatches <= 10)
            ADD_FAILURE() << "double test says " << doubleTest(p) << ", brute force " << ref.overlap
                          << ": " << describe(p);
    }
    std::printf("[tri_box] double: %zu borderline of %zu\n", borderline, pairs.size());
    EXPECT_EQ(mismatches, 0u);
    EXPECT_LT(borderline, pairs.size() / 1000);
}

// The builder's test must never lose an overlap (a lost leaf would lose hits), on the box the
// builder actually sees: float lo/hi.
TEST(TriBox, BuilderTestHasNoFalseNegatives) {
    std::vector<Pair> pairs = randomPairs(kRandomPairs, 3);
    size_t falseNeg = 0, falsePos = 0, overlaps = 0;
    for (const Pair& p : pairs) {
        Aabb box = {toVec3(p.c) - toVec3(p.h), toVec3(p.c) + toVec3(p.h)};
        Triangle tri = {toVec3(p.v[0]), toVec3(p.v[1]), toVec3(p.v[2])};
        SatResult ref = bruteSat(d3(box.lo), d3(box.hi), d3(tri.v0), d3(tri.v1), d3(tri.v2), kEps);
        bool got = builderTriangleOverlaps(tri, box);
        overlaps += ref.overlap;
        if (ref.overlap && !got && ++falseNeg <= 10)
            ADD_FAILURE() << "builder misses an overlap (scaled gap " << ref.maxScaledGap
                          << "): box (" << box.lo.x << " " << box.lo.y << " " << box.lo.z << ")-("
                          << box.hi.x << " " << box.hi.y << " " << box.hi.z << ") " << describe(p);
        // Away from the borderline the padded test is exact as well.
        if (!ref.borderline && !ref.overlap && got) ++falsePos;
    }
    EXPECT_EQ(falseNeg, 0u);
    EXPECT_EQ(falsePos, 0u);
    EXPECT_GT(overlaps, pairs.size() / 5);
}

// Pairs on a dyadic grid with small integer coordinates: a box centre C*q, half sizes H*q and
// vertices (C + k)*q with |k| <= 32, H <= 16, q a power of two. Every product and sum in both
// the float test and the brute force is exact there, so the answers must agree on every pair,
// including the many that only touch (a vertex, an edge or the whole triangle on a face, edge
// or corner of the box): the boundary convention "touching counts" is tested exactly.
TEST(TriBox, ExactAgreementOnDyadicGridIncludingTouching) {
    std::mt19937_64 rng(4);
    auto irange = [&](int lo, int hi) { return lo + int(rng() % uint64_t(hi - lo + 1)); };
    size_t touching = 0, overlaps = 0;
    for (int iter = 0; iter < 50000; ++iter) {
        float q = std::ldexp(1.0f, irange(-20, 10));
        int C[3], H[3], K[3][3];
        for (int a = 0; a < 3; ++a) {
            C[a] = irange(-(1 << 17), 1 << 17);
            H[a] = irange(1, 16);
        }
        int mode = irange(0, 3);
        for (auto& k : K)
            for (int a = 0; a < 3; ++a) k[a] = irange(-32, 32);
        if (mode == 1) {  // one vertex on a face, the others on its outer side
            int axis = irange(0, 2), side = (rng() & 1) ? 1 : -1;
            K[0][axis] = side * H[axis];
            for (int a = 0; a < 3; ++a)
                if (a != axis) K[0][a] = irange(-H[a], H[a]);
            for (int i = 1; i < 3; ++i) K[i][axis] = side * irange(H[axis], 32);
        } else if (mode == 2) {  // the whole triangle in a face plane (inside or beside it)
            int axis = irange(0, 2), side = (rng() & 1) ? 1 : -1;
            for (auto& k : K) k[axis] = side * H[axis];
        } else if (mode == 3) {  // one vertex on a corner, the others beyond it
            for (int a = 0; a < 3; ++a) {
                int side = (rng() & 1) ? 1 : -1;
                K[0][a] = side * H[a];
                for (int i = 1; i < 3; ++i) K[i][a] = side * irange(H[a], 32);
            }
        }
        Pair p;
        p.c = {C[0] * q, C[1] * q, C[2] * q};
        p.h = {H[0] * q, H[1] * q, H[2] * q};
        for (int i = 0; i < 3; ++i)
            p.v[i] = {(C[0] + K[i][0]) * q, (C[1] + K[i][1]) * q, (C[2] + K[i][2]) * q};
        SatResult ref = bruteOfPair(p, 0.0);
        overlaps += ref.overlap;
        touching += ref.overlap && ref.maxScaledGap == 0.0;
        ASSERT_EQ(floatTest(p), ref.overlap) << describe(p);
        ASSERT_EQ(doubleTest(p), ref.overlap) << describe(p);
        Aabb box = {toVec3(p.c) - toVec3(p.h), toVec3(p.c) + toVec3(p.h)};
        Triangle tri = {toVec3(p.v[0]), toVec3(p.v[1]), toVec3(p.v[2])};
        ASSERT_EQ(builderTriangleOverlaps(tri, box), ref.overlap) << describe(p);
    }
    std::printf("[tri_box] dyadic: %zu overlap, %zu of them touching\n", overlaps, touching);
    EXPECT_GT(touching, 5000u);
    EXPECT_GT(overlaps, 15000u);
    EXPECT_LT(overlaps, 45000u);
}

// Regression: builderTriangleOverlaps() once took the box centre from Aabb::center(), rounded
// in float, and padded only by 1e-9 of the half size, so for about half of all float boxes a
// triangle touching a face from outside, or lying in it, was missed; the builder then dropped a
// triangle lying in a node face from every leaf (spider.obj lost 42 references).
TEST(TriBox, BuilderCountsTouchingOnBoxWithInexactCentre) {
    std::mt19937_64 rng(6);
    auto u01 = [&] { return double(rng() >> 11) * 0x1p-53; };
    size_t misses = 0;
    for (int iter = 0; iter < 10000; ++iter) {
        Aabb b;
        for (int a = 0; a < 3; ++a) {
            b.lo[a] = float(-100.0 + 200.0 * u01());
            b.hi[a] = b.lo[a] + float(0.001 + u01());
        }
        float y = b.lo.y + 0.5f * (b.hi.y - b.lo.y), z = b.lo.z + 0.5f * (b.hi.z - b.lo.z);
        Triangle outside = {{b.hi.x, y, z}, {b.hi.x + 1, y + 1, z}, {b.hi.x + 1, y, z + 1}};
        Triangle inFace = {{b.lo.x, y, z}, {b.lo.x, y + 1, z}, {b.lo.x, y, z + 1}};
        misses += !builderTriangleOverlaps(outside, b);
        misses += !builderTriangleOverlaps(inFace, b);
    }
    EXPECT_EQ(misses, 0u);
}

// --- hand-made cases on the box [-1, 1]^3 ---------------------------------------------------

struct Case {
    const char* name;
    Vec3T<float> a, b, c;
    bool expected;
};

void checkCase(const Case& k, Vec3T<float> centre = {0, 0, 0}, Vec3T<float> half = {1, 1, 1}) {
    Pair p{centre, half, {k.a, k.b, k.c}};
    SatResult ref = bruteOfPair(p, 0.0);
    EXPECT_EQ(ref.overlap, k.expected) << k.name << " (brute force disagrees with the case)";
    EXPECT_EQ(floatTest(p), k.expected) << k.name << " (float)";
    EXPECT_EQ(doubleTest(p), k.expected) << k.name << " (double)";
    // The builder pads by 1e-9 of the box; every "no" here misses by far more than that, and
    // these boxes' float centres are exact, so the builder agrees on both answers.
    Aabb box = {toVec3(centre) - toVec3(half), toVec3(centre) + toVec3(half)};
    Triangle tri = {toVec3(k.a), toVec3(k.b), toVec3(k.c)};
    EXPECT_EQ(builderTriangleOverlaps(tri, box), k.expected) << k.name << " (builder)";
}

TEST(TriBox, HandMadeTouchingAndNearMisses) {
    const Case cases[] = {
        {"vertex touching face x=1 from outside", {1, 0, 0}, {3, 0.5f, 0}, {3, -0.5f, 0.5f}, true},
        {"edge lying on face x=1, rest outside", {1, -0.5f, 0}, {1, 0.5f, 0}, {3, 0, 0}, true},
        {"vertex touching corner", {1, 1, 1}, {2, 3, 1}, {3, 2, 2}, true},
        {"triangle in face x=1", {1, -0.5f, -0.5f}, {1, 0.5f, -0.5f}, {1, 0, 0.5f}, true},
        {"triangle in face plane, beyond the face", {1, 1.5f, 0}, {1, 2.5f, 0}, {1, 2, 1}, false},
        {"triangle 1e-3 outside face x=1",
         {1.001f, -0.5f, -0.5f},
         {1.001f, 0.5f, -0.5f},
         {1.001f, 0, 0.5f},
         false},
        {"vertex 1e-3 outside face", {1.001f, 0, 0}, {3, 0.5f, 0}, {3, -0.5f, 0.5f}, false},
        {"vertex 1e-3 outside corner", {1.001f, 1.001f, 1.001f}, {2, 3, 1.5f}, {3, 2, 2}, false},
    };
    for (const Case& k : cases) checkCase(k);
}

TEST(TriBox, HandMadeAxisParallelTriangles) {
    const Case cases[] = {
        {"in plane z=0.5 through box", {-3, -3, 0.5f}, {3, -3, 0.5f}, {0, 3, 0.5f}, true},
        {"in plane z=0.5 beside box", {1.5f, -3, 0.5f}, {3, -3, 0.5f}, {3, 3, 0.5f}, false},
        {"in plane z=2 above box", {-9, -9, 2}, {9, -9, 2}, {0, 9, 2}, false},
        {"in plane y=-1 (face)", {-9, -1, -9}, {9, -1, -9}, {0, -1, 9}, true},
        {"in plane x=0, small, inside", {0, 0.1f, 0.1f}, {0, 0.2f, 0.1f}, {0, 0.1f, 0.3f}, true},
        // Right triangle with legs along x and y whose hypotenuse passes outside the corner
        // (x + y = 2.5 > 2): only an edge-cross axis separates it.
        {"hypotenuse misses corner", {2.5f, 0, 0.5f}, {0, 2.5f, 0.5f}, {2.5f, 2.5f, 0.5f}, false},
        {"hypotenuse clips corner", {1.9f, 0, 0.5f}, {0, 1.9f, 0.5f}, {2.5f, 2.5f, 0.5f}, true},
    };
    for (const Case& k : cases) checkCase(k);
}

TEST(TriBox, HandMadeDegenerateTriangles) {
    const Case cases[] = {
        {"segment through box (v2 = v1)", {-2, -2, -2}, {2, 2, 2}, {2, 2, 2}, true},
        {"segment through box, collinear midpoint", {-2, 0, 0}, {2, 0, 0}, {0, 0, 0}, true},
        {"segment outside, parallel to z", {2, 0, -3}, {2, 0, 3}, {2, 0, 0}, false},
        {"diagonal segment missing the corner edge",
         {0, 2.5f, 0},
         {2.5f, 0, 0},
         {2.5f, 0, 0},
         false},
        {"diagonal segment clipping the corner edge",
         {0, 1.5f, 0},
         {1.5f, 0, 0},
         {1.5f, 0, 0},
         true},
        {"point inside", {0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}, true},
        {"point outside", {1.5f, 0, 0}, {1.5f, 0, 0}, {1.5f, 0, 0}, false},
        {"point on corner", {1, 1, 1}, {1, 1, 1}, {1, 1, 1}, true},
        {"point just outside corner", {1.001f, 1, 1}, {1.001f, 1, 1}, {1.001f, 1, 1}, false},
    };
    for (const Case& k : cases) checkCase(k);
}

TEST(TriBox, HandMadeContainmentAndSlicing) {
    const Case cases[] = {
        {"fully inside", {-0.5f, -0.5f, 0}, {0.5f, -0.5f, 0.2f}, {0, 0.5f, -0.3f}, true},
        {"huge triangle slicing the box (x+y+z=0)",
         {-100, -100, 200},
         {200, -100, -100},
         {-100, 200, -100},
         true},
        {"huge triangle in plane x+y+z=2.5",
         {-100, -100, 202.5f},
         {202.5f, -100, -100},
         {-100, 202.5f, -100},
         true},
        {"huge triangle in plane x+y+z=3.5",
         {-100, -100, 203.5f},
         {203.5f, -100, -100},
         {-100, 203.5f, -100},
         false},
        {"box inside triangle's cross-section, plane z=0",
         {-50, -50, 0},
         {50, -50, 0},
         {0, 50, 0},
         true},
    };
    for (const Case& k : cases) checkCase(k);
}

// The same cases moved and scaled: a non-unit box far from the origin.
TEST(TriBox, HandMadeCasesOnOffsetBox) {
    const Vec3T<float> centre = {64.0f, -32.0f, 16.0f}, half = {0.25f, 0.5f, 2.0f};
    auto map = [&](Vec3T<float> p) {
        return Vec3T<float>{centre.x + p.x * half.x, centre.y + p.y * half.y,
                            centre.z + p.z * half.z};
    };
    const Case cases[] = {
        {"touching face", map({1, 0, 0}), map({3, 0.5f, 0}), map({3, -0.5f, 0.5f}), true},
        {"in face", map({1, -0.5f, -0.5f}), map({1, 0.5f, -0.5f}), map({1, 0, 0.5f}), true},
        {"outside face", map({1.01f, -0.5f, -0.5f}), map({1.01f, 0.5f, -0.5f}),
         map({1.01f, 0, 0.5f}), false},
        {"segment through", map({-2, -2, -2}), map({2, 2, 2}), map({2, 2, 2}), true},
        {"point inside", map({0.5f, 0.5f, 0.5f}), map({0.5f, 0.5f, 0.5f}), map({0.5f, 0.5f, 0.5f}),
         true},
    };
    for (const Case& k : cases) checkCase(k, centre, half);
}

}  // namespace
}  // namespace oct
