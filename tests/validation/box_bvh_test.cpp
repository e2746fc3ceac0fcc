// The double truth's BVH (validation/policy/box_bvh.h) is a filter: against the brute force over
// every box, it must hand over every box a segment meets and every box within the best distance of
// a point, on seeded random boxes and segments, touching and axis-parallel ones included.
#include "validation/policy/box_bvh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <vector>

#include "tests/seeded.h"

namespace oct {
namespace {

using octtest::u01;

std::vector<DBox> randomBoxes(size_t n, double centre, std::mt19937_64& rng) {
    std::vector<DBox> boxes(n);
    for (DBox& b : boxes)
        for (int a = 0; a < 3; ++a) {
            const double c = centre + 10.0 * (u01(rng) - 0.5);
            const double h = (rng() % 8 == 0) ? 0.0 : 0.3 * u01(rng);  // some flat boxes
            b.lo[a] = c - h;
            b.hi[a] = c + h;
        }
    return boxes;
}

// Exact-enough reference: does the segment meet the closed box? In long double, with the
// parallel case by the origin's coordinate.
bool meets(const DBox& b, const double o[3], const double d[3], double t0, double t1) {
    long double lo = t0, hi = t1;
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0) {
            if (o[a] < b.lo[a] || o[a] > b.hi[a]) return false;
            continue;
        }
        long double ta = ((long double)b.lo[a] - o[a]) / d[a];
        long double tb = ((long double)b.hi[a] - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        lo = std::max(lo, ta);
        hi = std::min(hi, tb);
        if (lo > hi) return false;
    }
    return true;
}

double pointBox(const DBox& b, const double p[3]) {
    double d2 = 0.0;
    for (int a = 0; a < 3; ++a) {
        const double d = std::max({b.lo[a] - p[a], 0.0, p[a] - b.hi[a]});
        d2 += d * d;
    }
    return std::sqrt(d2);
}

TEST(BoxBvh, SegmentsGetEveryBoxTheyMeet) {
    for (double centre : {0.0, 5e5, 4e6}) {
        std::mt19937_64 rng(3);
        const std::vector<DBox> boxes = randomBoxes(3000, centre, rng);
        const BoxBvh bvh(boxes, 0.0);
        for (int i = 0; i < 2000; ++i) {
            double o[3], d[3];
            for (int a = 0; a < 3; ++a) {
                o[a] = centre + 16.0 * (u01(rng) - 0.5);
                d[a] = u01(rng) - 0.5;
            }
            if (i % 4 == 0) d[i % 3] = d[(i + 1) % 3] = 0.0;  // axis-parallel
            if (i % 7 == 0) {                                 // through a box's corner exactly
                const DBox& b = boxes[rng() % boxes.size()];
                for (int a = 0; a < 3; ++a) d[a] = b.hi[a] - o[a];
            }
            const double t0 = (i % 5 == 0) ? 0.5 : 0.0;
            const double t1 = (i % 3 == 0) ? 1.0 : INFINITY;
            std::set<uint32_t> got;
            bvh.segment(o, d, t0, t1, [&](uint32_t p) {
                got.insert(p);
                return t1;
            });
            for (uint32_t p = 0; p < boxes.size(); ++p) {
                if (!meets(boxes[p], o, d, t0, t1)) continue;
                ASSERT_TRUE(got.count(p)) << "centre " << centre << " ray " << i << " box " << p;
            }
        }
    }
}

TEST(BoxBvh, NearestVisitsEveryBoxWithinTheBestDistance) {
    std::mt19937_64 rng(5);
    const std::vector<DBox> boxes = randomBoxes(2000, 0.0, rng);
    const BoxBvh bvh(boxes, 0.0);
    for (int i = 0; i < 2000; ++i) {
        double p[3];
        for (int a = 0; a < 3; ++a) p[a] = 14.0 * (u01(rng) - 0.5);
        double bestBrute = INFINITY;
        uint32_t idBrute = 0;
        for (uint32_t k = 0; k < boxes.size(); ++k) {
            const double d = pointBox(boxes[k], p);
            if (d < bestBrute) bestBrute = d, idBrute = k;
        }
        double best = INFINITY;
        uint32_t id = UINT32_MAX;
        bvh.nearest(p, best, [&](uint32_t k) {
            const double d = pointBox(boxes[k], p);
            if (d < best || (d == best && k < id)) id = k;
            return d;
        });
        ASSERT_EQ(best, bestBrute) << i;
        ASSERT_EQ(id, idBrute) << i;
    }
}

TEST(BoxBvh, EmptyAndSingleBoxes) {
    const BoxBvh empty({}, 0.0);
    const double o[3] = {0, 0, 0}, d[3] = {1, 0, 0};
    int calls = 0;
    empty.segment(o, d, 0.0, INFINITY, [&](uint32_t) { return ++calls, INFINITY; });
    EXPECT_EQ(calls, 0);
    const BoxBvh one({{{1, -1, -1}, {2, 1, 1}}}, 0.0);
    one.segment(o, d, 0.0, INFINITY, [&](uint32_t) { return ++calls, INFINITY; });
    EXPECT_EQ(calls, 1);
    one.segment(o, d, 0.0, 0.5, [&](uint32_t) { return ++calls, INFINITY; });
    EXPECT_EQ(calls, 1);  // the segment ends before the box
}

}  // namespace
}  // namespace oct
