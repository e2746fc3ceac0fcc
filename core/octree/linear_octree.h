// Linear octree (paper, layout 1): the complete array of (8^(d+1) - 1) / 7 node records of a
// tree of depth d, root at 0, the children of p at 8p+1 .. 8p+8, adjacent. Positions below a
// leaf hold NodeType::Invalid records. Converted from the canonical octree.
#pragma once

#include <cstdint>
#include <type_traits>
#include <vector>

#include "core/octree/layout.h"
#include "core/octree/traversal.h"

namespace oct {

struct LinearOctreeView {
    static constexpr bool kNodeRecords = true;  // traversed by traverseOctree (traversal.h)
    const OctreeNode* nodes;                    // 8 bytes
    uint64_t nodeCount;                         // 8 bytes
    const uint32_t* primIndices;                // 8 bytes: the global leaf index array
    uint64_t primIndexCount;                    // 8 bytes: its entries (bounds, traversal.h)
    PrimitivesView prims;                       // 24 bytes

    OCT_HD const OctreeNode* root() const {
        NoObserver none;
        return root(none);
    }
    template <class Obs>
    OCT_HD const OctreeNode* root(Obs&) const {
        return nodes;
    }
    // The child of the internal node stored at `at` (its Morton key is not needed here).
    // Children of an internal node always exist in the complete array (it has depth+1 levels);
    // a position past the array (a corrupted tree) is absent rather than read.
    template <class Obs>
    OCT_HD const OctreeNode* child(const OctreeNode* at, uint64_t /*key*/, int octant, Obs&) const {
        const uint64_t p = static_cast<uint64_t>(at - nodes), c = 8 * p + 1 + uint64_t(octant);
        // After the parent and inside the array, or absent: the walk can neither cycle nor
        // read past the array, whatever the index arithmetic above computes (traversal.h).
        // (p < c < nodeCount as one unsigned compare: it runs for every child tested.)
        return c - p - 1 < nodeCount - p - 1 ? nodes + c : nullptr;
    }
};
static_assert(std::is_trivially_copyable<LinearOctreeView>::value, "views are passed by value");

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

// Registry entry. Arrays: 0 the node records, 1 the leaf index list.
struct LinearLayout {
    static constexpr const char* kName = "linear";
    static constexpr const char* kSummary =
        "the paper's linear octree: the complete array, children of p at 8p+1..8p+8";
    static constexpr bool kUsesOctree = true;
    using View = LinearOctreeView;

    static LayoutStorage convert(const Scene&, const std::shared_ptr<const Octree>& tree,
                                 const LayoutOptions& o);
    // Computed from the depth alone: the complete array is not allocated.
    static LayoutReport report(const Scene&, const Octree& tree, const LayoutOptions& o);
    static View view(const LayoutArrays& a, PrimitivesView prims) {
        return {a.array<OctreeNode>(0), a.count<OctreeNode>(0), a.array<uint32_t>(1),
                a.count<uint32_t>(1), prims};
    }
};

}  // namespace oct
