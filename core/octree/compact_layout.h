// The compact layout on the host: the canonical octree converted to child descriptors and
// quantised bounds (compact_octree.h), its node lookup for validate, and its registry entry
// (layout.h).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/octree/compact_octree.h"
#include "core/octree/layout.h"
#include "core/octree/node_lookup.h"
#include "core/octree/skip_reasons.h"

namespace oct {

struct CompactOctree {
    std::vector<CompactNode> nodes;   // root at 0, children adjacent (breadth first)
    std::vector<QuantBounds> bounds;  // per record; empty when built without bounds
    Aabb rootBox{};
    bool rootIsLeaf = false;
};

// Converts the canonical octree: internal nodes and non-empty leaves, in breadth-first order.
// The leaf lists stay in the canonical tree's primIndices (shared). With `scene`, also the
// quantised bounds of what each record's cell holds (leaf: its triangles clipped to the cell,
// its spheres' boxes cut to the cell; internal: the union of its children's), rounded outwards.
CompactOctree buildCompact(const Octree& tree, const Scene* scene = nullptr);
CompactOctreeView compactView(const CompactOctree& c, const Octree& tree, PrimitivesView prims);

// The node with Morton key `key` as traversal finds it: from record 0 and the root box, one
// step per octant digit through childMask, leafMask and compactChildIndex, the box halved by
// childBox. Empty leaves are not stored: found = false.
NodeLookup lookupNode(const CompactOctreeView& v, uint64_t key);

struct CompactLayout {
    static constexpr const char* kName = "compact";
    static constexpr const char* kSummary =
        "beyond the paper: 8-byte child descriptors, derived boxes, parametric front-to-back";
    static constexpr bool kUsesOctree = true;
    // Empty leaves are not stored (a clear child bit: empty); a cell whose quantised bounds the
    // ray misses is skipped after it was entered (outside bounds); an empty tree is absent.
    static constexpr uint32_t kSkipReasons =
        skipReasonBits(SkipReason::Missed, SkipReason::BeyondHit, SkipReason::Empty,
                       SkipReason::Absent, SkipReason::OutsideBounds);
    using View = CompactOctreeView;

    static LayoutStorage convert(const Scene& scene, const std::shared_ptr<const Octree>& tree,
                                 const LayoutOptions& o);
    static LayoutReport report(const Scene& scene, const Octree& tree, const LayoutOptions& o);
};

}  // namespace oct
