// The builder's pre-flight count along shared edges (core/octree/edge_bound.h): a lower bound on
// the nodes buildOctree makes, so a deep build that must pass the node budget is refused before
// it starts instead of after most of it is built.
#include "core/octree/edge_bound.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <random>
#include <string>

#include "core/octree/octree.h"

namespace oct {
namespace {

Scene twoTrianglesSharing(Vec3 a, Vec3 b, Vec3 c, Vec3 d, const char* name) {
    Scene s;
    s.name = name;
    s.kind = PrimKind::Triangles;
    s.triangles = {{a, b, c}, {a, c, d}};  // a-c shared
    return s;
}

// The quad: its diagonal lies in the root's middle plane and runs through cell corners
// at every level, so the cells touching it (faces and corners) are split too.
Scene unitQuad() { return twoTrianglesSharing({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, "quad"); }

uint64_t boundOf(const Scene& s, int depth) {
    const Aabb root = rootCube(s);
    const Triangle& t = s.triangles[0];
    return nodesAlongEdge(root, t.v0, t.v2, depth, UINT64_MAX).nodes;
}

// The count is a lower bound: never above the nodes the builder makes, over quads whose shared
// diagonal is axis-aligned, in a face, through corners or in general position, and over random
// pairs (which also cross each other: the cells along that line split too, uncounted). Where the
// shared edge is all that splits, it is close to them (it is what makes the refusal come early).
TEST(EdgeBound, NeverAboveTheBuiltNodesAndCloseToThem) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<Scene> scenes = {
        unitQuad(),
        twoTrianglesSharing({0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}, "xz quad"),
        twoTrianglesSharing({0, 0, 0}, {1, 0.5f, 0}, {1, 1, 1}, {0, 1, 0.25f}, "bent"),
        twoTrianglesSharing({-3, 0, 0}, {0, 1, 0}, {3, 0, 0}, {0, -1, 0}, "axis edge"),
    };
    const size_t structured = scenes.size();
    for (int i = 0; i < 12; ++i) {
        auto v = [&] { return Vec3{u(rng), u(rng), u(rng)}; };
        scenes.push_back(twoTrianglesSharing(v(), v(), v(), v(), "random"));
    }
    for (size_t k = 0; k < scenes.size(); ++k)
        for (int depth : {3, 6, 10}) {
            const Scene& s = scenes[k];
            const Octree tree = buildOctree(s, BuildParams{depth, 1});
            const uint64_t bound = boundOf(s, depth);
            EXPECT_LE(bound, tree.nodes.size()) << s.name << " " << k << " at depth " << depth;
            if (k < structured) {
                EXPECT_GE(double(bound), 0.5 * double(tree.nodes.size()))
                    << s.name << " at depth " << depth << ": " << bound << " of "
                    << tree.nodes.size();
            }
        }
    // The quad's tree is all along its diagonal: the count is exact.
    const Octree quad = buildOctree(unitQuad(), BuildParams{10, 1});
    EXPECT_EQ(boundOf(unitQuad(), 10), quad.nodes.size());
}

// The counting stops once past the limit, so a bound far beyond the budget costs no more than
// the budget itself.
TEST(EdgeBound, StopsOncePastTheLimit) {
    const Scene quad = unitQuad();
    const Triangle& t = quad.triangles[0];
    const EdgeNodeCount n = nodesAlongEdge(rootCube(quad), t.v0, t.v2, 21, 1000);
    EXPECT_TRUE(n.passed);
    EXPECT_GT(n.nodes, 1000u);
    EXPECT_LE(n.nodes, 1008u);
}

// Only edges that more than maxPrims distinct triangles share are counted: copies of one
// triangle do not split (the builder keeps them a leaf), nor does an edge under --max-prims 2.
TEST(EdgeBound, OnlyEdgesSharedByMoreThanMaxPrimsDistinctTriangles) {
    const Scene quad = unitQuad();
    const Aabb root = rootCube(quad);
    std::optional<SharedEdgeBound> b = sharedEdgePastLimit(quad, root, 1, 21, 1u << 20);
    ASSERT_TRUE(b.has_value());
    EXPECT_EQ(b->edge.triangles, 2u);
    EXPECT_GT(b->nodes, uint64_t(1) << 20);
    EXPECT_FALSE(sharedEdgePastLimit(quad, root, 2, 21, 1u << 20).has_value());
    Scene copies = quad;
    copies.triangles = {quad.triangles[0], quad.triangles[0]};
    EXPECT_FALSE(sharedEdgePastLimit(copies, rootCube(copies), 1, 21, 1u << 20).has_value());
    // Shallow builds cannot pass the limit: nothing is counted.
    EXPECT_FALSE(sharedEdgePastLimit(quad, root, 1, 5, 1u << 20).has_value());
}

// The case: a one-quad scene at --max-depth 21 --max-prims 1 under the default node
// budget ran 27-33 s before the level-by-level check refused it; it is refused before the
// build, naming the edge and the options.
TEST(EdgeBound, TheDeepQuadIsRefusedBeforeTheBuild) {
    const auto start = std::chrono::steady_clock::now();
    try {
        buildOctree(unitQuad(), BuildParams{21, 1});
        FAIL() << "the deep quad was built";
    } catch (const OctreeError& e) {
        const std::string what = e.what();
        for (const char* says :
             {"more than 33554432 nodes (the node budget)", "the edge (0, 0, 0)-(1, 1, 0)",
              "counted before building", "--max-depth", "--max-prims", "--node-budget"})
            EXPECT_NE(what.find(says), std::string::npos) << says << ": " << what;
    }
    // Not a timing assertion: the level-by-level refusal built 2^25 nodes first; say how long.
    std::printf("[edge_bound] refused in %.3f s\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

}  // namespace
}  // namespace oct
