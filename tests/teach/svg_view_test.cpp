// `octrace explain --svg` (teach/svg_view.h): the figure draws exactly the explained traversal.
// Its cells are the primary ray's box tests, in step order, their rectangles the tested boxes
// with the plane's axis dropped, placed by the figure's mapping; the visited ones carry the
// numbers 1..n in the order the steps visit them; leaves and internal cells are told apart as
// the canonical octree has them; the plane is chosen by the documented rule.
#include "teach/svg_view.h"

#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <set>

#include "core/octree/built_scene.h"
#include "core/render/frame.h"
#include "core/scene/load_scene.h"
#include "teach/teach_error.h"
#include "tests/paths.h"

namespace oct {
namespace {

using octtest::kTeapot;

struct Explained {
    Scene scene;
    BuiltScene bs;
    Explanation e;
};

Explained explainTeapot(const LayoutDesc& layout, int x, int y) {
    Explained out{loadScene(kTeapot, {}), {}, {}};
    out.bs = buildScene(out.scene, layout, LayoutOptions{});
    CameraOptions cam;
    cam.width = 32;
    cam.height = 24;
    out.e = explainPixel(out.bs, makeFrame(out.scene.bounds(), cam), x, y);
    return out;
}

struct SvgRect {
    double x, y, w, h;
    std::string role, key;
    int visit;
};

std::vector<SvgRect> cellRects(const std::string& svg) {
    static const std::regex re(
        "<rect x=\"([-0-9.]+)\" y=\"([-0-9.]+)\" width=\"([-0-9.]+)\" height=\"([-0-9.]+)\" "
        "class=\"cell ([a-z-]+)\" data-key=\"([0-7]+)\" data-visit=\"([0-9]+)\"");
    std::vector<SvgRect> out;
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), re); it != std::sregex_iterator();
         ++it)
        out.push_back({std::stod((*it)[1]), std::stod((*it)[2]), std::stod((*it)[3]),
                       std::stod((*it)[4]), (*it)[5], (*it)[6], std::stoi((*it)[7])});
    return out;
}

// The visit numbers as drawn, in document order: (number, key).
std::vector<std::pair<int, std::string>> visitNumbers(const std::string& svg) {
    static const std::regex re("class=\"visit-number\" data-key=\"([0-7]+)\"[^>]*>([0-9]+)<");
    std::vector<std::pair<int, std::string>> out;
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), re); it != std::sregex_iterator();
         ++it)
        out.push_back({std::stoi((*it)[2]), (*it)[1]});
    return out;
}

TEST(SvgView, CellsAreTheBoxTestsProjectedAndNumberedInVisitOrder) {
    const Explained x = explainTeapot(findLayout("linear"), 16, 12);
    ASSERT_GE(x.e.primary.hit.prim, 0) << "the case should hit";
    const AxisPlane plane = planeOfRay(x.e.primary.ray);
    const PlaneFigure f = planeFigure(x.e, x.scene, x.bs.tree.get(), plane);
    const std::string svg = planeFigureSvg(f, x.e);

    // The box tests, one per key, in step order, and the visits in Pop order.
    std::vector<const ExplainStep*> boxes;
    std::set<uint64_t> seen;
    std::vector<uint64_t> visits;
    for (const ExplainStep& s : x.e.primary.steps) {
        if (s.event == StepEvent::Box && seen.insert(s.key).second) boxes.push_back(&s);
        if (s.event == StepEvent::Pop && s.hit) visits.push_back(s.key);
    }
    ASSERT_GT(visits.size(), 2u);
    ASSERT_EQ(f.cells.size(), boxes.size());
    const std::vector<SvgRect> rects = cellRects(svg);
    ASSERT_EQ(rects.size(), boxes.size()) << "every tested cell drawn once";
    std::map<std::string, SvgRect> byKey;
    for (const SvgRect& r : rects) byKey[r.key] = r;
    const PlaneMapping& m = f.map;
    for (const ExplainStep* s : boxes) {
        SCOPED_TRACE(keyOctal(s->key));
        ASSERT_TRUE(byKey.count(keyOctal(s->key)));
        const SvgRect& r = byKey[keyOctal(s->key)];
        // x = left + (u - viewU0) * scale; y from the top, v upwards.
        EXPECT_NEAR(r.x, m.left + (s->box.lo[plane.u] - m.viewU0) * m.scale, 0.006);
        EXPECT_NEAR(r.w, (s->box.hi[plane.u] - s->box.lo[plane.u]) * m.scale, 0.011);
        EXPECT_NEAR(r.y, m.top + (m.viewV1 - s->box.hi[plane.v]) * m.scale, 0.006);
        EXPECT_NEAR(r.h, (s->box.hi[plane.v] - s->box.lo[plane.v]) * m.scale, 0.011);
        EXPECT_EQ(r.role == "missed", !s->hit);
    }
    // The numbers 1..n, drawn in visit order on the visited cells.
    const auto numbers = visitNumbers(svg);
    ASSERT_EQ(numbers.size(), visits.size());
    for (size_t i = 0; i < visits.size(); ++i) {
        EXPECT_EQ(numbers[i].first, int(i + 1));
        EXPECT_EQ(numbers[i].second, keyOctal(visits[i]));
        EXPECT_EQ(byKey[keyOctal(visits[i])].visit, int(i + 1));
    }
}

TEST(SvgView, LeavesAndInternalCellsAreTheOctreesOwn) {
    for (int px : {8, 16, 20}) {
        const Explained x = explainTeapot(findLayout("hash"), px, 12);
        const PlaneFigure f =
            planeFigure(x.e, x.scene, x.bs.tree.get(), planeOfRay(x.e.primary.ray));
        std::map<uint64_t, NodeType> types;
        for (const OctreeNode& n : x.bs.tree->nodes) types[n.key] = n.nodeType();
        int leaves = 0;
        for (const PlaneCell& c : f.cells) {
            if (c.role == CellRole::VisitedLeaf) {
                EXPECT_EQ(types[c.key], NodeType::Leaf) << keyOctal(c.key);
                ++leaves;
            }
            if (c.role == CellRole::VisitedInternal) {
                EXPECT_EQ(types[c.key], NodeType::Internal) << keyOctal(c.key);
            }
        }
        EXPECT_GT(leaves, 0) << "pixel " << px;
    }
}

TEST(SvgView, PrimitivesTestedAreDrawnAndTheHitMarked) {
    const Explained x = explainTeapot(findLayout("linear"), 16, 12);
    const std::string svg = explainSvg(x.e, x.scene, x.bs.tree.get(), "");
    std::set<uint32_t> tested;
    for (const ExplainStep& s : x.e.primary.steps)
        if (s.event == StepEvent::Prim) tested.insert(s.prim);
    ASSERT_FALSE(tested.empty());
    static const std::regex prim("class=\"prim( hit)?\" data-prim=\"([0-9]+)\"");
    std::set<uint32_t> drawn;
    int hits = 0;
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), prim); it != std::sregex_iterator();
         ++it) {
        drawn.insert(uint32_t(std::stoul((*it)[2])));
        if ((*it)[1].matched) {
            ++hits;
            EXPECT_EQ(std::stol((*it)[2]), x.e.primary.hit.prim);
        }
    }
    EXPECT_EQ(drawn, tested);
    EXPECT_EQ(hits, 1);
    EXPECT_NE(svg.find("class=\"hit-point\""), std::string::npos);
    EXPECT_NE(svg.find("class=\"primary-ray\""), std::string::npos);
    // The same explanation gives the same bytes (fixed number format: a figure can be committed).
    EXPECT_EQ(svg, explainSvg(x.e, x.scene, x.bs.tree.get(), ""));
    EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
    EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
}

// The hit is where the primary ray's drawn segment ends and its shadow ray starts: one point of
// the ray, read from the hit's position in the plane's two axes. (Found by the explain page:
// its WebAssembly build drew the hit elsewhere, reading a temporary Vec3 through operator[],
// which indexes past &x; the figure now reads named members.)
TEST(SvgView, TheHitIsWhereThePrimaryRayEnds) {
    for (const LayoutDesc& layout : layouts())
        for (auto [px, py] : {std::pair{16, 12}, {12, 10}, {20, 14}}) {
            const Explained x = explainTeapot(layout, px, py);
            if (x.e.primary.hit.prim < 0) continue;
            SCOPED_TRACE(std::string(layout.name) + " " + std::to_string(px) + "," +
                         std::to_string(py));
            const PlaneFigure f =
                planeFigure(x.e, x.scene, x.bs.tree.get(), planeOfRay(x.e.primary.ray));
            ASSERT_TRUE(f.hit);
            const Vec3 h = x.e.primary.ray.org + x.e.primary.ray.dir * x.e.primary.hit.t;
            const float axes[3] = {h.x, h.y, h.z};
            EXPECT_EQ(f.hitU, axes[f.plane.u]);
            EXPECT_EQ(f.hitV, axes[f.plane.v]);
            if (f.primary.endsAtHit) {
                EXPECT_NEAR(f.primary.u1, f.hitU, 1e-4 * length(x.e.root.extent()));
                EXPECT_NEAR(f.primary.v1, f.hitV, 1e-4 * length(x.e.root.extent()));
            }
        }
}

TEST(SvgView, ThePlaneDropsTheSmallestDirectionComponent) {
    Ray r{{1, 2, 3}, {0.1f, -0.9f, 0.3f}, 0, INFINITY};
    AxisPlane p = planeOfRay(r);
    EXPECT_EQ(p.name(), "yz");
    EXPECT_EQ(p.at, 1.0);
    r.dir = {0.6f, 0.8f, 0.0f};
    p = planeOfRay(r);
    EXPECT_EQ(p.name(), "xy");
    EXPECT_EQ(p.at, 3.0);
    r.dir = {0.0f, 0.0f, -1.0f};  // x and y tie: the later axis (y) is dropped
    EXPECT_EQ(planeOfRay(r).name(), "xz");
    EXPECT_EQ(parseAxisPlane("yz").w, 0);
    EXPECT_EQ(parseAxisPlane("xz").w, 1);
    try {
        parseAxisPlane("xw");
        FAIL() << "accepted xw";
    } catch (const TeachError& e) {
        EXPECT_NE(std::string(e.what()).find("--svg-plane 'xw'"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("xy, xz or yz"), std::string::npos) << e.what();
    }
}

TEST(SvgView, AChosenPlaneProjectsAlongItsAxis) {
    const Explained x = explainTeapot(findLayout("linear"), 16, 12);
    const AxisPlane xz = parseAxisPlane("xz");
    const PlaneFigure f = planeFigure(x.e, x.scene, x.bs.tree.get(), xz);
    ASSERT_FALSE(f.cells.empty());
    const ExplainStep* root = nullptr;
    for (const ExplainStep& s : x.e.primary.steps)
        if (s.event == StepEvent::Box && s.key == kRootKey) root = &s;
    ASSERT_NE(root, nullptr);
    EXPECT_EQ(f.cells[0].key, kRootKey);
    EXPECT_EQ(f.cells[0].u0, root->box.lo.x);
    EXPECT_EQ(f.cells[0].v0, root->box.lo.z);
    EXPECT_EQ(f.cells[0].v1, root->box.hi.z);
    // The hit point is the ray's point at the hit's t, its x and z.
    const Vec3 h = x.e.primary.ray.org + x.e.primary.ray.dir * x.e.primary.hit.t;
    EXPECT_EQ(f.hitU, h.x);
    EXPECT_EQ(f.hitV, h.z);
}

}  // namespace
}  // namespace oct
