// The binary BVH's structure (cpu_ref/binary_bvh.h): what the builder promises the walk. Every
// triangle in exactly one leaf, every box holding what lies below it, inner nodes' children
// side by side after them, leaves within the stack's depth, and the SAH's leaves small; then
// the cases the binning cannot split (coincident centroids) and a scene with no triangles.
#include "cpu_ref/binary_bvh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "core/octree/exhaustive.h"
#include "core/octree/layout.h"
#include "core/scene/load_scene.h"
#include "tests/paths.h"

namespace oct {
namespace {

bool inside(const Aabb& inner, const Aabb& outer) {
    return outer.lo.x <= inner.lo.x && outer.lo.y <= inner.lo.y && outer.lo.z <= inner.lo.z &&
           inner.hi.x <= outer.hi.x && inner.hi.y <= outer.hi.y && inner.hi.z <= outer.hi.z;
}

// Walks the tree checking each node against its parent and each leaf's triangles.
void expectWellFormed(const Scene& scene, const BinaryBvh& bvh) {
    const std::vector<BvhNode>& nodes = bvh.nodes();
    const BvhView v = bvh.view();
    std::vector<uint32_t> seen(scene.triangles.size(), 0);
    std::vector<std::pair<uint32_t, int>> todo = {{0u, 0}};
    uint64_t visited = 0;
    while (!todo.empty()) {
        const auto [at, depth] = todo.back();
        todo.pop_back();
        ++visited;
        ASSERT_LT(at, nodes.size());
        ASSERT_LT(depth, kBvhMaxDepth);
        const BvhNode& n = nodes[at];
        if (n.leaf()) {
            ASSERT_LE(uint64_t(n.index) + n.count, scene.triangles.size());
            for (uint32_t k = n.index; k < n.index + n.count; ++k) {
                ASSERT_LT(v.ids[k], scene.triangles.size());
                ++seen[v.ids[k]];
                EXPECT_TRUE(inside(boundsOf(v.tris[k]), n.box)) << "leaf " << at;
                EXPECT_EQ(std::memcmp(&v.tris[k], &scene.triangles[v.ids[k]], sizeof(Triangle)), 0);
            }
            continue;
        }
        // Children after their parent, side by side, each inside the parent's box.
        ASSERT_GT(n.index, at);
        ASSERT_LT(n.index + 1, nodes.size());
        for (uint32_t c : {n.index, n.index + 1}) {
            EXPECT_TRUE(inside(nodes[c].box, n.box)) << "node " << c << " of " << at;
            todo.push_back({c, depth + 1});
        }
    }
    EXPECT_EQ(visited, nodes.size()) << "every node reached once";
    for (size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], 1u) << "triangle " << i;
}

TEST(BinaryBvh, EveryCommittedMeshBuildsAWellFormedTree) {
    for (const std::string& mesh : octtest::committedMeshes()) {
        SCOPED_TRACE(mesh);
        const Scene scene = loadScene(octtest::meshPath(mesh));
        const BinaryBvh bvh(scene);
        expectWellFormed(scene, bvh);
        const BvhStats s = bvh.stats();
        EXPECT_EQ(s.nodes, 2 * s.leaves - 1);
        EXPECT_LE(s.largestLeaf, kBvhMaxLeafTriangles);
        EXPECT_LT(s.depth, kBvhMaxDepth);
        EXPECT_EQ(s.bytes, s.nodes * 32 + scene.triangles.size() * (36 + 4));
        if (scene.triangles.size() > kBvhLeafTriangles) {
            EXPECT_GT(s.leaves, 1u);
        }
    }
}

// Copies of one triangle: no plane separates their centroids, so they stay one leaf, and the
// nearest-hit rule still answers the lowest id among them, as exhaustive tracing does.
TEST(BinaryBvh, CoincidentCentroidsMakeOneLeafAndTiesGoToTheLowerId) {
    Scene scene;
    scene.name = "copies";
    const Triangle t{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    for (int i = 0; i < 40; ++i) scene.triangles.push_back(t);
    scene.triangles.push_back({{0, 0, 2}, {1, 0, 2}, {0, 1, 2}});  // nearer, above them
    const BinaryBvh bvh(scene);
    expectWellFormed(scene, bvh);
    const Ray down{{0.25f, 0.25f, 5.0f}, {0, 0, -1}, 0.0f, INFINITY};
    const Ray belowTheTop{{0.25f, 0.25f, 1.0f}, {0, 0, -1}, 0.0f, INFINITY};
    const ExhaustiveView all{primitivesView(scene)};
    for (const Ray& r : {down, belowTheTop}) {
        TraceCost c1{0, 0}, c2{0, 0};
        const Hit a = closestHit(bvh.view(), r, c1), b = closestHit(all, r, c2);
        EXPECT_EQ(a.t, b.t);
        EXPECT_EQ(a.prim, b.prim);
    }
    TraceCost c{0, 0};
    EXPECT_EQ(closestHit(bvh.view(), belowTheTop, c).prim, 0);
}

TEST(BinaryBvh, ASceneWithoutTrianglesMissesEverything) {
    Scene scene;
    scene.name = "empty";
    const BinaryBvh bvh(scene);
    EXPECT_EQ(bvh.stats().nodes, 1u);
    TraceCost c{0, 0};
    const Ray r{{0, 0, 5}, {0, 0, -1}, 0.0f, INFINITY};
    EXPECT_EQ(closestHit(bvh.view(), r, c).prim, -1);
    EXPECT_FALSE(anyHit(bvh.view(), r, c));
}

}  // namespace
}  // namespace oct
