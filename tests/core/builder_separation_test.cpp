// A node whose primitives no split could separate is not split (core/octree/builder.cpp):
// identical primitives, or spheres that all contain the node, cannot be told apart by any
// number of splits, so splitting them only multiplies nodes and references. Before: 9 identical
// points built 1.34 M nodes, 1,000 identical points (a 6 KB .xyz) took 4.4 GB and 38 s before the
// reference cap refused them.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "core/octree/octree.h"
#include "core/scene/load_scene.h"

namespace oct {
namespace {

Scene identicalPoints(uint32_t n) {
    std::vector<Vec3> points(n, Vec3{1, 2, 3});
    Scene s;
    s.name = "identical points";
    s.kind = PrimKind::Spheres;
    const float r = defaultPointRadius(points);
    for (const Vec3& p : points) s.spheres.push_back({p, r});
    return s;
}

Scene copiesOfOneTriangle(uint32_t n) {
    Scene s;
    s.name = "copies";
    s.kind = PrimKind::Triangles;
    s.triangles.assign(n, Triangle{{0, 0, 0}, {1, 0.2f, 0.1f}, {0.3f, 1, 0.7f}});
    return s;
}

TEST(BuilderSeparation, IdenticalPrimitivesStayInOneLeaf) {
    for (uint32_t n : {9u, 1000u, 100000u}) {
        Octree t = buildOctree(identicalPoints(n), BuildParams{});
        EXPECT_EQ(t.nodes.size(), 1u) << n << " identical points";
        EXPECT_EQ(t.referenceCount(), n);
    }
    for (uint32_t n : {9u, 100u}) {
        Octree t = buildOctree(copiesOfOneTriangle(n), BuildParams{21, 1});
        EXPECT_EQ(t.nodes.size(), 1u) << n << " copies of one triangle";
        EXPECT_EQ(t.referenceCount(), n);
    }
}

// Distinct spheres that all contain a node cannot be separated inside it either: the nodes deep
// inside all of them stay leaves, only the nodes their surfaces cross are split.
TEST(BuilderSeparation, NodesInsideEverySphereStayLeaves) {
    Scene s;
    s.name = "nested spheres";
    s.kind = PrimKind::Spheres;
    for (int i = 0; i < 20; ++i)  // nearly concentric: their surfaces lie in a thin shell
        s.spheres.push_back({{1e-5f * float(i), 0, 0}, 1.0f + 1e-4f * float(i)});
    Octree t = buildOctree(s, BuildParams{7, 8});
    // Before: every node inside the spheres was split down to depth 7: the unit ball is 30% of
    // the root cube (side 2.4), 630,000 of its 8^7 cells, each listing all 20 spheres (12.6 M
    // references). Now only the cells the thin shell of their surfaces crosses are split.
    EXPECT_LT(t.nodes.size(), 300000u);
    EXPECT_LT(t.referenceCount(), uint64_t(5) * 1000 * 1000);
    for (const OctreeNode& n : t.nodes)
        if (n.nodeType() == NodeType::Leaf && n.primCount > 8 && n.depth < 7) {
            for (uint32_t k = 0; k < n.primCount; ++k) {
                const Sphere& sp = s.spheres[t.primIndices[n.primOffset + k]];
                EXPECT_LE(double(length(n.box.hi - sp.center)), double(sp.radius));
            }
        }
}

// Copies beside distinct geometry: the distinct part is still split as the paper says, the
// copies stop where nothing tells them apart. References stay proportional to the input.
// Flipped copies (the same vertices in another order) are copies too.
TEST(BuilderSeparation, CopiesBesideOtherGeometryCostInProportion) {
    Scene s = copiesOfOneTriangle(100);
    for (int i = 0; i < 100; i += 2) std::swap(s.triangles[i].v1, s.triangles[i].v2);
    for (int i = 0; i < 64; ++i) {  // a row of small triangles away from the copies
        float x = 2.0f + 0.05f * float(i);
        s.triangles.push_back({{x, 3, 3}, {x + 0.04f, 3, 3}, {x, 3.04f, 3}});
    }
    BuildParams p{7, 8};
    Octree t = buildOctree(s, p);
    // Every leaf holding the copies holds all of them (nothing separates them), and no more
    // than a handful of leaves do.
    uint64_t leavesWithCopies = 0;
    for (const OctreeNode& n : t.nodes) {
        if (n.nodeType() != NodeType::Leaf) continue;
        uint32_t copies = 0;
        for (uint32_t k = 0; k < n.primCount; ++k) copies += t.primIndices[n.primOffset + k] < 100;
        if (copies) ++leavesWithCopies;
    }
    EXPECT_LE(leavesWithCopies, 8u);
    EXPECT_LE(t.referenceCount(), 8u * 100 + 64 * 8) << t.nodes.size() << " nodes";
    // The small triangles were split apart: some leaf holds at most maxPrims of them.
    bool split = false;
    for (const OctreeNode& n : t.nodes)
        if (n.nodeType() == NodeType::Leaf && n.primCount > 0 && n.primCount <= p.maxPrims)
            split = true;
    EXPECT_TRUE(split);
}

// What the separation rule cannot stop (distinct large primitives crossing everywhere) meets
// the reference cap, refused while the level that would pass it is built.
TEST(BuilderSeparation, ReferenceCapRefusesWhileBuilding) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Scene s;
    s.name = "crossing";
    s.kind = PrimKind::Triangles;
    for (int i = 0; i < 100; ++i)  // large, distinct, crossing one another
        s.triangles.push_back({{u(rng), u(rng), 0}, {u(rng), 1, u(rng)}, {1, u(rng), u(rng)}});
    BuildParams p{7, 8, 20000};
    try {
        buildOctree(s, p);
        ADD_FAILURE() << "no refusal";
    } catch (const OctreeError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("20000 primitive references"), std::string::npos) << msg;
        EXPECT_NE(msg.find("--max-depth"), std::string::npos) << msg;
    }
    p.maxReferences = BuildParams{}.maxReferences;
    EXPECT_GT(buildOctree(s, p).referenceCount(), 20000u);  // the cap was what refused it
}

// Two triangles sharing a diagonal (a quad): with --max-prims 1 every cell the diagonal touches
// holds both and splits to --max-depth, the cells doubling each level (depth 21: 100 M nodes,
// 48 s and 6 GB before memory ran out). The node budget refuses the level that would pass it.
TEST(BuilderSeparation, NodeBudgetRefusesWhileBuilding) {
    Scene s;
    s.name = "quad";
    s.kind = PrimKind::Triangles;
    s.triangles = {{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}}, {{0, 0, 0}, {1, 1, 0}, {0, 1, 0}}};
    BuildParams p;
    p.maxDepth = 21;
    p.maxPrims = 1;
    p.maxNodes = 100000;
    try {
        buildOctree(s, p);
        ADD_FAILURE() << "no refusal";
    } catch (const OctreeError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("more than 100000 nodes"), std::string::npos) << msg;
        for (const char* option : {"--max-depth", "--max-prims", "--node-budget"})
            EXPECT_NE(msg.find(option), std::string::npos) << msg;
    }
    p.maxDepth = 10;  // 48777 nodes: within the budget, built as before
    const Octree t = buildOctree(s, p);
    EXPECT_LE(t.nodes.size(), p.maxNodes);
    EXPECT_GT(t.nodes.size(), 40000u);
    EXPECT_EQ(t.depth, 10);
}

}  // namespace
}  // namespace oct
