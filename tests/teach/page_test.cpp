// The explain page (teach/explain_page.h) as text: one self-contained file, its data a JSON
// object that parses and matches the explanation, nothing loaded from elsewhere, and the model
// indexed (shared vertices) or decimated within budget. The browser test renders it.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "core/octree/built_scene.h"
#include "core/render/frame.h"
#include "core/scene/load_scene.h"
#include "teach/explain_page.h"
#include "teach/viewer_script.h"
#include "tests/paths.h"
#include "tests/teach/page_data.h"

namespace oct {
namespace {

using octtest::kMeshes;

Scene cube() {
    Scene s;
    s.name = "cube";
    const Vec3 c[8] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0},
                       {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
    const int faces[12][3] = {{0, 1, 3}, {0, 3, 2}, {4, 7, 5}, {4, 6, 7}, {0, 4, 5}, {0, 5, 1},
                              {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
    for (auto& f : faces) {
        s.triangles.push_back({c[f[0]], c[f[1]], c[f[2]]});
        s.sourceFace.push_back(uint32_t(s.sourceFace.size()));
    }
    return s;
}

TEST(PageMesh, SharesIdenticalVerticesAndKeepsEveryTriangle) {
    const Scene s = cube();
    const IndexedMesh m = pageMesh(s, 1000);
    EXPECT_FALSE(m.decimated);
    EXPECT_EQ(m.positions.size(), 8u * 3);
    ASSERT_EQ(m.indices.size(), 12u * 3);
    for (size_t t = 0; t < 12; ++t) {
        const Vec3 v[3] = {s.triangles[t].v0, s.triangles[t].v1, s.triangles[t].v2};
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = m.indices[3 * t + k];
            EXPECT_EQ(m.positions[3 * i], v[k].x);
            EXPECT_EQ(m.positions[3 * i + 1], v[k].y);
            EXPECT_EQ(m.positions[3 * i + 2], v[k].z);
        }
    }
}

TEST(PageMesh, DecimatesLargeMeshesWithinTheBudget) {
    const Scene s = loadScene(kMeshes + "/teapot.obj", {});
    ASSERT_GT(s.triangles.size(), 600u);
    const IndexedMesh m = pageMesh(s, 300);
    EXPECT_TRUE(m.decimated);
    EXPECT_LE(m.indices.size() / 3, 300u);
    EXPECT_GT(m.indices.size() / 3, 50u);
    for (uint32_t i : m.indices) ASSERT_LT(i, m.positions.size() / 3);
}

using octtest::dataOf;

TEST(ExplainPage, IsOneFileWhoseDataMatchesTheExplanation) {
    if (!viewerAvailable()) GTEST_SKIP() << "built with -DOCT_VIEWER=OFF";
    Scene scene = loadScene(kMeshes + "/teapot.obj", {});
    scene.name = "tea</script><b>pot";  // must neither end the data nor inject markup
    CameraOptions cam;
    cam.width = cam.height = 32;
    const FrameParams frame = makeFrame(scene.bounds(), cam);
    for (const LayoutDesc& layout : layouts()) {
        SCOPED_TRACE(layout.name);
        const BuiltScene bs = buildScene(scene, layout, LayoutOptions{});
        const Explanation e = explainPixel(bs, frame, 16, 16);
        PageStats stats;
        const std::string page = explainPage(e, scene, &stats);
        EXPECT_EQ(page.rfind("<!DOCTYPE html>", 0), 0u);
        EXPECT_EQ(stats.bytes, page.size());
        EXPECT_NE(page.find(viewerScript()), std::string::npos) << "the viewer is inlined";
        // Self-contained: the markup around the data and the script loads nothing.
        const std::string markup = page.substr(0, page.find("<script id=\"octrace-data\""));
        EXPECT_EQ(markup.find("src="), std::string::npos);
        EXPECT_EQ(markup.find("<link"), std::string::npos);
        EXPECT_EQ(markup.find("<b>pot"), std::string::npos);
        EXPECT_NE(markup.find("tea&lt;/script&gt;&lt;b&gt;pot"), std::string::npos);
        const nlohmann::json d = nlohmann::json::parse(dataOf(page));
        uint64_t lines = 0;
        for (const auto& l : d["lines"]) lines += !l.contains("heading");
        EXPECT_EQ(lines, stats.lines);
        size_t expected = explainLines(e, 0).size() + (e.shadow ? explainLines(e, 1).size() : 0);
        EXPECT_EQ(lines, expected);
        EXPECT_EQ(d["rays"].size(), e.shadow ? 2u : 1u);
        EXPECT_EQ(d["cells"].size(), stats.cells);
        EXPECT_EQ(stats.modelPrimitives, scene.triangles.size());
        EXPECT_FALSE(stats.reduced);
        if (layout.usesOctree) {
            EXPECT_GT(stats.cells, 0u);
            // Every visited cell has a colour and a visit number.
            for (const auto& c : d["cells"]) {
                if (c["visited"]) {
                    EXPECT_TRUE(c.contains("colour") && c.contains("order"));
                }
            }
        } else {
            EXPECT_EQ(stats.cells, 0u);
        }
    }
}

}  // namespace
}  // namespace oct
