// The teaching images (teach/heatmap.h, teach/overlay.h, teach/legend.h): colours and
// statistics on hand-made films, the projection against the camera's own ray generation, and
// the overlay's depth test against films whose surface is everywhere in front or nowhere.
#include <gtest/gtest.h>

#include <cmath>

#include "core/octree/built_scene.h"
#include "core/render/frame.h"
#include "core/scene/load_scene.h"
#include "teach/heatmap.h"
#include "teach/legend.h"
#include "teach/overlay.h"
#include "teach/teach_error.h"
#include "tests/paths.h"

namespace oct {
namespace {

using octtest::kMeshes;

bool same(Rgb8 a, Rgb8 b) { return a.r == b.r && a.g == b.g && a.b == b.b; }

// A 10 x 10 film whose nodes cost is the pixel index (0..99) and prims cost 3 everywhere.
Film rampFilm() {
    Film f(10, 10);
    for (size_t i = 0; i < f.pixelCount(); ++i) {
        f.nodes[i] = uint32_t(i);
        f.primsTested[i] = 3;
    }
    return f;
}

TEST(Heatmap, StatisticsAndTheAutomaticScale) {
    const Film f = rampFilm();
    const CostStats s = costStats(f, CostQuantity::Nodes, 0);
    EXPECT_EQ(s.min, 0u);
    EXPECT_EQ(s.max, 99u);
    EXPECT_DOUBLE_EQ(s.mean, 49.5);
    EXPECT_EQ(s.p99, 98u);  // nearest rank: the 99th of 100 sorted values
    EXPECT_EQ(s.scaleMax, 98u);
    EXPECT_EQ(s.clipped, 1u);
    const CostStats fixed = costStats(f, CostQuantity::Nodes, 10);
    EXPECT_EQ(fixed.scaleMax, 10u);
    EXPECT_EQ(fixed.clipped, 89u);
}

TEST(Heatmap, ColoursFollowTheScaleAndTheLegendIsBelow) {
    const Film f = rampFilm();
    HeatmapSpec spec;
    spec.quantity = CostQuantity::Nodes;
    spec.scaleMax = 50;
    spec.layout = "linear";
    spec.scene = "ramp";
    CostStats stats;
    const RgbImage img = heatmapImage(f, spec, &stats);
    // The picture is in the top-left corner of a band at least kMinLegendWidth wide.
    ASSERT_EQ(img.width, kMinLegendWidth);
    ASSERT_GT(img.height, f.height + 20);
    const int ox = 0;
    EXPECT_TRUE(same(img.at(ox + 0, 0), mapColour(ColourMap::Inferno, 0.0)));
    EXPECT_TRUE(same(img.at(ox + 5, 2), mapColour(ColourMap::Inferno, 25.0 / 50.0)));
    EXPECT_TRUE(same(img.at(ox + 0, 5), mapColour(ColourMap::Inferno, 1.0)));  // 50
    EXPECT_TRUE(same(img.at(ox + 9, 9), mapColour(ColourMap::Inferno, 1.0)));  // 99: clipped
    EXPECT_EQ(stats.clipped, 49u);
    // The band holds ink (text and the colour bar) below the picture.
    int ink = 0;
    for (int y = f.height; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) ink += img.at(x, y).r < 128;
    EXPECT_GT(ink, 500);
}

TEST(Heatmap, AnAllZeroImageStaysAtTheBottomColour) {
    Film f(4, 4);
    std::fill(f.nodes.begin(), f.nodes.end(), 0u);
    HeatmapSpec spec;
    const RgbImage img = heatmapImage(f, spec);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            EXPECT_TRUE(same(img.at(x, y), mapColour(ColourMap::Inferno, 0.0)));
}

// A teacher reads a pixel off the PNG (an image viewer's x, y from the top left) and passes it
// to `octrace explain --pixel x,y`: the picture is not shifted by the legend's width, and the
// legend says so.
TEST(Heatmap, ThePngPixelIsThePixelToExplain) {
    Film f(7, 5);  // narrower than the legend band, so the band is wider than the picture
    for (size_t i = 0; i < f.pixelCount(); ++i) f.nodes[i] = uint32_t(i);
    HeatmapSpec spec;
    spec.scaleMax = uint32_t(f.pixelCount());
    const RgbImage img = heatmapImage(f, spec);
    ASSERT_GT(img.width, f.width);
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x)
            EXPECT_TRUE(same(img.at(x, y), mapColour(ColourMap::Inferno,
                                                     double(y * f.width + x) / spec.scaleMax)))
                << x << "," << y;
    const Legend legend = heatmapLegend(f, spec, costStats(f, spec.quantity, spec.scaleMax));
    bool named = false;
    for (const std::string& n : legend.notes) named = named || n.find("--pixel x,y") != n.npos;
    EXPECT_TRUE(named) << "the legend should say which --pixel a PNG pixel is";
}

// The light is part of what a heat map shows (the shadow ray's cost): the legend states where
// it is, the default light included.
TEST(Heatmap, TheLegendStatesTheLight) {
    const Film f = rampFilm();
    HeatmapSpec spec;
    spec.light = Vec3{8, 0, 0.5f};
    const Legend legend = heatmapLegend(f, spec, costStats(f, spec.quantity, 0));
    std::string text;
    for (const std::string& s : legend.subtitle) text += s + "\n";
    EXPECT_NE(text.find("light at (8, 0, 0.5)"), std::string::npos) << text;
}

TEST(Heatmap, QuantityNamesAreChecked) {
    EXPECT_EQ(parseCostQuantity("boxes", "--heatmap"), CostQuantity::Nodes);
    EXPECT_EQ(parseCostQuantity("nodes", "--heatmap"), CostQuantity::Nodes);  // the old name
    EXPECT_STREQ(costQuantityName(CostQuantity::Nodes), "boxes");
    EXPECT_EQ(parseCostQuantity("prims", "--heatmap"), CostQuantity::Prims);
    try {
        parseCostQuantity("rays", "--heatmap");
        ADD_FAILURE() << "accepted";
    } catch (const TeachError& e) {
        EXPECT_NE(std::string(e.what()).find("--heatmap 'rays'"), std::string::npos);
    }
}

TEST(ColourMap, IsMonotoneInLightness) {
    for (ColourMap m : {ColourMap::Inferno, ColourMap::Viridis}) {
        double last = -1;
        for (int i = 0; i <= 16; ++i) {
            const Rgb8 c = mapColour(m, i / 16.0);
            const double luma = 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
            EXPECT_GT(luma, last);
            last = luma;
        }
    }
    EXPECT_TRUE(same(mapColour(ColourMap::Viridis, NAN), mapColour(ColourMap::Viridis, 0.0)));
}

TEST(Text, DrawsInkWithinItsWidth) {
    RgbImage img(200, 40, {255, 255, 255});
    drawText(img, 2, 2, "Nodes 123", {0, 0, 0}, 2);
    const int w = textWidth("Nodes 123", 2);
    int inkInside = 0, inkOutside = 0;
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 200; ++x)
            (x >= 2 && x < 2 + w && y < 2 + textHeight(2) ? inkInside : inkOutside) +=
                img.at(x, y).r == 0;
    EXPECT_GT(inkInside, 50);
    EXPECT_EQ(inkOutside, 0);
    std::string longText(300, 'x');
    EXPECT_EQ(fitText(longText, 100, 3), 1);
    EXPECT_LE(textWidth(longText, 1), 100);
}

// --- overlay ---------------------------------------------------------------------------------

TEST(Overlay, ProjectionInvertsTheCameraRay) {
    CameraOptions cam;
    cam.width = 64;
    cam.height = 48;
    cam.eye = Vec3{3, 2, 7};
    cam.fovDegrees = 60;
    const FrameParams f = makeFrame({{-1, -1, -1}, {1, 1, 1}}, cam);
    for (int y = 0; y < 48; y += 7)
        for (int x = 0; x < 64; x += 9) {
            const Ray r = primaryRay(f.camera, x, y, f.width, f.height);
            double px, py, dist;
            ASSERT_TRUE(projectToPixel(f, r.org + r.dir * 5.0f, px, py, dist));
            EXPECT_NEAR(px, x + 0.5, 1e-3);
            EXPECT_NEAR(py, y + 0.5, 1e-3);
            EXPECT_NEAR(dist, 5.0, 1e-4);
        }
    double px, py, dist;
    EXPECT_FALSE(projectToPixel(f, f.camera.eye - f.camera.forward, px, py, dist));
}

struct TeapotFrame {
    Scene scene;
    std::shared_ptr<const Octree> tree;
    FrameParams frame;
};

TeapotFrame teapot() {
    TeapotFrame t{loadScene(kMeshes + "/teapot.obj", {}), nullptr, {}};
    t.tree = buildSharedOctree(t.scene, BuildParams{});
    CameraOptions cam;
    cam.width = 96;
    cam.height = 80;
    t.frame = makeFrame(t.scene.bounds(), cam);
    return t;
}

Film flatFilm(int w, int h, float t) {
    Film f(w, h);
    std::fill(f.rgb.begin(), f.rgb.end(), uint8_t(40));
    std::fill(f.t.begin(), f.t.end(), t);
    return f;
}

TEST(Overlay, EdgesBehindTheSurfaceAreHidden) {
    const TeapotFrame tp = teapot();
    // A surface right in front of the eye everywhere: every edge is behind it.
    const Film wall = flatFilm(96, 80, 1e-3f);
    OverlayStats hidden;
    const RgbImage a = overlayImage(wall, tp.frame, *tp.tree, OverlaySpec{}, &hidden);
    EXPECT_EQ(hidden.samplesDrawn, 0u);
    EXPECT_GT(hidden.samplesHidden, 1000u);
    const int ox = 0;  // the picture is in the top-left corner, above the legend band
    for (int y = 0; y < 80; ++y)
        for (int x = 0; x < 96; ++x) ASSERT_TRUE(same(a.at(ox + x, y), {40, 40, 40}));
    // No surface at all: nothing is hidden, edges are drawn.
    const Film open = flatFilm(96, 80, INFINITY);
    OverlayStats shown;
    const RgbImage b = overlayImage(open, tp.frame, *tp.tree, OverlaySpec{}, &shown);
    EXPECT_EQ(shown.samplesHidden, 0u);
    EXPECT_EQ(shown.samplesDrawn, hidden.samplesHidden);
    int changed = 0;
    for (int y = 0; y < 80; ++y)
        for (int x = 0; x < 96; ++x) changed += !same(b.at(ox + x, y), {40, 40, 40});
    EXPECT_GT(changed, 500);
    EXPECT_EQ(shown.cells, hidden.cells);
}

TEST(Overlay, DrawsTheLeavesOrTheCellsOfOneDepth) {
    const TeapotFrame tp = teapot();
    const Film open = flatFilm(96, 80, INFINITY);
    uint64_t leaves = 0, depth2 = 0;
    for (const OctreeNode& n : tp.tree->nodes) {
        leaves += n.nodeType() == NodeType::Leaf || n.nodeType() == NodeType::EmptyLeaf;
        depth2 += n.depth == 2;
    }
    OverlayStats s;
    overlayImage(open, tp.frame, *tp.tree, OverlaySpec{}, &s);
    EXPECT_EQ(s.cells, leaves);
    OverlaySpec two;
    two.depth = 2;
    overlayImage(open, tp.frame, *tp.tree, two, &s);
    EXPECT_EQ(s.cells, depth2);
    OverlaySpec tooDeep;
    tooDeep.depth = tp.tree->depth + 1;
    EXPECT_THROW(overlayImage(open, tp.frame, *tp.tree, tooDeep), TeachError);
}

}  // namespace
}  // namespace oct
