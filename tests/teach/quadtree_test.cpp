// The quadtree of `octrace explain --quadtree` (teach/quadtree.h, the paper's Figure 1 in 2D):
// keys computed by hand for a small case (root 1, a child appends 2 bits), the octree's split
// rule, the traversal's visit order and hit worked out by hand, the hit equal to the octree's
// for a ray in the plane of a flat point cloud, and the refusals of scenes that are not flat.
#include "teach/quadtree.h"

#include <gtest/gtest.h>

#include <map>
#include <regex>

#include "core/octree/built_scene.h"
#include "core/render/frame.h"
#include "core/scene/load_scene.h"
#include "teach/explain.h"
#include "teach/teach_error.h"
#include "tests/paths.h"

namespace oct {
namespace {

Scene flatPoints(const std::vector<std::pair<float, float>>& uv, float radius) {
    Scene s;
    s.name = "flat points";
    s.kind = PrimKind::Spheres;
    for (auto [u, v] : uv) s.spheres.push_back({{u, v, 0.0f}, radius});
    return s;
}

// Three points in the unit square: two in the lower-left quarter (split once more), one upper
// right, none elsewhere.
Scene threePoints() { return flatPoints({{0.1f, 0.1f}, {0.3f, 0.1f}, {0.9f, 0.9f}}, 0.01f); }
const QuadCell kUnit = {0, 0, 1, 1};

BuildParams quadParams(int depth, uint32_t prims) {
    BuildParams p;
    p.maxDepth = depth;
    p.maxPrims = prims;
    return p;
}

TEST(Quadtree, KeysAreTheRootOneAndTwoBitsAChild) {
    EXPECT_EQ(quadChildKey(kQuadRootKey, 3), 0b111u);
    EXPECT_EQ(quadChildKey(0b111, 2), 0b11110u);
    EXPECT_EQ(quadKeyBase4(1), "1");
    EXPECT_EQ(quadKeyBase4(0b11011), "123");  // 27: root, quadrant 2, quadrant 3
    EXPECT_EQ(quadKeyBinary(0b11011), "0b11011");
    EXPECT_EQ(quadKeyDepth(0b11011), 2);
    EXPECT_EQ(quadKeyDepth(1), 0);
}

TEST(Quadtree, ThreePointsGiveTheHandComputedCells) {
    const Scene s = threePoints();
    const Quadtree q = buildQuadtree(s, parseAxisPlane("xy"), kUnit, quadParams(4, 1));
    std::map<std::string, std::vector<uint32_t>> leaves;
    std::vector<std::string> internal;
    for (const QuadNode& n : q.nodes) {
        if (n.leaf())
            leaves[quadKeyBase4(n.key)] = n.prims;
        else
            internal.push_back(quadKeyBase4(n.key));
    }
    // The root (3 points > 1) splits; its quadrant 0 (two points) splits again, nothing else.
    EXPECT_EQ(internal, (std::vector<std::string>{"1", "10"}));
    ASSERT_EQ(q.nodes.size(), 9u);
    EXPECT_EQ(q.depth, 2);
    // (0.1, 0.1): quadrant 0 of quadrant 0, key 0b10000; (0.3, 0.1): upper in u of [0, 0.5],
    // key 0b10001; (0.9, 0.9): quadrant 3, key 0b111.
    EXPECT_EQ(leaves["100"], std::vector<uint32_t>{0});
    EXPECT_EQ(leaves["101"], std::vector<uint32_t>{1});
    EXPECT_EQ(leaves["13"], std::vector<uint32_t>{2});
    for (const char* empty : {"11", "12", "102", "103"})
        EXPECT_TRUE(leaves[empty].empty()) << empty;
    for (const QuadNode& n : q.nodes)
        if (quadKeyBase4(n.key) == "101") {
            EXPECT_EQ(n.key, 0b10001u);
            EXPECT_DOUBLE_EQ(n.cell.u0, 0.25);
            EXPECT_DOUBLE_EQ(n.cell.u1, 0.5);
            EXPECT_DOUBLE_EQ(n.cell.v1, 0.25);
        }
    // max-depth 1 stops the second split; max-prims 2 the first one's child.
    EXPECT_EQ(buildQuadtree(s, parseAxisPlane("xy"), kUnit, quadParams(1, 1)).nodes.size(), 5u);
    EXPECT_EQ(buildQuadtree(s, parseAxisPlane("xy"), kUnit, quadParams(4, 2)).nodes.size(), 5u);
    EXPECT_EQ(buildQuadtree(s, parseAxisPlane("xy"), kUnit, quadParams(4, 3)).nodes.size(), 1u);
}

TEST(Quadtree, TheRayVisitsNearestFirstAndStopsAtTheHit) {
    const Scene s = threePoints();
    const Quadtree q = buildQuadtree(s, parseAxisPlane("xy"), kUnit, quadParams(4, 1));
    Ray2D r;
    r.ou = -0.5;
    r.ov = 0.1;  // along v = 0.1, through the two lower-left cells
    const QuadTrace t = traceQuadtree(q, s, r);
    std::vector<std::string> visits;
    for (uint32_t n : t.visits) visits.push_back(quadKeyBase4(q.nodes[n].key));
    // Root, its quadrant 0, then cell 100 (entered at t 0.5) whose point is hit at
    // 0.5 + 0.1 - 0.01; cell 101 (entered at 0.75) is dropped beyond that hit.
    EXPECT_EQ(visits, (std::vector<std::string>{"1", "10", "100"}));
    EXPECT_EQ(t.hitPrim, 0);
    EXPECT_NEAR(t.hitT, 0.59, 1e-6);
    int dropped = 0;
    for (const QuadStep& st : t.steps)
        if (st.event == QuadEvent::Pop && !st.hit) {
            ++dropped;
            EXPECT_EQ(quadKeyBase4(q.nodes[st.node].key), "101");
        }
    EXPECT_EQ(dropped, 1);
    const std::string svg = quadtreeSvg(q, t, s, "title", "query");
    // Every cell drawn with its key; the visited leaf numbered.
    for (const QuadNode& n : q.nodes)
        EXPECT_NE(svg.find("data-key=\"" + quadKeyBase4(n.key) + "\""), std::string::npos);
    EXPECT_NE(svg.find("class=\"qvisit\" data-key=\"100\""), std::string::npos);
    EXPECT_NE(svg.find(">100</text>"), std::string::npos) << "the key is written in the cell";
    EXPECT_EQ(svg, quadtreeSvg(q, t, s, "title", "query"));
}

// A ray in the plane of a flat point cloud meets each sphere as its centre circle: the
// quadtree's hit is the octree's, primitive and distance.
TEST(Quadtree, AgreesWithTheOctreeForARayInTheCloudsPlane) {
    std::vector<std::pair<float, float>> uv;
    for (int i = 0; i < 40; ++i)
        uv.push_back({float((i * 37) % 41) / 41.0f, float((i * 11) % 17) / 17.0f});
    const Scene s = flatPoints(uv, 0.015f);
    const BuiltScene bs = buildScene(s, findLayout("linear"), LayoutOptions{});
    const FrameParams frame = makeFrame(s.bounds(), CameraOptions{});
    const AxisPlane plane = quadtreePlane(s, "");
    EXPECT_EQ(plane.name(), "xy");
    const Quadtree q = buildQuadtree(s, plane, quadRootOf(s, plane), quadParams(5, 2));
    int hits = 0;
    for (float dv : {0.0f, 0.13f, 0.31f, -0.2f, 0.55f}) {
        const Explanation e = explainRay(bs, frame, Vec3{-0.2f, 0.3f, 0.0f}, Vec3{1.0f, dv, 0.0f});
        const QuadTrace t = traceQuadtree(q, s, rayInPlane(e.primary.ray, plane));
        EXPECT_EQ(t.hitPrim, e.primary.hit.prim) << dv;
        if (t.hitPrim >= 0) {
            EXPECT_NEAR(t.hitT, e.primary.hit.t, 1e-4);
            ++hits;
        }
    }
    EXPECT_GT(hits, 1);
}

TEST(Quadtree, ScenesNotFlatAreRefusedNamingTheirExtents) {
    const Scene teapot = loadScene(octtest::kTeapot, {});
    try {
        quadtreePlane(teapot, "");
        FAIL() << "the teapot is not flat";
    } catch (const TeachError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("--quadtree"), std::string::npos) << m;
        EXPECT_NE(m.find("is not flat"), std::string::npos) << m;
        EXPECT_NE(m.find(", z "), std::string::npos) << m;
    }
    const Scene slivers = loadScene("slivers:8", {});
    EXPECT_EQ(quadtreePlane(slivers, "").name(), "xy");
    EXPECT_EQ(quadtreePlane(slivers, "xy").name(), "xy");
    try {
        quadtreePlane(slivers, "xz");
        FAIL() << "slivers lie in xy";
    } catch (const TeachError& e) {
        EXPECT_NE(std::string(e.what()).find("--svg-plane xz"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("xy plane"), std::string::npos) << e.what();
    }
    // A ray across the plane has no direction in it.
    EXPECT_THROW(rayInPlane(Ray{{0.5f, 0.5f, 1}, {0, 0, -1}, 0, INFINITY}, parseAxisPlane("xy")),
                 TeachError);
}

TEST(Quadtree, TrianglesBelongToEveryCellTheyOverlap) {
    // One triangle across the square's lower half: it overlaps quadrants 0 and 1, not 2 and 3.
    Scene s;
    s.name = "one triangle";
    s.triangles.push_back({{0.1f, 0.1f, 0}, {0.9f, 0.1f, 0}, {0.5f, 0.4f, 0}});
    s.triangles.push_back({{0.6f, 0.9f, 0}, {0.9f, 0.9f, 0}, {0.9f, 0.6f, 0}});
    const Quadtree q = buildQuadtree(s, parseAxisPlane("xy"), kUnit, quadParams(1, 1));
    ASSERT_EQ(q.nodes.size(), 5u);
    EXPECT_EQ(q.nodes[1].prims, std::vector<uint32_t>{0});
    EXPECT_EQ(q.nodes[2].prims, std::vector<uint32_t>{0});
    EXPECT_TRUE(q.nodes[3].prims.empty());
    EXPECT_EQ(q.nodes[4].prims, std::vector<uint32_t>{1});
    // A ray along v = 0.2 enters the first triangle's region where its left edge crosses it.
    Ray2D r;
    r.ou = -1;
    r.ov = 0.2;
    const QuadTrace t = traceQuadtree(q, s, r);
    EXPECT_EQ(t.hitPrim, 0);
    // Left edge from (0.1, 0.1) to (0.5, 0.4): at v = 0.2, u = 0.1 + 0.4 / 3 (corners in float).
    EXPECT_NEAR(t.hitT, 1.0 + 0.1 + 0.4 / 3.0, 1e-6);
}

}  // namespace
}  // namespace oct
