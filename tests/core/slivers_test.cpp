// The slivers scene (core/scene/slivers.h) and the table of generated scenes
// (core/scene/scene_generators.h): N non-degenerate triangles that tile the unit square exactly,
// neighbours sharing bit-identical vertices; the same bytes for the same spec; the spec's limits.
#include "core/scene/slivers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <utility>

#include "core/geometry/numeric_range.h"
#include "core/scene/load_scene.h"
#include "core/scene/mesh_topology.h"
#include "core/scene/scene_formats.h"
#include "core/scene/scene_generators.h"

namespace oct {
namespace {

// Twice the signed area seen from +z, in double: exact, since the vertices are multiples of
// 2^-24 in [0, 1] (products of differences need at most 48 bits).
double twiceAreaZ(const Triangle& t) {
    return (double(t.v1.x) - t.v0.x) * (double(t.v2.y) - t.v0.y) -
           (double(t.v1.y) - t.v0.y) * (double(t.v2.x) - t.v0.x);
}

TEST(Slivers, TheTrianglesTileTheSquareExactly) {
    for (uint64_t n : {2u, 4u, 1000u, 20000u}) {
        SCOPED_TRACE(n);
        const Scene s = makeSlivers(n, 7);
        ASSERT_EQ(s.triangles.size(), n);
        ASSERT_EQ(s.sourceFace.size(), n);
        EXPECT_EQ(s.kind, PrimKind::Triangles);
        EXPECT_EQ(s.report.facesRead, n);
        EXPECT_EQ(s.report.verticesRead, n / 2 + 3);  // the 4 corners and one per split
        EXPECT_EQ(s.report.totalDropped(), 0u);
        double area = 0.0;
        for (size_t i = 0; i < s.triangles.size(); ++i) {
            const Triangle& t = s.triangles[i];
            EXPECT_EQ(s.sourceFace[i], i);
            for (Vec3 v : {t.v0, t.v1, t.v2}) {
                ASSERT_TRUE(v.x >= 0.0f && v.x <= 1.0f && v.y >= 0.0f && v.y <= 1.0f) << i;
                ASSERT_EQ(v.z, 0.0f) << i;
                // On the grid of step 2^-24.
                ASSERT_EQ(double(v.x) * 0x1p24, std::floor(double(v.x) * 0x1p24)) << i;
            }
            const double a2 = twiceAreaZ(t);
            ASSERT_GT(a2, 0.0) << "triangle " << i << " is degenerate or turned over";
            ASSERT_GE(a2, kMinTriangleArea2) << i;  // loadable: inside the numeric range
            area += a2 / 2;
        }
        EXPECT_EQ(area, 1.0);  // exact: every term is a multiple of 2^-49
        // Welded by exact position, the vertices are the generator's own (no two coincide, none
        // is a copy that differs in a bit), every interior edge lies in exactly two triangles,
        // and the boundary is the square's four sides.
        const MeshTopology topo = meshTopology(s);
        EXPECT_EQ(topo.vertices.size(), n / 2 + 3);
        EXPECT_EQ(topo.nonManifoldEdges, 0u);
        EXPECT_EQ(topo.boundaryEdges, 4u);
        EXPECT_EQ(topo.edges.size(), 3 * n / 2 + 2);  // Euler: V - E + F = 1 for a disc
        std::map<std::pair<uint32_t, uint32_t>, int> directed;
        for (const auto& c : topo.corners)
            for (int k = 0; k < 3; ++k) ++directed[{c[k], c[(k + 1) % 3]}];
        for (const MeshEdge& e : topo.edges) {
            const Vec3 a = topo.vertices[e.a], b = topo.vertices[e.b];
            if (e.triangles == 1) {  // on a side of the square
                EXPECT_TRUE((a.x == b.x && (a.x == 0.0f || a.x == 1.0f)) ||
                            (a.y == b.y && (a.y == 0.0f || a.y == 1.0f)));
                continue;
            }
            ASSERT_EQ(e.triangles, 2u);
            // The two triangles run along it in opposite directions: one winding, no fold.
            EXPECT_EQ(directed[std::make_pair(e.a, e.b)], 1);
            EXPECT_EQ(directed[std::make_pair(e.b, e.a)], 1);
        }
    }
}

TEST(Slivers, AreSlivers) {
    // The point of the scene: triangles far thinner than a float step near 1 (6e-8).
    const Scene s = makeSlivers(2000, 1);
    int thin = 0;
    for (const Triangle& t : s.triangles) {
        const double a2 = twiceAreaZ(t);
        const double longest =
            std::max({length(t.v1 - t.v0), length(t.v2 - t.v1), length(t.v0 - t.v2)});
        thin += a2 / longest < 1e-7;  // the smallest altitude
    }
    EXPECT_GT(thin, 100);
}

TEST(Slivers, SameSpecSameBytes) {
    const Scene a = makeSlivers(3000, 11), b = loadScene("slivers:3000:11");
    const Scene c = makeSlivers(3000, 12);
    ASSERT_EQ(a.triangles.size(), b.triangles.size());
    EXPECT_EQ(std::memcmp(a.triangles.data(), b.triangles.data(), a.triangles.size() * 36), 0);
    EXPECT_NE(std::memcmp(a.triangles.data(), c.triangles.data(), a.triangles.size() * 36), 0);
    EXPECT_EQ(b.name, "slivers:3000:11");
    EXPECT_EQ(b.report.format, "slivers");
    EXPECT_TRUE(isSliversScene(b));
    EXPECT_EQ(loadScene("slivers:10").name, "slivers:10:1");  // default seed 1
    EXPECT_EQ(loadScene("SLIVERS:10").name, "slivers:10:1");  // the prefix in any case
    EXPECT_FALSE(isSliversScene(loadScene("grid:10")));
}

TEST(Slivers, TheSpecsLimitsAreOneLineErrors) {
    auto message = [](const std::string& spec) -> std::string {
        try {
            loadScene(spec);
        } catch (const SceneError& e) {
            return e.what();
        }
        return "";
    };
    for (const char* bad : {"slivers:", "slivers:x", "slivers:10:", "slivers:-2", "slivers:1:2:3",
                            "slivers:99999999999999999999999"})
        EXPECT_NE(message(bad).find("write slivers:N or slivers:N:SEED"), std::string::npos) << bad;
    EXPECT_NE(message("slivers:0").find("at least the square's 2 triangles"), std::string::npos);
    EXPECT_NE(message("slivers:1").find("at least the square's 2 triangles"), std::string::npos);
    EXPECT_EQ(message("slivers:2001"),
              "slivers:2001: N is the number of triangles, and each split adds two to the "
              "square's two, so N must be even; use slivers:2000 or slivers:2002");
    EXPECT_EQ(message("slivers:4194306"),
              "slivers:4194306: more than the maximum of 4194304 triangles; use at most 4194304");
    for (const char* bad : {"slivers:0", "slivers:3", "slivers:4194306"})
        EXPECT_EQ(message(bad).find('\n'), std::string::npos) << bad;
}

TEST(SceneGenerators, OneTableForLoadingTheHelpAndMessages) {
    ASSERT_NE(findSceneGenerator("grid:5"), nullptr);
    EXPECT_STREQ(findSceneGenerator("Grid:5")->prefix, "grid");
    EXPECT_STREQ(findSceneGenerator("slivers:4:2")->prefix, "slivers");
    EXPECT_EQ(findSceneGenerator("grid"), nullptr);
    EXPECT_EQ(findSceneGenerator("mesh.obj"), nullptr);
    EXPECT_EQ(findSceneGenerator("cube:3"), nullptr);
    EXPECT_EQ(sceneGeneratorList(" or "), "grid:N[:SEED] or slivers:N[:SEED]");
    const std::string help = sceneFormatsHelp();
    for (const SceneGenerator& g : sceneGenerators()) {
        EXPECT_NE(help.find(g.usage), std::string::npos) << help;
        EXPECT_NE(help.find(g.description), std::string::npos) << help;
        // Every generator's spec loads through loadScene.
        const Scene s = loadScene(std::string(g.prefix) + ":8");
        EXPECT_EQ(s.report.format, g.prefix);
        EXPECT_EQ(s.primitiveCount(), 8u);
    }
    uint64_t n = 0, seed = 5;
    EXPECT_TRUE(parseCountSpec("x:12", 100, n, seed));
    EXPECT_EQ(n, 12u);
    EXPECT_EQ(seed, 5u);  // kept when none is given
    EXPECT_TRUE(parseCountSpec("x:12:9", 100, n, seed));
    EXPECT_EQ(seed, 9u);
    EXPECT_FALSE(parseCountSpec("x:101", 100, n, seed));
    EXPECT_FALSE(parseCountSpec("x:1 ", 100, n, seed));
    EXPECT_FALSE(parseCountSpec("x:+1", 100, n, seed));
}

}  // namespace
}  // namespace oct
