// What a traversal reports, step by step, when asked: `octrace explain` passes an observer that
// records each step; every kernel passes NoObserver, whose empty inline calls compile to
// nothing, so the traced answers and costs are those of the same code either way.
#pragma once

#include <cstdint>

#include "core/geometry/aabb.h"

namespace oct {

// Why a node was not descended into.
enum class SkipReason : uint8_t {
    Missed = 0,         // the ray's segment does not meet the node's box
    BeyondHit = 1,      // the box is entered beyond the closest hit found so far
    Empty = 2,          // an empty leaf: nothing to hit
    Absent = 3,         // no node stored there (linear: Invalid record; hash: key not found)
    OutsideBounds = 4,  // the ray meets the cell but not the bounds of what the cell holds
};

// The calls a traversal makes. Keys are Morton keys (root 1, child = key << 3 | octant); a node
// is identified by its key in every layout, whatever the layout stores.
struct NoObserver {
    // A node's box was tested against the ray (the root, or a child of an internal node);
    // hit with the clipped interval [t0, t1] or missed.
    OCT_HD void boxTested(uint64_t /*key*/, int /*depth*/, const Aabb& /*box*/, bool /*hit*/,
                          float /*t0*/, float /*t1*/) {}
    // A child was not tested: an empty leaf or an absent node.
    OCT_HD void childSkipped(uint64_t /*key*/, SkipReason /*why*/) {}
    // A node was taken from the stack: visited (its children or primitives follow), or
    // dropped because the closest hit found meanwhile is nearer than tEnter.
    OCT_HD void nodePopped(uint64_t /*key*/, float /*tEnter*/, bool /*visited*/) {}
    // A primitive was tested: hit at t, or missed (t undefined).
    OCT_HD void primTested(uint32_t /*prim*/, bool /*hit*/, float /*t*/) {}
    // The hash layout looked at slot `slot` of bucket `bucket` for `key` and found `slotKey`
    // there (0: an empty slot, which ends the search).
    OCT_HD void hashProbe(uint64_t /*key*/, uint64_t /*bucket*/, uint32_t /*slot*/,
                          uint64_t /*slotKey*/) {}
};

}  // namespace oct
