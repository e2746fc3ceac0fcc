// `octrace explain --layouts-svg F.svg`: one small octree as each of the three layouts stores
// it, side by side, for a slide: (a) the paper's linear octree, the complete array whose slot p
// has its children at 8p+1..8p+8; (b) the paper's hash octree, m buckets of B slots keyed by
// Morton key with h(k) = k mod m, and the probes of one lookup; (c) our compact layout, 8-byte
// child descriptors (child mask, leaf mask, first child). All three are converted from one
// canonical octree (built_scene.h: convertLayout), each panel states its arrays' bytes as
// `octrace info` counts them (LayoutStorage::bytes, arrayBytes).
//
// This figure is about these three layouts specifically, so unlike the rest of octrace outside
// core/ it names their types and reads their views' own fields (slots, buckets, masks): that is
// what it draws. It stays in teach/, and takes each layout's registry entry by its kName.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/octree/layout.h"
#include "core/scene/scene.h"
#include "teach/explain.h"

namespace oct {

// A figure for a slide: larger octrees are refused (lower --max-depth or raise --max-prims).
constexpr size_t kMaxFigureNodes = 80;
constexpr uint64_t kMaxFigureLinearSlots = 585;  // the complete array of depth 3
constexpr uint64_t kMaxFigureBuckets = 200;

struct FigureArray {
    std::string what;  // forEachArray's name of it
    uint64_t bytes = 0;
};

struct LinearSlotFigure {
    uint64_t key = 0;  // 0: an unused slot (NodeType::Invalid)
    NodeType type = NodeType::Invalid;
    uint32_t prims = 0;
};

struct HashSlotFigure {
    uint64_t key = 0;  // 0: empty
    NodeType type = NodeType::Invalid;
    int probe = 0;  // 1..n: looked at by the shown lookup, in that order; 0: not
};

struct CompactRecordFigure {
    uint64_t key = 0;  // the cell the record stands for (derived by walking from record 0)
    bool leaf = false;
    uint32_t childMask = 0, leafMask = 0, firstChild = 0;  // internal
    uint32_t primOffset = 0, primCount = 0;                // leaf
};

struct LayoutFigure {
    std::string scene;
    uint64_t nodes = 0;  // the canonical octree's
    int depth = 0;
    // (a) linear: every slot of the complete array, index order.
    std::vector<LinearSlotFigure> linear;
    uint64_t linearBytes = 0;
    std::vector<FigureArray> linearArrays;
    // (b) hash: slot b * B + s is bucket b's slot s.
    uint64_t buckets = 0;
    uint32_t bucketSlots = 0;
    std::vector<HashSlotFigure> hash;
    uint64_t hashBytes = 0;
    std::vector<FigureArray> hashArrays;
    uint64_t lookupKey = 0;         // the key whose lookup is shown
    bool lookupIsFirstLeaf = true;  // false: the ray visits no leaf, the root's lookup is shown
    bool probesRecorded = false;    // taken from the Explanation's Probe steps (hash explained)
    std::vector<ExplainStep> probes;
    // (c) compact: every record, index order.
    std::vector<CompactRecordFigure> compact;
    uint64_t compactBytes = 0;
    std::vector<FigureArray> compactArrays;
};

// The three layouts of `tree` (the canonical octree of `scene` under `options.build`). The
// lookup shown is that of the first leaf the explained primary ray visits: its Probe steps when
// `e` explains the hash layout, otherwise the hash view's own lookup recorded now. TeachError
// naming --layouts-svg, the size and --max-depth when the octree is too large to draw.
LayoutFigure layoutFigure(const Scene& scene, const std::shared_ptr<const Octree>& tree,
                          const LayoutOptions& options, const Explanation& e);
std::string layoutFigureSvg(const LayoutFigure& f);

}  // namespace oct
