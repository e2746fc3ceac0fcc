// The compact layout holds the canonical octree exactly: every internal node and non-empty leaf
// once, in child-descriptor form, with the boxes traversal derives by halving equal, bit for
// bit, to the canonical nodes' boxes, and the leaf lists unchanged. (Its traversal is checked
// against exhaustive tracing with every other layout in traversal_test.cpp.)
#include "core/octree/compact_octree.h"

#include <gtest/gtest.h>

#include <cstring>
#include <map>
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

Scene mesh(const std::string& name) {
    return loadScene(std::string(OCT_SOURCE_DIR) + "/meshes/" + name);
}

TEST(CompactOctree, HoldsTheCanonicalTreeExactly) {
    for (const char* m : {"teapot.obj", "cornell_box.obj", "spider.obj", "sphere_with_hole.stl"})
        for (BuildParams p : {BuildParams{7, 8}, BuildParams{10, 1}, BuildParams{3, 4}}) {
            SCOPED_TRACE(std::string(m) + " depth " + std::to_string(p.maxDepth));
            checkAgainstCanonical(buildOctree(mesh(m), p));
        }
    checkAgainstCanonical(buildOctree(makeGridCloud(4096, 3), {kMaxOctreeDepth, 1}));
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

TEST(CompactOctree, ReportsEightBytesANodeAndSharesTheLeafLists) {
    Scene s = mesh("teapot.obj");
    auto tree = std::make_shared<const Octree>(buildOctree(s, {}));
    BuiltScene b = convertLayout(s, tree, findLayout("compact"), {});
    const uint64_t records = buildCompact(*tree).nodes.size();
    EXPECT_EQ(b.layoutBytes(), records * 8 + tree->primIndices.size() * 4);
    LayoutReport r = findLayout("compact").report(*tree, {});
    EXPECT_EQ(r.bytes, b.layoutBytes());
    // Against the paper's complete array of 48-byte records.
    EXPECT_LT(r.bytes * 20, findLayout("linear").report(*tree, {}).bytes);
}

}  // namespace
}  // namespace oct
