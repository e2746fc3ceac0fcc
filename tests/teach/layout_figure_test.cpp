// `octrace explain --layouts-svg` (teach/layout_figure.h): one canonical octree drawn as the
// three layouts. Each panel is checked against the canonical octree, not against the figure's
// own reading of the views: the linear array's used slots are the octree's nodes at their
// linear index, the hash table's keys are the octree's keys in bucket k mod m, the probes are
// the explained traversal's (or one lookup's), the compact records' masks are the nodes'
// children, and the bytes are what `octrace info` reports.
#include "teach/layout_figure.h"

#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <set>

#include "core/octree/built_scene.h"
#include "core/octree/morton.h"
#include "core/render/frame.h"
#include "core/scene/load_scene.h"
#include "teach/teach_error.h"
#include "tests/paths.h"

namespace oct {
namespace {

struct FigureCase {
    Scene scene;
    LayoutOptions options;
    BuiltScene bs;
    Explanation e;
    LayoutFigure f;
};

// grid:20 split to one sphere a leaf: depth 2, a few dozen nodes.
FigureCase makeFigureCase(const std::string& layout) {
    FigureCase c{loadScene("grid:20", {}), {}, {}, {}, {}};
    c.options.build.maxPrims = 1;
    c.bs = buildScene(c.scene, findLayout(layout), c.options);
    CameraOptions cam;
    cam.width = 24;
    cam.height = 24;
    const FrameParams frame = makeFrame(c.scene.bounds(), cam);
    // The first pixel from the centre outwards whose ray visits a leaf.
    for (int x = 12; x < 24; ++x) {
        c.e = explainPixel(c.bs, frame, x, 12);
        if (c.e.primary.hit.prim >= 0) break;
    }
    c.f = layoutFigure(c.scene, c.bs.tree, c.options, c.e);
    return c;
}

std::map<uint64_t, const OctreeNode*> nodesByKey(const Octree& t) {
    std::map<uint64_t, const OctreeNode*> m;
    for (const OctreeNode& n : t.nodes) m[n.key] = &n;
    return m;
}

uint64_t firstLeafVisited(const Explanation& e, const Octree& t) {
    const auto nodes = nodesByKey(t);
    for (const ExplainStep& s : e.primary.steps)
        if (s.event == StepEvent::Pop && s.hit && nodes.at(s.key)->nodeType() == NodeType::Leaf)
            return s.key;
    return 0;
}

size_t countMatches(const std::string& text, const std::string& pattern) {
    const std::regex re(pattern);
    return size_t(
        std::distance(std::sregex_iterator(text.begin(), text.end(), re), std::sregex_iterator()));
}

TEST(LayoutFigure, LinearSlotsAreTheNodesAtTheirLinearIndex) {
    const FigureCase c = makeFigureCase("linear");
    const Octree& t = *c.bs.tree;
    ASSERT_EQ(t.depth, 2);
    EXPECT_EQ(c.f.nodes, t.nodes.size());
    EXPECT_EQ(c.f.linear.size(), 73u);  // (8^3 - 1) / 7
    size_t used = 0;
    for (const LinearSlotFigure& s : c.f.linear) used += s.key != 0;
    EXPECT_EQ(used, t.nodes.size());
    for (const OctreeNode& n : t.nodes) {
        const LinearSlotFigure& s = c.f.linear[linearIndexOfKey(n.key)];
        EXPECT_EQ(s.key, n.key);
        EXPECT_EQ(s.type, n.nodeType());
    }
    const std::string svg = layoutFigureSvg(c.f);
    EXPECT_EQ(countMatches(svg, "class=\"lslot used\""), t.nodes.size());
    EXPECT_EQ(countMatches(svg, "class=\"lslot unused\""), 73u - t.nodes.size());
}

TEST(LayoutFigure, HashKeysAreTheOctreesInBucketKeyModM) {
    const FigureCase c = makeFigureCase("linear");
    const Octree& t = *c.bs.tree;
    std::set<uint64_t> expected, drawn;
    for (const OctreeNode& n : t.nodes) expected.insert(n.key);
    ASSERT_EQ(c.f.hash.size(), c.f.buckets * c.f.bucketSlots);
    for (size_t i = 0; i < c.f.hash.size(); ++i) {
        if (!c.f.hash[i].key) continue;
        drawn.insert(c.f.hash[i].key);
        EXPECT_EQ(c.f.hash[i].key % c.f.buckets, i / c.f.bucketSlots);
    }
    EXPECT_EQ(drawn, expected);
    const std::string svg = layoutFigureSvg(c.f);
    EXPECT_EQ(countMatches(svg, "class=\"hslot\"[^>]*data-key=\"[0-7]+\""), t.nodes.size());
    // A bucket is marked a collision exactly when it holds two keys or more.
    std::map<uint64_t, int> perBucket;
    for (uint64_t k : expected) ++perBucket[k % c.f.buckets];
    size_t collisions = 0;
    for (auto [b, n] : perBucket) collisions += n > 1;
    EXPECT_EQ(countMatches(svg, "class=\"bucket collision\""), collisions);
}

TEST(LayoutFigure, ProbesAreTheExplainedTraversalsOnTheHashLayout) {
    const FigureCase c = makeFigureCase("hash");
    const uint64_t leaf = firstLeafVisited(c.e, *c.bs.tree);
    ASSERT_NE(leaf, 0u);
    EXPECT_EQ(c.f.lookupKey, leaf);
    EXPECT_TRUE(c.f.probesRecorded);
    // The explained steps' first lookup of that key, counted here.
    size_t probes = 0;
    bool started = false;
    for (const ExplainStep& s : c.e.primary.steps) {
        if (s.event == StepEvent::Probe && s.key == leaf) {
            started = true;
            ++probes;
            if (s.hit) break;
        } else if (started) {
            break;
        }
    }
    ASSERT_GT(probes, 0u);
    EXPECT_EQ(c.f.probes.size(), probes);
    EXPECT_EQ(c.f.probes.back().slotKey, leaf);
    const std::string svg = layoutFigureSvg(c.f);
    EXPECT_EQ(countMatches(svg, "data-probe=\"[1-9][0-9]*\""), probes);
}

TEST(LayoutFigure, ProbesOfAnotherLayoutAreTheLookupsOwn) {
    const FigureCase c = makeFigureCase("linear");
    const uint64_t leaf = firstLeafVisited(c.e, *c.bs.tree);
    ASSERT_NE(leaf, 0u);
    EXPECT_FALSE(c.f.probesRecorded);
    // The lookup looks at the key's bucket front to back up to the key.
    const uint64_t b = leaf % c.f.buckets;
    size_t position = 0;
    while (c.f.hash[b * c.f.bucketSlots + position].key != leaf) ++position;
    ASSERT_EQ(c.f.probes.size(), position + 1);
    for (size_t i = 0; i <= position; ++i) {
        EXPECT_EQ(c.f.probes[i].bucket, b);
        EXPECT_EQ(c.f.probes[i].slot, i);
        EXPECT_EQ(c.f.hash[b * c.f.bucketSlots + i].probe, int(i + 1));
    }
}

TEST(LayoutFigure, CompactMasksAreTheNodesChildren) {
    const FigureCase c = makeFigureCase("linear");
    const Octree& t = *c.bs.tree;
    const auto nodes = nodesByKey(t);
    std::map<uint64_t, const CompactRecordFigure*> records;
    for (const CompactRecordFigure& r : c.f.compact) records[r.key] = &r;
    size_t stored = 0;
    for (const OctreeNode& n : t.nodes) {
        const NodeType type = n.nodeType();
        if (type == NodeType::EmptyLeaf) {
            EXPECT_EQ(records.count(n.key), 0u) << "empty leaves are not stored";
            continue;
        }
        ++stored;
        ASSERT_EQ(records.count(n.key), 1u) << keyOctal(n.key);
        const CompactRecordFigure& r = *records[n.key];
        EXPECT_EQ(r.leaf, type == NodeType::Leaf);
        if (type != NodeType::Internal) {
            EXPECT_EQ(r.primCount, n.primCount);
            continue;
        }
        uint32_t child = 0, leaf = 0;
        for (int i = 0; i < 8; ++i) {
            const NodeType ct = nodes.at(childKey(n.key, i))->nodeType();
            child |= uint32_t(ct == NodeType::Internal || ct == NodeType::Leaf) << i;
            leaf |= uint32_t(ct == NodeType::Leaf) << i;
        }
        EXPECT_EQ(r.childMask, child) << keyOctal(n.key);
        EXPECT_EQ(r.leafMask, leaf) << keyOctal(n.key);
    }
    EXPECT_EQ(c.f.compact.size(), stored);
    const std::string svg = layoutFigureSvg(c.f);
    EXPECT_EQ(countMatches(svg, "class=\"crecord\""), stored);
}

TEST(LayoutFigure, EachPanelStatesTheBytesInfoReports) {
    const FigureCase c = makeFigureCase("linear");
    const Octree& t = *c.bs.tree;
    const std::string names[3] = {"linear", "hash", "compact"};
    const uint64_t figure[3] = {c.f.linearBytes, c.f.hashBytes, c.f.compactBytes};
    const std::string svg = layoutFigureSvg(c.f);
    for (int i = 0; i < 3; ++i) {
        const LayoutDesc& d = findLayout(names[i]);
        const uint64_t info = d.report(c.scene, t, c.options).bytes;
        EXPECT_EQ(figure[i], info) << names[i];
        EXPECT_NE(svg.find(std::to_string(info) + " bytes:"), std::string::npos) << names[i];
    }
}

TEST(LayoutFigure, ALargeOctreeIsRefusedSayingWhatToLower) {
    const Scene teapot = loadScene(octtest::kTeapot, {});
    LayoutOptions o;
    const BuiltScene bs = buildScene(teapot, findLayout("linear"), o);
    const Explanation e = explainPixel(bs, makeFrame(teapot.bounds(), CameraOptions{}), 10, 10);
    try {
        layoutFigure(teapot, bs.tree, o, e);
        FAIL() << "the teapot's octree was drawn";
    } catch (const TeachError& err) {
        const std::string m = err.what();
        EXPECT_NE(m.find("--layouts-svg"), std::string::npos) << m;
        EXPECT_NE(m.find(std::to_string(bs.tree->nodes.size()) + " nodes"), std::string::npos) << m;
        EXPECT_NE(m.find("lower --max-depth (now 7)"), std::string::npos) << m;
    }
}

}  // namespace
}  // namespace oct
