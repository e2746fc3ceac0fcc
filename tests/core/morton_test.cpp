// Morton keys (core/octree/morton.h) against references written with explicit bit loops, the
// linear index against a breadth-first enumeration of the complete tree, and the octant digit
// convention against childBox() (core/geometry/aabb.h).
#include "core/octree/morton.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <random>
#include <vector>

#include "core/geometry/aabb.h"

namespace oct {
namespace {

// Reference encoder: one octant digit per level, most significant level first, digit bit 0
// from x, bit 1 from y, bit 2 from z; the leading 1 is the root.
uint64_t refEncode(uint32_t x, uint32_t y, uint32_t z, int depth) {
    uint64_t key = 1;
    for (int level = depth - 1; level >= 0; --level) {
        uint64_t digit =
            ((x >> level) & 1u) | (((y >> level) & 1u) << 1) | (((z >> level) & 1u) << 2);
        key = key * 8 + digit;
    }
    return key;
}

// Reference depth: index of the highest set bit, found by scanning all 64 bits, divided by 3.
int refDepth(uint64_t key) {
    int msb = -1;
    for (int b = 0; b < 64; ++b)
        if ((key >> b) & 1u) msb = b;
    return msb / 3;
}

// Reference decoder: read the digits back, least significant level first.
void refDecode(uint64_t key, uint32_t& x, uint32_t& y, uint32_t& z) {
    int d = refDepth(key);
    x = y = z = 0;
    for (int level = 0; level < d; ++level) {
        uint64_t digit = (key >> (3 * level)) & 7u;
        x |= uint32_t(digit & 1u) << level;
        y |= uint32_t((digit >> 1) & 1u) << level;
        z |= uint32_t((digit >> 2) & 1u) << level;
    }
}

uint64_t randomKey(std::mt19937_64& rng, int depth) {
    uint64_t key = 1;
    for (int i = 0; i < depth; ++i) key = key * 8 + (rng() & 7u);
    return key;
}

TEST(Morton, EncodeDecodeRoundTripRandomCells) {
    std::mt19937_64 rng(12345);
    for (int iter = 0; iter < 200000; ++iter) {
        int depth = static_cast<int>(rng() % (kMaxOctreeDepth + 1));
        uint32_t mask = depth == 0 ? 0u : ((1u << depth) - 1u);
        uint32_t x = static_cast<uint32_t>(rng()) & mask;
        uint32_t y = static_cast<uint32_t>(rng()) & mask;
        uint32_t z = static_cast<uint32_t>(rng()) & mask;
        uint64_t key = encodeMorton(x, y, z, depth);
        ASSERT_EQ(key, refEncode(x, y, z, depth)) << x << " " << y << " " << z << " d" << depth;
        ASSERT_EQ(keyDepth(key), depth);
        uint32_t dx, dy, dz;
        decodeMorton(key, dx, dy, dz);
        ASSERT_EQ(dx, x);
        ASSERT_EQ(dy, y);
        ASSERT_EQ(dz, z);
        uint32_t rx, ry, rz;
        refDecode(key, rx, ry, rz);
        ASSERT_EQ(rx, x);
        ASSERT_EQ(ry, y);
        ASSERT_EQ(rz, z);
    }
}

TEST(Morton, ExtremeCells) {
    const uint32_t maxCoord = (1u << kMaxOctreeDepth) - 1u;
    // The deepest, all-ones cell fills all 64 bits.
    EXPECT_EQ(encodeMorton(maxCoord, maxCoord, maxCoord, kMaxOctreeDepth), ~uint64_t(0));
    EXPECT_EQ(keyDepth(~uint64_t(0)), kMaxOctreeDepth);
    EXPECT_EQ(encodeMorton(0, 0, 0, kMaxOctreeDepth), uint64_t(1) << 63);
    EXPECT_EQ(encodeMorton(0, 0, 0, 0), kRootKey);
    EXPECT_EQ(keyDepth(kRootKey), 0);
    uint32_t x, y, z;
    decodeMorton(~uint64_t(0), x, y, z);
    EXPECT_EQ(x, maxCoord);
    EXPECT_EQ(y, maxCoord);
    EXPECT_EQ(z, maxCoord);
    // One axis at a time: x is digit bit 0, y bit 1, z bit 2.
    EXPECT_EQ(encodeMorton(1, 0, 0, 1), 0b1001u);
    EXPECT_EQ(encodeMorton(0, 1, 0, 1), 0b1010u);
    EXPECT_EQ(encodeMorton(0, 0, 1, 1), 0b1100u);
    EXPECT_EQ(encodeMorton(2, 0, 0, 2), 0b1001000u);
}

TEST(Morton, KeyArithmeticMatchesBitLoops) {
    std::mt19937_64 rng(777);
    for (int iter = 0; iter < 100000; ++iter) {
        int depth = static_cast<int>(rng() % kMaxOctreeDepth);  // room for one more level
        uint64_t key = randomKey(rng, depth);
        int octant = static_cast<int>(rng() & 7u);
        uint64_t child = childKey(key, octant);
        // Reference child: append the three bits of the octant one at a time.
        uint64_t refChild = key;
        for (int b = 2; b >= 0; --b) refChild = refChild * 2 + ((octant >> b) & 1);
        ASSERT_EQ(child, refChild);
        ASSERT_EQ(parentKey(child), key);
        ASSERT_EQ(octantOf(child), octant);
        ASSERT_EQ(keyDepth(child), depth + 1);
        ASSERT_EQ(keyDepth(key), refDepth(key));
        ASSERT_EQ(refDepth(child), depth + 1);
        // Reference parent: drop the last three bits by division.
        ASSERT_EQ(parentKey(key), key / 8);
        ASSERT_EQ(octantOf(key), static_cast<int>(key % 8));
    }
}

TEST(Morton, LinearIndexMatchesBreadthFirstEnumeration) {
    for (int maxDepth = 0; maxDepth <= 4; ++maxDepth) {
        // Enumerate the complete tree level by level; a node's children are queued in octant
        // order, which is the order the 8p+1+i rule assigns their positions.
        std::deque<uint64_t> queue = {kRootKey};
        std::vector<uint64_t> order;
        while (!queue.empty()) {
            uint64_t k = queue.front();
            queue.pop_front();
            order.push_back(k);
            if (refDepth(k) < maxDepth)
                for (int i = 0; i < 8; ++i) queue.push_back(k * 8 + i);
        }
        uint64_t expectedCount = 0, level = 1;
        for (int d = 0; d <= maxDepth; ++d, level *= 8) expectedCount += level;
        ASSERT_EQ(order.size(), expectedCount);
        for (uint64_t pos = 0; pos < order.size(); ++pos) {
            uint64_t k = order[pos];
            ASSERT_EQ(linearIndexOfKey(k), pos) << "key " << k;
            if (refDepth(k) < maxDepth) {
                for (int i = 0; i < 8; ++i)
                    ASSERT_EQ(linearIndexOfKey(childKey(k, i)), 8 * pos + 1 + i);
            }
        }
    }
}

TEST(Morton, LinearIndexChildrenRuleAtDepth) {
    std::mt19937_64 rng(99);
    for (int iter = 0; iter < 20000; ++iter) {
        int depth = static_cast<int>(rng() % 20);  // 8p+8 still fits 64 bits below depth 20
        uint64_t key = randomKey(rng, depth);
        uint64_t p = linearIndexOfKey(key);
        for (int i = 0; i < 8; ++i) ASSERT_EQ(linearIndexOfKey(childKey(key, i)), 8 * p + 1 + i);
        // Parent from position: (c - 1) / 8.
        if (depth > 0) {
            ASSERT_EQ((p - 1) / 8, linearIndexOfKey(parentKey(key)));
        }
    }
}

TEST(Morton, ChildBoxOctantConvention) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-10.0f, 10.0f);
    for (int iter = 0; iter < 1000; ++iter) {
        Aabb parent;
        for (int a = 0; a < 3; ++a) {
            float p = u(rng), q = u(rng);
            parent.lo[a] = std::min(p, q);
            parent.hi[a] = std::max(p, q) + 0.5f;
        }
        Vec3 c = parent.center();
        double vol = 0.0;
        for (int i = 0; i < 8; ++i) {
            Aabb b = childBox(parent, i);
            for (int a = 0; a < 3; ++a) {
                bool upper = (i >> a) & 1;
                EXPECT_EQ(b.lo[a], upper ? c[a] : parent.lo[a]) << "octant " << i << " axis " << a;
                EXPECT_EQ(b.hi[a], upper ? parent.hi[a] : c[a]) << "octant " << i << " axis " << a;
            }
            Vec3 e = b.extent();
            vol += double(e.x) * e.y * e.z;
        }
        Vec3 pe = parent.extent();
        EXPECT_NEAR(vol, double(pe.x) * pe.y * pe.z, 1e-4 * double(pe.x) * pe.y * pe.z);
    }
}

// Descending from the root with childBox() towards a point reaches the cell that encodeMorton
// names. The root is [0, 2^21]^3 so that every cell boundary down to depth 21 is an exact float
// and the cell centres (odd multiples of half a cell) are exact too: no rounding ambiguity.
TEST(Morton, DescentWithChildBoxMatchesEncode) {
    const float side = float(1u << kMaxOctreeDepth);
    const Aabb root = {{0.0f, 0.0f, 0.0f}, {side, side, side}};
    std::mt19937_64 rng(2024);
    for (int iter = 0; iter < 5000; ++iter) {
        int depth = static_cast<int>(rng() % (kMaxOctreeDepth + 1));
        uint32_t mask = depth == 0 ? 0u : ((1u << depth) - 1u);
        uint32_t cell[3];
        Vec3 p;
        float cellSize = side / float(1u << depth);
        for (int a = 0; a < 3; ++a) {
            cell[a] = static_cast<uint32_t>(rng()) & mask;
            p[a] = (float(cell[a]) + 0.5f) * cellSize;  // exact: needs at most 22 bits
        }
        uint64_t key = kRootKey;
        Aabb box = root;
        for (int level = 0; level < depth; ++level) {
            Vec3 c = box.center();
            int octant = (p.x >= c.x ? 1 : 0) | (p.y >= c.y ? 2 : 0) | (p.z >= c.z ? 4 : 0);
            box = childBox(box, octant);
            ASSERT_TRUE(box.contains(p));
            key = childKey(key, octant);
        }
        ASSERT_EQ(key, encodeMorton(cell[0], cell[1], cell[2], depth));
        // The box reached is the cell's box.
        for (int a = 0; a < 3; ++a) {
            ASSERT_EQ(box.lo[a], float(cell[a]) * cellSize);
            ASSERT_EQ(box.hi[a], float(cell[a] + 1) * cellSize);
        }
    }
}

// The same on an arbitrary (non power-of-two) root box with random points: the key reached by
// descent decodes to the cell whose nominal box contains the point (up to float rounding).
TEST(Morton, DescentOnArbitraryBoxDecodesToContainingCell) {
    std::mt19937_64 rng(31);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    for (int iter = 0; iter < 5000; ++iter) {
        Aabb root;
        for (int a = 0; a < 3; ++a) {
            root.lo[a] = float(-50.0 + 40.0 * u01(rng));
            root.hi[a] = root.lo[a] + float(1.0 + 60.0 * u01(rng));
        }
        int depth = static_cast<int>(rng() % 11);
        Vec3 p;
        for (int a = 0; a < 3; ++a)
            p[a] = float(root.lo[a] + u01(rng) * (double(root.hi[a]) - root.lo[a]));
        uint64_t key = kRootKey;
        Aabb box = root;
        for (int level = 0; level < depth; ++level) {
            Vec3 c = box.center();
            int octant = (p.x >= c.x ? 1 : 0) | (p.y >= c.y ? 2 : 0) | (p.z >= c.z ? 4 : 0);
            box = childBox(box, octant);
            key = childKey(key, octant);
        }
        ASSERT_TRUE(box.contains(p));
        ASSERT_EQ(keyDepth(key), depth);
        uint32_t cell[3];
        decodeMorton(key, cell[0], cell[1], cell[2]);
        double n = double(1u << depth);
        for (int a = 0; a < 3; ++a) {
            double size = (double(root.hi[a]) - root.lo[a]) / n;
            double lo = root.lo[a] + cell[a] * size;
            double tol = 1e-5 * (std::fabs(root.lo[a]) + std::fabs(root.hi[a]));
            ASSERT_NEAR(box.lo[a], lo, tol);
            ASSERT_NEAR(box.hi[a], lo + size, tol);
            ASSERT_GE(p[a], lo - tol);
            ASSERT_LE(p[a], lo + size + tol);
        }
    }
}

}  // namespace
}  // namespace oct
