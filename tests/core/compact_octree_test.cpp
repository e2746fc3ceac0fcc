// The compact layout holds the canonical octree exactly: every internal node and non-empty leaf
// once, in child-descriptor form, with the boxes traversal derives by halving equal, bit for
// bit, to the canonical nodes' boxes, and the leaf lists unchanged. (Its traversal is checked
// against exhaustive tracing with every other layout in traversal_test.cpp.)
#include "core/octree/compact_octree.h"

#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <random>
#include <string>

#include "core/octree/built_scene.h"
#include "core/scene/grid_cloud.h"
#include "core/scene/load_scene.h"

namespace oct {
namespace {

bool sameBits(const Aabb& a, const Aabb& b) { return std::memcmp(&a, &b, sizeof(Aabb)) == 0; }

// Walks the compact records from the root, deriving each child's box and key as traversal does,
// and checks every record against the canonical node with that key.
void checkAgainstCanonical(const Octree& t) {
    const CompactOctree c = buildCompact(t);
    std::map<uint64_t, const OctreeNode*> byKey;
    uint64_t storedCanonical = 0;
    for (const OctreeNode& n : t.nodes) {
        byKey[n.key] = &n;
        storedCanonical += n.nodeType() == NodeType::Internal ||
                           (n.nodeType() == NodeType::Leaf && n.primCount > 0);
    }
    ASSERT_EQ(c.nodes.size(), storedCanonical) << "internal nodes and non-empty leaves, once each";
    ASSERT_TRUE(sameBits(c.rootBox, t.root));

    struct Item {
        uint32_t index;
        bool leaf;
        uint64_t key;
        Aabb box;
    };
    std::vector<Item> todo = {{0, c.rootIsLeaf, kRootKey, c.rootBox}};
    std::vector<int> seen(c.nodes.size(), 0);
    while (!todo.empty()) {
        Item it = todo.back();
        todo.pop_back();
        ASSERT_LT(it.index, c.nodes.size());
        ++seen[it.index];
        auto found = byKey.find(it.key);
        ASSERT_NE(found, byKey.end()) << "key " << it.key;
        const OctreeNode& n = *found->second;
        EXPECT_TRUE(sameBits(it.box, n.box)) << "derived box of key " << it.key;
        const CompactNode& rec = c.nodes[it.index];
        if (it.leaf) {
            ASSERT_EQ(n.nodeType(), NodeType::Leaf) << "key " << it.key;
            EXPECT_EQ(rec.primOffset(), n.primOffset);
            EXPECT_EQ(rec.primCount(), n.primCount);
            continue;
        }
        ASSERT_EQ(n.nodeType(), NodeType::Internal) << "key " << it.key;
        EXPECT_EQ(rec.leafMask() & ~rec.childMask(), 0u) << "leaves are a subset of the children";
        uint32_t next = rec.firstChild();
        for (int i = 0; i < 8; ++i) {
            const uint64_t k = childKey(it.key, i);
            const OctreeNode& ch = *byKey.at(k);
            const bool stored = ch.nodeType() == NodeType::Internal || ch.primCount > 0;
            EXPECT_EQ(bool(rec.childMask() & (1u << i)), stored) << "child key " << k;
            if (!stored) continue;
            todo.push_back({next++, bool(rec.leafMask() & (1u << i)), k, childBox(it.box, i)});
        }
    }
    for (size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], 1) << "record " << i;
}

bool inside(const Aabb& b, Vec3 p) {
    return p.x >= b.lo.x && p.x <= b.hi.x && p.y >= b.lo.y && p.y <= b.hi.y && p.z >= b.lo.z &&
           p.z <= b.hi.z;
}

// Every point of a leaf's primitives that lies in the leaf's cell lies in the dequantised
// bounds of the leaf and of every ancestor: points on the triangles (vertices, edge points and
// random interior points) and on the spheres, checked in float as the kernel compares.
void checkBoundsContainGeometry(const Scene& scene, const Octree& t) {
    const CompactOctree c = buildCompact(t, &scene);
    ASSERT_EQ(c.bounds.size(), c.nodes.size());
    std::mt19937_64 rng(5);
    auto u = [&] { return float(double(rng() >> 11) * 0x1.0p-53); };
    struct Item {
        uint32_t index;
        bool leaf;
        Aabb cell;
        std::vector<Aabb> bounds;  // this record's and its ancestors'
    };
    std::vector<Item> todo = {{0, c.rootIsLeaf, c.rootBox, {}}};
    uint64_t checked = 0;
    while (!todo.empty()) {
        Item it = todo.back();
        todo.pop_back();
        it.bounds.push_back(dequantize(c.bounds[it.index], it.cell));
        const CompactNode& rec = c.nodes[it.index];
        if (!it.leaf) {
            uint32_t next = rec.firstChild();
            for (int i = 0; i < 8; ++i)
                if (rec.childMask() & (1u << i))
                    todo.push_back({next++, bool(rec.leafMask() & (1u << i)), childBox(it.cell, i),
                                    it.bounds});
            continue;
        }
        for (uint32_t k = 0; k < rec.primCount(); ++k) {
            const uint32_t prim = t.primIndices[rec.primOffset() + k];
            std::vector<Vec3> pts;
            if (scene.kind == PrimKind::Triangles) {
                const Triangle& tr = scene.triangles[prim];
                pts = {tr.v0, tr.v1, tr.v2};
                for (int n = 0; n < 200; ++n) {
                    float a = u(), b = u();
                    if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
                    pts.push_back(tr.v0 + (tr.v1 - tr.v0) * a + (tr.v2 - tr.v0) * b);
                    pts.push_back(tr.v0 + (tr.v1 - tr.v0) * u());
                }
            } else {
                const Sphere& sp = scene.spheres[prim];
                for (int n = 0; n < 200; ++n) {
                    Vec3 d = {u() - 0.5f, u() - 0.5f, u() - 0.5f};
                    pts.push_back(sp.center + normalize(d) * sp.radius);
                }
            }
            for (Vec3 p : pts) {
                if (!inside(it.cell, p)) continue;
                ++checked;
                for (const Aabb& b : it.bounds)
                    ASSERT_TRUE(inside(b, p)) << "prim " << prim << " point outside the bounds";
            }
        }
    }
    EXPECT_GT(checked, 1000u);
}

Scene mesh(const std::string& name) {
    return loadScene(std::string(OCT_SOURCE_DIR) + "/meshes/" + name);
}

// The bit helpers the child indices and the front-to-back order rest on, over every mask.
TEST(CompactOctree, BitHelpersOverEveryMask) {
    for (uint32_t m = 0; m < 256; ++m) {
        uint32_t count = 0;
        for (int b = 0; b < 8; ++b) count += (m >> b) & 1u;
        ASSERT_EQ(oct::compact_detail::bitCount8(m), count) << m;
        for (int flip = 0; flip < 8; ++flip) {
            const uint32_t p = oct::compact_detail::xorPermute(m, flip);
            for (int j = 0; j < 8; ++j)
                ASSERT_EQ((p >> j) & 1u, (m >> (j ^ flip)) & 1u) << m << " " << flip << " " << j;
        }
        if (m) {
            int high = 7;
            while (!((m >> high) & 1u)) --high;
            ASSERT_EQ(oct::compact_detail::highestBit(m), high) << m;
        }
    }
}

TEST(CompactOctree, HoldsTheCanonicalTreeExactly) {
    for (const char* m : {"teapot.obj", "cornell_box.obj", "spider.obj", "sphere_with_hole.stl"})
        for (BuildParams p : {BuildParams{7, 8}, BuildParams{10, 1}, BuildParams{3, 4}}) {
            SCOPED_TRACE(std::string(m) + " depth " + std::to_string(p.maxDepth));
            checkAgainstCanonical(buildOctree(mesh(m), p));
        }
    checkAgainstCanonical(buildOctree(makeGridCloud(4096, 3), {kMaxOctreeDepth, 1}));
}

TEST(CompactOctree, BoundsContainWhatEachCellHolds) {
    for (const char* m : {"teapot.obj", "spider.obj", "cornell_box.obj"}) {
        SCOPED_TRACE(m);
        Scene s = mesh(m);
        checkBoundsContainGeometry(s, buildOctree(s, {7, 8}));
    }
    Scene cloud = makeGridCloud(2000, 9);
    checkBoundsContainGeometry(cloud, buildOctree(cloud, {kMaxOctreeDepth, 1}));
}

TEST(CompactOctree, WholeTreeInOneLeafAndEmptyLeavesAreNotStored) {
    Scene s = mesh("cube_binary.ply");  // 12 triangles
    Octree oneLeaf = buildOctree(s, {7, 64});
    ASSERT_EQ(oneLeaf.nodes.size(), 1u);
    CompactOctree c = buildCompact(oneLeaf);
    EXPECT_TRUE(c.rootIsLeaf);
    ASSERT_EQ(c.nodes.size(), 1u);
    EXPECT_EQ(c.nodes[0].primCount(), 12u);
    checkAgainstCanonical(oneLeaf);

    // A ray through the one leaf hits the cube; one missing the root box tests nothing.
    BuiltScene b = buildScene(s, findLayout("compact"), {{7, 64}, {}, kDefaultLinearBudget});
    const Aabb box = s.bounds();
    const Vec3 c0 = box.center();
    TraceCost cost = {0, 0};
    b.visit([&](const auto& v) {
        Hit h = closestHit(v, {{c0.x, c0.y, box.hi.z + 1.0f}, {0, 0, -1}, 0.0f, INFINITY}, cost);
        EXPECT_GE(h.prim, 0);
        TraceCost missCost = {0, 0};
        Hit m = closestHit(v, {{box.hi.x + 5.0f, c0.y, c0.z}, {0, 1, 0}, 0.0f, INFINITY}, missCost);
        EXPECT_LT(m.prim, 0);
        EXPECT_EQ(missCost.primsTested, 0u);
        EXPECT_EQ(missCost.nodesVisited, 1u);
    });

    // A deeper tree of the same cube: 8 children at depth 1, empty ones absent.
    Octree split = buildOctree(s, {1, 1});
    uint64_t empty = 0;
    for (const OctreeNode& n : split.nodes) empty += n.nodeType() == NodeType::EmptyLeaf;
    EXPECT_EQ(buildCompact(split).nodes.size(), split.nodes.size() - empty);
    checkAgainstCanonical(split);
}

TEST(CompactOctree, ReportsSixteenBytesANodeAndSharesTheLeafLists) {
    Scene s = mesh("teapot.obj");
    auto tree = std::make_shared<const Octree>(buildOctree(s, {}));
    BuiltScene b = convertLayout(s, tree, findLayout("compact"), {});
    const uint64_t records = buildCompact(*tree).nodes.size();
    // An 8-byte record and 8 bytes of bounds a node, and the canonical leaf lists.
    EXPECT_EQ(b.layoutBytes(), records * 16 + tree->primIndices.size() * 4);
    LayoutReport r = findLayout("compact").report(s, *tree, {});
    EXPECT_EQ(r.bytes, b.layoutBytes());
    // Against the paper's complete array of 48-byte records.
    EXPECT_LT(r.bytes * 20, findLayout("linear").report(s, *tree, {}).bytes);
}

}  // namespace
}  // namespace oct
