#include "teach/layout_figure.h"

#include <algorithm>
#include <cstdio>
#include <map>

#include "core/octree/built_scene.h"
#include "core/octree/morton.h"
#include "teach/svg.h"
#include "teach/teach_error.h"

namespace oct {
namespace {

template <class View>
std::vector<FigureArray> arraysOf(const View& v) {
    std::vector<FigureArray> out;
    View::forEachArray(v, [&](const char* what, const auto& span) {
        out.push_back({what, span.bytes()});
    });
    return out;
}

void checkDrawable(const Octree& tree, const std::string& scene) {
    const uint64_t slots = linearNodeCount(tree.depth);
    if (tree.nodes.size() <= kMaxFigureNodes && slots <= kMaxFigureLinearSlots) return;
    throw TeachError(
        "--layouts-svg: the octree of '" + scene + "' has " + std::to_string(tree.nodes.size()) +
        " nodes and depth " + std::to_string(tree.depth) + " (" + std::to_string(slots) +
        " linear slots), more than a figure can show (" + std::to_string(kMaxFigureNodes) +
        " nodes, " + std::to_string(kMaxFigureLinearSlots) + " slots): lower --max-depth (now " +
        std::to_string(tree.params.maxDepth) + ") or raise --max-prims");
}

BuiltScene convertTo(const char* name, const Scene& scene,
                     const std::shared_ptr<const Octree>& tree, const LayoutOptions& options) {
    return convertLayout(scene, tree, findLayout(name), options);
}

void fillLinear(LayoutFigure& f, const BuiltScene& bs) {
    const LinearOctreeView& v = bs.storage.as<LinearOctreeView>();
    for (uint64_t i = 0; i < v.nodes.count; ++i) {
        const OctreeNode& n = v.nodes.data[i];
        LinearSlotFigure s;
        s.type = n.nodeType();
        s.key = s.type == NodeType::Invalid ? 0 : n.key;
        s.prims = n.primCount;
        f.linear.push_back(s);
    }
    f.linearBytes = bs.layoutBytes();
    f.linearArrays = arraysOf(v);
}

// The first leaf the primary ray visits: the key of its first visited Pop whose node is a leaf.
uint64_t firstLeafVisited(const Explanation& e, const Octree& tree) {
    std::map<uint64_t, NodeType> types;
    for (const OctreeNode& n : tree.nodes) types[n.key] = n.nodeType();
    for (const ExplainStep& s : e.primary.steps)
        if (s.event == StepEvent::Pop && s.hit && types[s.key] == NodeType::Leaf) return s.key;
    return 0;
}

// The first run of Probe steps for `key` in the explained primary ray: one lookup.
std::vector<ExplainStep> recordedLookup(const Explanation& e, uint64_t key) {
    std::vector<ExplainStep> run;
    for (const ExplainStep& s : e.primary.steps) {
        if (s.event == StepEvent::Probe && s.key == key) {
            run.push_back(s);
            if (s.hit) break;
        } else if (!run.empty()) {
            break;
        }
    }
    return run;
}

void fillHash(LayoutFigure& f, const BuiltScene& bs, const Explanation& e, const Octree& tree) {
    const HashOctreeView& v = bs.storage.as<HashOctreeView>();
    if (v.bucketCount > kMaxFigureBuckets)
        throw TeachError("--layouts-svg: the hash octree has " + std::to_string(v.bucketCount) +
                         " buckets, more than the " + std::to_string(kMaxFigureBuckets) +
                         " a figure can show: raise --hash-slots (now " +
                         std::to_string(v.bucketSlots) + ") or lower --max-depth");
    f.buckets = v.bucketCount;
    f.bucketSlots = v.bucketSlots;
    for (uint64_t i = 0; i < v.slots.count; ++i) {
        HashSlotFigure s;
        s.key = v.slots.data[i].key;
        s.type = s.key ? v.slots.data[i].nodeType() : NodeType::Invalid;
        f.hash.push_back(s);
    }
    f.hashBytes = bs.layoutBytes();
    f.hashArrays = arraysOf(v);
    f.lookupKey = firstLeafVisited(e, tree);
    f.lookupIsFirstLeaf = f.lookupKey != 0;
    if (!f.lookupIsFirstLeaf) f.lookupKey = kRootKey;
    // The explained traversal's own probes when it ran on the hash layout; otherwise the view's
    // lookup (HashOctreeView::find) run now with a recorder, the same code the kernel runs.
    f.probesRecorded = e.layout == HashLayout::kName;
    if (f.probesRecorded) {
        f.probes = recordedLookup(e, f.lookupKey);
    } else {
        StepRecorder rec;
        v.find(f.lookupKey, rec);
        f.probes = rec.steps;
    }
    for (size_t i = 0; i < f.probes.size(); ++i)
        f.hash[f.probes[i].bucket * v.bucketSlots + f.probes[i].slot].probe = int(i + 1);
}

// Record r's cell and form, walking from record 0 as lookupNode(CompactOctreeView) does: an
// internal record's children are stored from firstChild on, one per set bit of childMask in
// octant order, and its leafMask says which of them are leaves.
void fillCompact(LayoutFigure& f, const BuiltScene& bs) {
    const CompactOctreeView& v = bs.storage.as<CompactOctreeView>();
    f.compact.assign(v.nodes.count, CompactRecordFigure{});
    if (v.nodes.count > 0) {
        f.compact[0].key = kRootKey;
        f.compact[0].leaf = v.rootIsLeaf != 0;
    }
    for (uint64_t r = 0; r < v.nodes.count; ++r) {
        CompactRecordFigure& c = f.compact[r];
        const CompactNode& n = v.nodes.data[r];
        if (c.leaf) {
            c.primOffset = n.primOffset();
            c.primCount = n.primCount();
            continue;
        }
        c.childMask = n.childMask();
        c.leafMask = n.leafMask();
        c.firstChild = n.firstChild();
        uint32_t next = c.firstChild;
        for (int i = 0; i < 8; ++i) {
            if (!(c.childMask >> i & 1)) continue;
            if (next < f.compact.size()) {
                f.compact[next].key = childKey(c.key, i);
                f.compact[next].leaf = (c.leafMask >> i & 1) != 0;
            }
            ++next;
        }
    }
    f.compactBytes = bs.layoutBytes();
    f.compactArrays = arraysOf(v);
}

}  // namespace

LayoutFigure layoutFigure(const Scene& scene, const std::shared_ptr<const Octree>& tree,
                          const LayoutOptions& options, const Explanation& e) {
    checkDrawable(*tree, scene.name);
    LayoutFigure f;
    f.scene = scene.name;
    f.nodes = tree->nodes.size();
    f.depth = tree->depth;
    fillLinear(f, convertTo(LinearLayout::kName, scene, tree, options));
    fillHash(f, convertTo(HashLayout::kName, scene, tree, options), e, *tree);
    fillCompact(f, convertTo(CompactLayout::kName, scene, tree, options));
    return f;
}

// --- the figure ------------------------------------------------------------------------------

namespace {

constexpr double kWidth = 1000, kMarginX = 20;

const char* typeFill(NodeType t) {
    switch (t) {
        case NodeType::Internal:
            return "#3b5dc9";
        case NodeType::Leaf:
            return "#38b764";
        case NodeType::EmptyLeaf:
            return "#d8f0df";
        case NodeType::Invalid:
            return "#ffffff";
    }
    return "#ffffff";
}
const char* typeName(NodeType t) {
    switch (t) {
        case NodeType::Internal:
            return "internal";
        case NodeType::Leaf:
            return "leaf";
        case NodeType::EmptyLeaf:
            return "empty leaf";
        case NodeType::Invalid:
            return "unused";
    }
    return "unused";
}

std::string bytesLine(uint64_t total, const std::vector<FigureArray>& arrays) {
    std::string s = std::to_string(total) + " bytes:";
    for (size_t i = 0; i < arrays.size(); ++i)
        s += std::string(i ? " +" : "") + " " + arrays[i].what + " " +
             std::to_string(arrays[i].bytes);
    return s;
}

// `text` left-aligned in `width` characters (monospace columns).
std::string padded(std::string text, size_t width) {
    if (text.size() < width) text.append(width - text.size(), ' ');
    return text;
}

std::string bits8(uint32_t mask) {
    std::string s;
    for (int i = 7; i >= 0; --i) s += char('0' + (mask >> i & 1));
    return s;
}

double heading(SvgWriter& svg, double y, const std::string& title, const std::string& sub) {
    svg.text(kMarginX, y, title, " font-size=\"15\" font-weight=\"bold\"");
    svg.text(kMarginX, y + 18, sub, " font-size=\"12\" fill=\"#404040\"");
    return y + 34;
}

// (a) Level by level, 64 slots a row in groups of 8 siblings (the children of slot p at
// 8p+1..8p+8), used slots filled by type, unused ones white.
double drawLinear(SvgWriter& svg, const LayoutFigure& f, double y) {
    uint64_t used = 0;
    for (const LinearSlotFigure& s : f.linear) used += s.type != NodeType::Invalid;
    y = heading(svg, y,
                std::string("(a) ") + LinearLayout::kName + " octree: the complete array, " +
                    std::to_string(f.linear.size()) + " slots, " + std::to_string(used) +
                    " used; the children of slot p at 8p+1..8p+8",
                bytesLine(f.linearBytes, f.linearArrays));
    constexpr double kSlot = 12, kGap = 3, kRowH = 16, kLabelW = 70;
    uint64_t first = 0;
    for (int level = 0; level <= f.depth; ++level) {
        const uint64_t count = uint64_t(1) << (3 * level);
        for (uint64_t i = 0; i < count; ++i) {
            if (i % 64 == 0) {
                if (i > 0) y += kRowH;
                svg.text(kMarginX, y + 10, "slot " + std::to_string(first + i),
                         " font-size=\"10\" fill=\"#606060\"");
            }
            const uint64_t index = first + i;
            const LinearSlotFigure& s = f.linear[index];
            const double x =
                kMarginX + kLabelW + double(i % 64) * kSlot + double(i % 64 / 8) * kGap;
            std::string title = "slot " + std::to_string(index) + ": " + typeName(s.type);
            if (s.key) title += ", key " + keyOctal(s.key) + " (octal)";
            svg.withTitle("<rect x=\"" + svgNum(x) + "\" y=\"" + svgNum(y) + "\" width=\"" +
                              svgNum(kSlot - 1) + "\" height=\"" + svgNum(kSlot - 1) +
                              "\" class=\"lslot " + (s.key ? "used" : "unused") +
                              "\" data-slot=\"" + std::to_string(index) + "\" data-key=\"" +
                              (s.key ? keyOctal(s.key) : "") + "\" fill=\"" + typeFill(s.type) +
                              "\" stroke=\"#909090\" stroke-width=\"0.6\"",
                          "rect", title);
        }
        first += count;
        y += kRowH;
    }
    // The types' key.
    double x = kMarginX;
    for (NodeType t :
         {NodeType::Internal, NodeType::Leaf, NodeType::EmptyLeaf, NodeType::Invalid}) {
        svg.rect(
            x, y, 11, 11,
            std::string(" fill=\"") + typeFill(t) + "\" stroke=\"#909090\" stroke-width=\"0.6\"");
        svg.text(x + 16, y + 10, typeName(t), " font-size=\"11\"");
        x += 110;
    }
    return y + 34;
}

// (b) Each bucket a row of B slots, keys in octal; a bucket holding more than one key is a
// collision (marked); the shown lookup's probes numbered.
double drawHash(SvgWriter& svg, const LayoutFigure& f, double y) {
    uint64_t keys = 0, collisions = 0;
    for (uint64_t b = 0; b < f.buckets; ++b) {
        uint32_t held = 0;
        for (uint32_t s = 0; s < f.bucketSlots; ++s) held += f.hash[b * f.bucketSlots + s].key != 0;
        keys += held;
        collisions += held > 1;
    }
    y = heading(
        svg, y,
        std::string("(b) ") + HashLayout::kName + " octree: m = " + std::to_string(f.buckets) +
            " buckets x B = " + std::to_string(f.bucketSlots) + " slots, h(k) = k mod m, " +
            std::to_string(keys) + " keys (octal), " + std::to_string(collisions) + " collisions",
        bytesLine(f.hashBytes, f.hashArrays));
    std::string lookup =
        "lookup of key " + keyOctal(f.lookupKey) +
        (f.lookupIsFirstLeaf ? " (the first leaf the ray visits)"
                             : " (the root: the ray visits no leaf)") +
        ": bucket " + std::to_string(f.lookupKey % std::max<uint64_t>(f.buckets, 1)) + ", " +
        std::to_string(f.probes.size()) + (f.probes.size() == 1 ? " probe" : " probes") +
        (f.probesRecorded ? ", as the explained traversal made them"
                          : ", as the hash view's lookup makes them");
    svg.text(kMarginX, y, lookup, " font-size=\"12\" fill=\"#a05000\"");
    y += 12;
    constexpr double kSlotW = 46, kRowH = 17, kLabelW = 54, kColGap = 18;
    const double colW = kLabelW + f.bucketSlots * kSlotW + kColGap;
    const uint64_t cols = std::max<uint64_t>(1, uint64_t((kWidth - 2 * kMarginX) / colW));
    const uint64_t rows = std::max<uint64_t>(20, (f.buckets + cols - 1) / cols);
    for (uint64_t b = 0; b < f.buckets; ++b) {
        const double x0 = kMarginX + double(b / rows) * colW, yb = y + double(b % rows) * kRowH;
        uint32_t held = 0;
        for (uint32_t s = 0; s < f.bucketSlots; ++s) held += f.hash[b * f.bucketSlots + s].key != 0;
        svg.text(x0, yb + 12, "b " + std::to_string(b) + (held > 1 ? " *" : ""),
                 std::string(" class=\"bucket") + (held > 1 ? " collision" : "") +
                     "\" font-size=\"11\"" +
                     (held > 1 ? " font-weight=\"bold\" fill=\"#b13e53\"" : ""));
        for (uint32_t s = 0; s < f.bucketSlots; ++s) {
            const HashSlotFigure& h = f.hash[b * f.bucketSlots + s];
            const double x = x0 + kLabelW + s * kSlotW;
            svg.rect(x, yb, kSlotW - 2, kRowH - 3,
                     " class=\"hslot\" data-bucket=\"" + std::to_string(b) + "\" data-slot=\"" +
                         std::to_string(s) + "\" data-key=\"" + (h.key ? keyOctal(h.key) : "") +
                         "\" data-probe=\"" + std::to_string(h.probe) + "\" fill=\"" +
                         (h.key ? typeFill(h.type) : "#ffffff") +
                         "\" fill-opacity=\"0.35\" stroke=\"" + (h.probe ? "#e07000" : "#909090") +
                         "\" stroke-width=\"" + (h.probe ? "2.2" : "0.6") + "\"");
            if (h.key)
                svg.text(x + 3, yb + 11, keyOctal(h.key),
                         " font-size=\"10\" font-family=\"monospace\"");
            if (h.probe)
                svg.text(
                    x + kSlotW - 5, yb + 11, std::to_string(h.probe),
                    " font-size=\"10\" text-anchor=\"end\" font-weight=\"bold\" fill=\"#e07000\"");
        }
    }
    y += double(std::min<uint64_t>(rows, std::max<uint64_t>(f.buckets, 1))) * kRowH + 6;
    svg.text(kMarginX, y + 10,
             "* a collision: the bucket holds more than one key. Orange: a probe of the lookup, "
             "numbered; slots fill front to back, an empty slot ends the lookup.",
             " font-size=\"11\" fill=\"#404040\"");
    return y + 34;
}

// (c) One row per record: its cell's key, then an internal record's child mask, leaf mask (bit
// i = octant i, bit 7 first) and first child, or a leaf record's list in primIndices.
double drawCompact(SvgWriter& svg, const LayoutFigure& f, double y) {
    y = heading(svg, y,
                std::string("(c) ") + CompactLayout::kName +
                    " octree: " + std::to_string(f.compact.size()) +
                    " records of 8 bytes, children stored together; empty leaves not stored",
                bytesLine(f.compactBytes, f.compactArrays));
    constexpr double kRowH = 15, kColW = 240;
    constexpr uint64_t kRows = 20;
    const uint64_t cols = (f.compact.size() + kRows - 1) / kRows;
    for (uint64_t c = 0; c < std::max<uint64_t>(cols, 1); ++c)
        svg.text(kMarginX + c * kColW, y + 10, "rec key  child    leaf     first",
                 " font-size=\"10\" font-family=\"monospace\" font-weight=\"bold\" "
                 "xml:space=\"preserve\"");
    y += kRowH;
    for (size_t r = 0; r < f.compact.size(); ++r) {
        const CompactRecordFigure& c = f.compact[r];
        std::string row = padded(std::to_string(r), 4) + padded(keyOctal(c.key), 5);
        if (c.leaf)
            row += "leaf: " + std::to_string(c.primCount) + " prims from " +
                   std::to_string(c.primOffset);
        else
            row +=
                bits8(c.childMask) + " " + bits8(c.leafMask) + " " + std::to_string(c.firstChild);
        svg.text(kMarginX + double(r / kRows) * kColW, y + double(r % kRows) * kRowH + 10, row,
                 " class=\"crecord\" data-record=\"" + std::to_string(r) + "\" data-key=\"" +
                     keyOctal(c.key) + "\" data-leaf=\"" + (c.leaf ? "1" : "0") +
                     "\" data-child-mask=\"" + bits8(c.childMask) + "\" data-leaf-mask=\"" +
                     bits8(c.leafMask) + "\" data-first-child=\"" + std::to_string(c.firstChild) +
                     "\" font-size=\"10\" font-family=\"monospace\" xml:space=\"preserve\"" +
                     (c.leaf ? " fill=\"#2a8a4a\"" : " fill=\"#203a90\""));
    }
    y += double(std::min<uint64_t>(kRows, f.compact.size())) * kRowH + 8;
    svg.text(
        kMarginX, y + 10,
        "masks: bit i (i = x + 2y + 4z) from the right; the children of an internal record are "
        "records first .. first + (bits in child) - 1",
        " font-size=\"11\" fill=\"#404040\"");
    return y + 24;
}

}  // namespace

std::string layoutFigureSvg(const LayoutFigure& f) {
    const std::string title = "octrace explain --layouts-svg: " + f.scene + ", one octree of " +
                              std::to_string(f.nodes) + " nodes (depth " + std::to_string(f.depth) +
                              ") in three layouts";
    // Drawn once to learn the height, then again at that height: the panels' sizes depend on
    // the octree.
    auto draw = [&](double height) {
        SvgWriter svg(kWidth, height, title);
        svg.text(kMarginX, 26, title, " font-size=\"16\" font-weight=\"bold\"");
        svg.text(kMarginX, 44,
                 "keys: Morton keys in octal, 1 is the root and each further digit an octant x + "
                 "2y + 4z",
                 " font-size=\"12\" fill=\"#404040\"");
        double y = drawLinear(svg, f, 72);
        y = drawHash(svg, f, y);
        y = drawCompact(svg, f, y);
        return std::make_pair(y, svg.finish());
    };
    return draw(draw(0).first + 10).second;
}

}  // namespace oct
