// Linear octree (paper, layout 1), the kernel's view: the complete array of (8^(d+1) - 1) / 7
// node records of a tree of depth d, root at 0, the children of p at 8p+1 .. 8p+8, adjacent.
// Positions below a leaf hold NodeType::Invalid records. Device code only; building it from
// the canonical octree is linear_layout.h.
#pragma once

#include <cstdint>
#include <type_traits>

#include "core/octree/array_span.h"
#include "core/octree/traversal.h"

namespace oct {

// 56 bytes.
struct LinearOctreeView {
    static constexpr bool kNodeRecords = true;  // traversed by traverseOctree (traversal.h)
    ArraySpan<OctreeNode> nodes;                // 16 bytes: the complete array
    ArraySpan<uint32_t> primIndices;            // 16 bytes: the global leaf index array
    PrimitivesView prims;                       // 24 bytes

    // The arrays, each once (layout.h): host view, CUDA upload and byte count derive from it.
    template <class V, class F>
    static void forEachArray(V& v, F&& f) {
        f("the linear octree's nodes", v.nodes);
        f("the leaf index list", v.primIndices);
    }

    // The array the traversal's record indices count in (at most kMaxNodeRecords).
    OCT_HD const OctreeNode* records() const { return nodes.data; }
    OCT_HD const OctreeNode* root() const {
        NoObserver none;
        return root(none);
    }
    template <class Obs>
    OCT_HD const OctreeNode* root(Obs&) const {
        return nodes.data;
    }
    // The child of the internal node stored at `at` (its Morton key is not needed here).
    // Children of an internal node always exist in the complete array (it has depth+1 levels);
    // a position past the array (a corrupted tree) is absent rather than read.
    template <class Obs>
    OCT_HD const OctreeNode* child(const OctreeNode* at, uint64_t /*key*/, int octant, Obs&) const {
        const uint64_t p = static_cast<uint64_t>(at - nodes.data), c = 8 * p + 1 + uint64_t(octant);
        // After the parent and inside the array, or absent: the walk can neither cycle nor
        // read past the array, whatever the index arithmetic above computes (traversal.h).
        // (p < c < count as one unsigned compare: it runs for every child tested.)
        return c - p - 1 < nodes.count - p - 1 ? nodes.data + c : nullptr;
    }
};
// The layout above is for 64-bit pointers (hosts, CUDA); the explain page's WebAssembly kernel
// (32-bit pointers) has smaller spans.
static_assert(sizeof(void*) != 8 || sizeof(LinearOctreeView) == 56,
              "LinearOctreeView byte layout is documented above");
static_assert(std::is_trivially_copyable<LinearOctreeView>::value, "views are passed by value");

}  // namespace oct
