// The explain page (teach/explain_page.h) as text: one self-contained file, its data a JSON
// object that parses and matches the explanation, nothing loaded from elsewhere, and the model
// indexed (shared vertices) or decimated within budget. The browser test renders it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

#include "core/octree/built_scene.h"
#include "core/render/frame.h"
#include "core/scene/load_scene.h"
#include "teach/explain_page.h"
#include "teach/page_kernel_script.h"
#include "teach/teach_error.h"
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
        const std::string page = explainPage(e, bs, LayoutOptions{}, frame, &stats);
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

namespace oct {
namespace {

// What the page's kernel receives: the spec and the primitive bytes the viewer hands it.
struct KernelInput {
    nlohmann::json spec;
    std::string positions, indices;
};

KernelInput kernelInput(const BuiltScene& bs, const LayoutOptions& o, const FrameParams& f,
                        bool fromModel) {
    KernelInput in;
    in.spec = nlohmann::json::parse(kernelSpec(bs, o, f, fromModel).dump());
    if (fromModel) {
        const IndexedMesh m = pageMesh(*bs.scene, kPageMaxTriangles);
        in.positions = base64Decode(base64Encode(m.positions.data(), m.positions.size() * 4));
        in.indices = base64Decode(base64Encode(m.indices.data(), m.indices.size() * 4));
    } else {
        in.positions = base64Decode(in.spec["scene"]["data"].get<std::string>());
    }
    return in;
}

// The page's kernel rebuilds the traced layout from what the page carries (kernelSpec and the
// model's or the spec's primitive bytes; teach/wasm/page_kernel.cpp does exactly these calls):
// the rebuilt layout's arrays must be the traced ones, byte for byte (the fingerprint), and its
// explanations octrace's. Runs on the host, so a build without emscripten checks it too.
TEST(PageKernelSpec, RebuildsTheTracedLayoutAndExplainsAsOctraceDoes) {
    struct Case {
        std::string scene;
        bool fromModel;
        int maxDepth;
    };
    for (const Case& c : {Case{kMeshes + "/teapot.obj", true, 7},
                          Case{kMeshes + "/teapot.obj", false, 4}, Case{"grid:300", false, 7}}) {
        Scene scene = loadScene(c.scene, {});
        CameraOptions cam;
        cam.width = 40;
        cam.height = 24;
        const FrameParams frame = makeFrame(scene.bounds(), cam);
        LayoutOptions options;
        options.build.maxDepth = c.maxDepth;
        options.build.maxPrims = 3;
        options.hash.bucketSlots = 2;
        for (const LayoutDesc& layout : layouts()) {
            SCOPED_TRACE(c.scene + " " + layout.name + (c.fromModel ? " from the model" : ""));
            const BuiltScene bs = buildScene(scene, layout, options);
            const KernelInput in = kernelInput(bs, options, frame, c.fromModel);
            const Scene rebuiltScene = kernelSpecScene(in.spec, in.positions, in.indices);
            const LayoutOptions rebuiltOptions = kernelSpecOptions(in.spec);
            EXPECT_EQ(rebuiltOptions.build.maxPrims, 3u);
            EXPECT_EQ(rebuiltOptions.hash.bucketSlots, 2u);
            const BuiltScene rebuilt =
                buildScene(rebuiltScene, findLayout(in.spec["layout"]), rebuiltOptions);
            char hex[17];
            std::snprintf(hex, sizeof hex, "%016llx",
                          (unsigned long long)layoutFingerprint(rebuilt));
            EXPECT_EQ(in.spec["fingerprint"].get<std::string>(), hex);
            const FrameParams rebuiltFrame = kernelSpecFrame(in.spec);
            for (auto [x, y] : {std::pair{20, 12}, {3, 3}, {31, 9}})
                EXPECT_EQ(explainJson(explainPixel(rebuilt, rebuiltFrame, x, y)),
                          explainJson(explainPixel(bs, frame, x, y)))
                    << x << "," << y;
        }
    }
}

// A changed layout is caught: the fingerprint covers every array and the primitives.
TEST(PageKernelSpec, FingerprintChangesWithTheBuildAndThePrimitives) {
    for (const std::string& name : {kMeshes + "/teapot.obj", std::string("grid:300")}) {
        Scene scene = loadScene(name, {});
        LayoutOptions a, b;
        b.build.maxPrims = 1;
        b.build.maxDepth = 3;
        for (const LayoutDesc& layout : layouts()) {
            SCOPED_TRACE(name + " " + layout.name);
            const uint64_t base = layoutFingerprint(buildScene(scene, layout, a));
            if (layout.usesOctree) {
                EXPECT_NE(layoutFingerprint(buildScene(scene, layout, b)), base);
            }
            Scene moved = scene;
            float& x = scene.kind == PrimKind::Triangles ? moved.triangles[17].v1.x
                                                         : moved.spheres[17].center.x;
            x = std::nextafter(x, 1e9f);
            EXPECT_NE(layoutFingerprint(buildScene(moved, layout, a)), base);
        }
    }
}

TEST(PageKernelSpec, RefusesBytesThatDoNotFit) {
    Scene scene = loadScene(kMeshes + "/teapot.obj", {});
    const BuiltScene bs = buildScene(scene, findLayout("hash"), LayoutOptions{});
    const FrameParams frame = makeFrame(scene.bounds(), CameraOptions{});
    KernelInput in = kernelInput(bs, LayoutOptions{}, frame, true);
    in.indices.pop_back();
    EXPECT_THROW(kernelSpecScene(in.spec, in.positions, in.indices), TeachError);
    in = kernelInput(bs, LayoutOptions{}, frame, true);
    const uint32_t beyond = uint32_t(in.positions.size() / 12);
    std::memcpy(in.indices.data(), &beyond, 4);
    try {
        kernelSpecScene(in.spec, in.positions, in.indices);
        ADD_FAILURE() << "an index past the vertices was accepted";
    } catch (const TeachError& e) {
        EXPECT_NE(std::string(e.what()).find("names vertex " + std::to_string(beyond)),
                  std::string::npos)
            << e.what();
    }
    in.spec["scene"].erase("grid_depth");
    EXPECT_THROW(kernelSpecScene(in.spec, in.positions, ""), TeachError);
    EXPECT_THROW(base64Decode("abc"), TeachError);
    EXPECT_THROW(base64Decode("ab!d"), TeachError);
    EXPECT_EQ(base64Decode(base64Encode("octree", 6)), "octree");
    EXPECT_EQ(base64Decode(base64Encode("octre", 5)), "octre");
}

// The page carries its kernel's input when this build has the kernel and a pixel was explained;
// otherwise it carries why not, which the page shows (the pixel recorded only).
TEST(PageKernelSpec, ThePageSaysWhenItCannotTraceItself) {
    if (!viewerAvailable()) GTEST_SKIP() << "built with -DOCT_VIEWER=OFF";
    Scene scene = loadScene(kMeshes + "/teapot.obj", {});
    CameraOptions cam;
    cam.width = cam.height = 32;
    const FrameParams frame = makeFrame(scene.bounds(), cam);
    const BuiltScene bs = buildScene(scene, findLayout("compact"), LayoutOptions{});
    PageStats stats;
    const nlohmann::json pixel = nlohmann::json::parse(
        dataOf(explainPage(explainPixel(bs, frame, 16, 16), bs, LayoutOptions{}, frame, &stats)));
    EXPECT_EQ(stats.kernel, pageKernelAvailable());
    if (pageKernelAvailable()) {
        EXPECT_EQ(pixel["kernel"]["layout"], "compact");
        EXPECT_TRUE(pixel["kernel"]["scene"]["from_model"].get<bool>());
        EXPECT_GT(stats.kernelBytes, 100000u);
    } else {
        EXPECT_TRUE(pixel["kernel"].is_null());
        EXPECT_NE(pixel["kernel_missing"].get<std::string>().find("without emscripten"),
                  std::string::npos);
    }
    const float row[8] = {0, 0.5f, 10, 0, 0, -1, 0, INFINITY};
    const nlohmann::json ray = nlohmann::json::parse(
        dataOf(explainPage(explainRay(bs, frame, row), bs, LayoutOptions{}, frame)));
    EXPECT_TRUE(ray["kernel"].is_null());
    EXPECT_NE(ray["kernel_missing"].get<std::string>().find("--ray"), std::string::npos);
}

}  // namespace
}  // namespace oct
