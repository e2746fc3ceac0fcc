// Structural check of a layout against the canonical octree it was converted from
// (docs/VALIDATION.md, "Layout structure"): every canonical node is looked up through the
// layout's own view, the way its traversal finds children (lookupNode: linear index arithmetic,
// hash probes, compact child masks), and must be there with the same type, the same box (bit for
// bit) and, for a leaf, the same list. Rays reach only the leaves they cross; this reaches all
// of them, so a node a layout loses (a probe that stops early, an index off by one) fails here
// even where no ray of the check passes.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/octree/node_lookup.h"
#include "core/octree/octree.h"

namespace oct {

using NodeLookupFn = std::function<NodeLookup(uint64_t key)>;

struct StructureReport {
    uint64_t nodes = 0;               // canonical nodes looked up
    uint64_t missing = 0;             // an internal node or a non-empty leaf not found
    uint64_t wrongType = 0;           // found as another kind of node
    uint64_t wrongBox = 0;            // found with another box
    uint64_t wrongList = 0;           // a leaf found with another list
    uint64_t broken = 0;              // the lookup left the layout's arrays
    std::vector<std::string> errors;  // the first 16, each naming the node
    uint64_t failures() const { return missing + wrongType + wrongBox + wrongList + broken; }
    bool passes() const { return failures() == 0; }
};

StructureReport checkLayoutStructure(const Octree& canonical, const NodeLookupFn& lookup);

}  // namespace oct
