// The linear layout on the host: the complete array built from the canonical octree, its size
// computed before anything is allocated, and its registry entry (layout.h).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/octree/layout.h"
#include "core/octree/linear_octree.h"
#include "core/octree/node_lookup.h"
#include "core/octree/skip_reasons.h"

namespace oct {

struct LinearOctree {
    std::vector<OctreeNode> nodes;  // (8^(depth+1) - 1) / 7 records
};

// Nodes of a complete octree of the given depth, (8^(d+1) - 1) / 7, and its bytes. Both
// saturate at UINT64_MAX rather than overflow (depth 21 has 1.2e19 nodes).
uint64_t linearNodeCount(int depth);
uint64_t linearBytes(int depth);

// Throws OctreeError naming the bytes needed when they exceed budgetBytes; nothing is
// allocated before that check.
LinearOctree buildLinear(const Octree& tree, uint64_t budgetBytes = kDefaultLinearBudget);
LinearOctreeView linearView(const LinearOctree& lin, const Octree& tree, PrimitivesView prims);

struct LinearLayout {
    static constexpr const char* kName = "linear";
    static constexpr const char* kSummary =
        "the paper's linear octree: the complete array, children of p at 8p+1..8p+8";
    static constexpr bool kUsesOctree = true;
    // Invalid records below leaves are absent; empty leaves are stored and skipped.
    static constexpr uint32_t kSkipReasons = skipReasonBits(
        SkipReason::Missed, SkipReason::BeyondHit, SkipReason::Empty, SkipReason::Absent);
    using View = LinearOctreeView;

    static LayoutStorage convert(const Scene& scene, const std::shared_ptr<const Octree>& tree,
                                 const LayoutOptions& o);
    // Computed from the depth alone: the complete array is not allocated.
    static LayoutReport report(const Scene&, const Octree& tree, const LayoutOptions& o);
    // The array's size follows from the depth alone: the deepest one within --linear-budget
    // and the 2^32 records the traversal indexes.
    static void limitBuild(BuildParams& build, const LayoutOptions& o);
};

}  // namespace oct
