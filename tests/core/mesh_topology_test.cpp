// Which triangles share an edge (core/scene/mesh_topology.h): closed and open meshes, a
// non-manifold edge, welding by position, and the fans around vertices.
#include "core/scene/mesh_topology.h"

#include <gtest/gtest.h>

#include <set>

#include "core/scene/grid_cloud.h"
#include "core/scene/load_scene.h"
#include "tests/paths.h"

namespace oct {
namespace {

TEST(MeshTopology, TheCubeIsClosed) {
    MeshTopology t = meshTopology(loadScene(octtest::meshPath("cube_binary.ply")));
    EXPECT_TRUE(t.closed());
    EXPECT_EQ(t.vertices.size(), 8u);
    EXPECT_EQ(t.edges.size(), 18u);  // 12 cube edges + 6 face diagonals
    EXPECT_EQ(t.boundaryEdges, 0u);
    EXPECT_EQ(t.nonManifoldEdges, 0u);
    for (uint32_t v = 0; v < 8; ++v) EXPECT_GE(vertexLink(t, v).size(), 3u) << v;
}

TEST(MeshTopology, OpenMeshesCountTheirBoundary) {
    // sphere_with_hole.stl: an STL (no shared vertices in the file), welded by position; its
    // holes are three missing triangles, 9 boundary edges through 7 vertices (two holes share a
    // vertex twice).
    MeshTopology t = meshTopology(loadScene(octtest::meshPath("sphere_with_hole.stl")));
    EXPECT_FALSE(t.closed());
    EXPECT_EQ(t.vertices.size(), 146u);
    EXPECT_EQ(t.boundaryEdges, 9u);
    EXPECT_EQ(t.nonManifoldEdges, 0u);
    std::set<uint32_t> onBoundary;
    for (const MeshEdge& e : t.edges)
        if (e.triangles == 1) onBoundary.insert({e.a, e.b});
    EXPECT_EQ(onBoundary.size(), 7u);
    // Exactly the vertices on a hole have no closed fan.
    for (uint32_t v = 0; v < t.vertices.size(); ++v)
        EXPECT_EQ(vertexLink(t, v).empty(), onBoundary.count(v) == 1) << v;
}

TEST(MeshTopology, ThreeTrianglesOnOneEdgeAreNonManifold) {
    Scene s;
    s.name = "fin";
    s.triangles = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
                   {{1, 0, 0}, {0, 0, 0}, {0, -1, 0}},
                   {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}}};
    MeshTopology t = meshTopology(s);
    EXPECT_EQ(t.vertices.size(), 5u);
    EXPECT_EQ(t.nonManifoldEdges, 1u);
    EXPECT_EQ(t.boundaryEdges, 6u);
    EXPECT_FALSE(t.closed());
    const MeshEdge* e = t.findEdge(1, 0);
    ASSERT_TRUE(e);
    EXPECT_EQ(e->triangles, 3u);
    EXPECT_TRUE(vertexLink(t, 0).empty());
}

TEST(MeshTopology, NegativeZeroWeldsWithZero) {
    Scene s;
    s.name = "two";
    s.triangles = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{1, 0, 0}, {-0.0f, 0, 0}, {0, -1, 0}}};
    MeshTopology t = meshTopology(s);
    EXPECT_EQ(t.vertices.size(), 4u);
    ASSERT_TRUE(t.findEdge(0, 1));
    EXPECT_EQ(t.findEdge(0, 1)->triangles, 2u);
}

TEST(MeshTopology, PointCloudsHaveNone) {
    EXPECT_THROW(meshTopology(makeGridCloud(10, 1)), std::invalid_argument);
}

}  // namespace
}  // namespace oct
