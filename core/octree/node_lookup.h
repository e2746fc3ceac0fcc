// A node of the canonical octree as a layout stores it, found through the layout's own view
// (its root, its child step), for validate's structural check (docs/VALIDATION.md, "Layout
// structure"). Host code only; the views are host views.
#pragma once

#include <cstdint>
#include <type_traits>

#include "core/geometry/aabb.h"
#include "core/octree/morton.h"
#include "core/octree/node.h"
#include "core/octree/traversal_observer.h"

namespace oct {

struct NodeLookup {
    bool found = false;                 // false: the layout has no record at this key
    NodeType type = NodeType::Invalid;  // Internal, Leaf or EmptyLeaf
    Aabb box{};                         // stored (node records) or derived (compact)
    const uint32_t* list = nullptr;     // a leaf's entries in the layout's index array
    uint32_t count = 0;                 // their number
    bool broken = false;                // the walk left the layout's arrays
};

// The node with Morton key `key` in a view that stores the paper's node record (kNodeRecords:
// linear, hash), found as traverseOctree finds it: from root(), one child() step per octant
// digit of the key.
template <class View, std::enable_if_t<View::kNodeRecords, int> = 0>
inline NodeLookup lookupNode(const View& v, uint64_t key) {
    NoObserver none;
    NodeLookup out;
    const OctreeNode* at = v.root(none);
    const int depth = keyDepth(key);
    for (int d = depth - 1; at != nullptr && d >= 0; --d) {
        if (at->nodeType() != NodeType::Internal) return out;
        at = v.child(at, at->key, int((key >> (3 * d)) & 7u), none);
    }
    if (at == nullptr || at->key != key) return out;
    out.found = true;
    out.type = at->nodeType();
    out.box = at->box;
    if (out.type == NodeType::Leaf || out.type == NodeType::EmptyLeaf) {
        if (uint64_t(at->primOffset) + at->primCount > v.primIndices.count) {
            out.broken = true;
            return out;
        }
        out.list = v.primIndices.data + at->primOffset;
        out.count = at->primCount;
    }
    return out;
}

}  // namespace oct
