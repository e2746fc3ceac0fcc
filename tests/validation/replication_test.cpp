// The replication check (validation/exact/replication.h): the builder's leaf lists against CGAL's
// exact overlap test. No false negatives on real meshes and a generated cloud; a primitive
// removed from one leaf on purpose is found and named; an extra one is a counted false positive.
#include "validation/exact/replication.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "tests/validation/fixtures.h"
#include "validation/exact/exact_overlap.h"
#include "validation/report/report.h"

namespace oct {
namespace {

using octtest::meshPath;

TEST(Replication, NoFalseNegativesOnCommittedMeshes) {
    for (const std::string& name : octtest::committedMeshes()) {
        Scene scene = loadScene(meshPath(name));
        Octree tree = buildOctree(scene, BuildParams{});
        ReplicationReport r = checkReplication(scene, tree);
        SCOPED_TRACE(name);
        EXPECT_EQ(r.falseNegatives, 0u) << humanSummary(r);
        EXPECT_TRUE(r.passes());
        EXPECT_EQ(r.octreeFaces, tree.referenceCount());
        EXPECT_EQ(r.primitives, scene.primitiveCount());
        EXPECT_EQ(r.indexOutOfRange + r.duplicateEntries, 0u);
        EXPECT_GE(r.exactOverlaps + r.falsePositives, r.octreeFaces);
        // The builder pads its test by a relative 1e-9: anything it adds is that close.
        EXPECT_LE(r.maxFalsePositiveGap, 1e-6);
        uint64_t prims = 0, refs = 0;
        for (const auto& [count, n] : r.distribution) {
            prims += n;
            refs += uint64_t(count) * n;
        }
        EXPECT_EQ(prims, r.primitives);
        EXPECT_EQ(refs, r.octreeFaces);
    }
}

TEST(Replication, GridCloudHasOneLeafPerSphere) {
    Scene scene = makeGridCloud(4000, 3);
    Octree tree = buildOctree(scene, BuildParams{});
    ReplicationReport r = checkReplication(scene, tree);
    EXPECT_TRUE(r.passes());
    EXPECT_EQ(r.falseNegatives + r.falsePositives, 0u);
    ASSERT_EQ(r.distribution.size(), 1u);
    EXPECT_EQ(r.distribution.begin()->first, 1u);
    EXPECT_EQ(r.octreeFaces, 4000u);
}

// A leaf and one of its triangles that overlaps the leaf robustly (the box shrunk by 1% still
// overlaps), so removing it is a certain false negative.
bool pickRobustEntry(const Scene& scene, const Octree& tree, uint32_t& leaf, uint32_t& slot) {
    for (uint32_t k = 0; k < tree.nodes.size(); ++k) {
        const OctreeNode& n = tree.nodes[k];
        if (n.nodeType() != NodeType::Leaf || n.primCount < 2) continue;
        Aabb shrunk = n.box;
        Vec3 d = n.box.extent() * 0.01f;
        shrunk.lo = shrunk.lo + d;
        shrunk.hi = shrunk.hi - d;
        for (uint32_t j = 0; j < n.primCount; ++j)
            if (exactTriangleBoxOverlap(scene.triangles[tree.primIndices[n.primOffset + j]],
                                        shrunk)) {
                leaf = k;
                slot = j;
                return true;
            }
    }
    return false;
}

TEST(Replication, RemovedEntryIsOneNamedFalseNegative) {
    Scene scene = loadScene(meshPath("wuson.obj"));
    Octree tree = buildOctree(scene, BuildParams{});
    uint32_t leaf = 0, slot = 0;
    ASSERT_TRUE(pickRobustEntry(scene, tree, leaf, slot));
    OctreeNode& n = tree.nodes[leaf];
    const uint32_t prim = tree.primIndices[n.primOffset + slot];
    // Remove it from the leaf's list: swap it to the list's end and shorten the list. The index
    // array keeps its size, so no other leaf moves.
    std::swap(tree.primIndices[n.primOffset + slot],
              tree.primIndices[n.primOffset + n.primCount - 1]);
    --n.primCount;
    ReplicationReport r = checkReplication(scene, tree);
    EXPECT_FALSE(r.passes());
    EXPECT_EQ(r.falseNegatives, 1u);
    ASSERT_EQ(r.falseNegativeList.size(), 1u);
    EXPECT_EQ(r.falseNegativeList[0].prim, prim);
    EXPECT_EQ(r.falseNegativeList[0].leafKey, n.key);
    EXPECT_EQ(r.falseNegativeList[0].node, leaf);
    nlohmann::json j = toJson(r);
    EXPECT_EQ(j["false_negatives"], 1);
    EXPECT_EQ(j["false_negative_list"][0]["prim"], prim);
    EXPECT_EQ(j["false_negative_list"][0]["leaf_key"], n.key);
    std::string text = humanSummary(r);
    EXPECT_NE(text.find("primitive " + std::to_string(prim)), std::string::npos) << text;
    EXPECT_NE(text.find("leaf key " + std::to_string(n.key)), std::string::npos) << text;
}

TEST(Replication, ExtraEntryIsACountedFalsePositiveWithItsGap) {
    Scene scene = loadScene(meshPath("cube_binary.ply"));  // unit cube, 12 triangles
    Octree tree = buildOctree(scene, BuildParams{1, 1});   // the root and 8 leaves
    ASSERT_EQ(tree.nodes.size(), 9u);
    // A leaf that does not list triangle t, and t's gap to it: list t there as well.
    uint32_t target = 0, prim = 0;
    double gap = 0.0;
    for (uint32_t k = 1; k < 9 && gap == 0.0; ++k)
        for (uint32_t t = 0; t < 12; ++t) {
            const OctreeNode& n = tree.nodes[k];
            auto b = tree.primIndices.begin() + n.primOffset;
            if (std::find(b, b + n.primCount, t) != b + n.primCount) continue;
            double g = triangleBoxGap(scene.triangles[t], n.box);
            if (g > 0.0) {
                target = k, prim = t, gap = g;
                break;
            }
        }
    ASSERT_GT(gap, 0.0);
    // Append to the index array and point the leaf at a fresh copy of its list plus t.
    OctreeNode& n = tree.nodes[target];
    std::vector<uint32_t> list(tree.primIndices.begin() + n.primOffset,
                               tree.primIndices.begin() + n.primOffset + n.primCount);
    list.push_back(prim);
    n.primOffset = uint32_t(tree.primIndices.size());
    n.primCount = uint32_t(list.size());
    tree.primIndices.insert(tree.primIndices.end(), list.begin(), list.end());
    ReplicationReport r = checkReplication(scene, tree);
    // A false positive costs time, not hits, but one this far from its leaf (a whole cell,
    // far beyond the builder's 1e-9 padding) means the builder's overlap test is wrong: a
    // dropped separating axis looks exactly like this. It fails (kMaxFalsePositiveGap).
    EXPECT_FALSE(r.passes());
    EXPECT_EQ(r.wideFalsePositives, 1u);
    EXPECT_NE(humanSummary(r).find("wider than"), std::string::npos) << humanSummary(r);
    EXPECT_EQ(r.falseNegatives, 0u);
    EXPECT_EQ(r.falsePositives, 1u);
    ASSERT_EQ(r.falsePositiveList.size(), 1u);
    EXPECT_EQ(r.falsePositiveList[0].prim, prim);
    EXPECT_EQ(r.falsePositiveList[0].node, target);
    Vec3 e = n.box.extent();
    EXPECT_NEAR(r.falsePositiveList[0].gap, gap / double(std::max({e.x, e.y, e.z})), 1e-12);
}

// A stored box that is not the subdivision's cell (here one leaf shrunk by 1e-4 of its edge,
// its list unchanged) loses hits along the gap, which the lists alone cannot show: the tiling
// check names the node and fails.
TEST(Replication, ShrunkNodeBoxIsATilingError) {
    Scene scene = loadScene(meshPath("teapot.obj"));
    Octree tree = buildOctree(scene, BuildParams{});
    ASSERT_TRUE(checkReplication(scene, tree).passes());
    uint32_t leaf = 0;
    while (tree.nodes[leaf].nodeType() != NodeType::Leaf) ++leaf;
    Aabb& b = tree.nodes[leaf].box;
    const float s = 1e-4f * (b.hi.x - b.lo.x);
    b.lo = b.lo + makeVec3(s);
    b.hi = b.hi - makeVec3(s);
    ReplicationReport r = checkReplication(scene, tree);
    EXPECT_FALSE(r.passes());
    EXPECT_EQ(r.tilingErrors, 1u);
    ASSERT_FALSE(r.structuralErrors.empty());
    EXPECT_NE(r.structuralErrors[0].find("node " + std::to_string(leaf) + " "), std::string::npos)
        << r.structuralErrors[0];
}

// The check diagnoses broken trees, so a broken range must be reported, not read through.
TEST(Replication, BrokenNodeRangesAreNamedStructuralErrors) {
    Scene scene = loadScene(meshPath("cube_binary.ply"));
    const Octree good = buildOctree(scene, BuildParams{1, 1});  // the root and 8 leaves
    ASSERT_EQ(good.nodes.size(), 9u);
    uint32_t leaf = 1;
    while (leaf < 9 && good.nodes[leaf].primCount == 0) ++leaf;
    ASSERT_LT(leaf, 9u);
    auto named = [](const ReplicationReport& r, uint32_t node) {
        return r.structuralErrors.size() == 1 &&
               r.structuralErrors[0].rfind("node " + std::to_string(node) + " ", 0) == 0;
    };

    Octree tree = good;  // a leaf list past the end of the index array
    tree.nodes[leaf].primOffset = uint32_t(tree.primIndices.size()) + 1000;
    ReplicationReport r = checkReplication(scene, tree);
    EXPECT_FALSE(r.passes());
    EXPECT_EQ(r.rangeErrors, 1u);
    EXPECT_TRUE(named(r, leaf)) << (r.structuralErrors.empty() ? "" : r.structuralErrors[0]);
    EXPECT_GT(r.falseNegatives, 0u) << "the leaf's triangles are listed nowhere else";

    tree = good;  // offset + count wraps around in 32 bits
    tree.nodes[leaf].primOffset = 0xfffffff0u;
    tree.nodes[leaf].primCount = 0x20u;
    r = checkReplication(scene, tree);
    EXPECT_EQ(r.rangeErrors, 1u);
    EXPECT_TRUE(named(r, leaf));

    tree = good;  // the root's children past the end of the node array
    tree.firstChild[0] = uint32_t(tree.nodes.size()) - 3;
    r = checkReplication(scene, tree);
    EXPECT_FALSE(r.passes());
    EXPECT_EQ(r.rangeErrors, 1u);
    EXPECT_TRUE(named(r, 0)) << (r.structuralErrors.empty() ? "" : r.structuralErrors[0]);

    tree = good;  // the root as its own child: a walk that would never end
    tree.firstChild[0] = 0;
    r = checkReplication(scene, tree);
    EXPECT_EQ(r.rangeErrors, 1u);
    EXPECT_TRUE(named(r, 0));

    EXPECT_TRUE(checkReplication(scene, good).passes());
}

TEST(Replication, RejectsATreeOfAnotherScene) {
    Scene a = loadScene(meshPath("cube_binary.ply"));
    Scene b = loadScene(meshPath("teapot.obj"));
    Octree tree = buildOctree(a, BuildParams{});
    EXPECT_THROW(checkReplication(b, tree), std::invalid_argument);
}

}  // namespace
}  // namespace oct
