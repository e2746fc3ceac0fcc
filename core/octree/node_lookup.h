// A node of the canonical octree as a layout stores it, found through the layout's own view
// (its root, its child step), for the structural check of validation (docs/VALIDATION.md,
// "Layout structure"): every canonical node must be found where the layout's traversal would
// look, with the same type, box and leaf list. Host code only; the views are host views.
#pragma once

#include <cstdint>

#include "core/geometry/aabb.h"
#include "core/octree/node.h"

namespace oct {

struct NodeLookup {
    bool found = false;                 // false: the layout has no record at this key
    NodeType type = NodeType::Invalid;  // Internal, Leaf or EmptyLeaf
    Aabb box{};                         // stored (node records) or derived (compact)
    const uint32_t* list = nullptr;     // a leaf's entries in the layout's index array
    uint32_t count = 0;                 // their number
    bool broken = false;                // the walk left the layout's arrays
};

}  // namespace oct
