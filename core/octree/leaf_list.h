// A leaf's primitive list tested against a ray: the one bounds-checked loop every octree
// traversal runs at a leaf (traversal.h, compact_octree.h). A list entry past the global index
// array, or an id past the primitives, is a broken structure: the traversal then answers
// faultHit() (core/geometry/ray.h), never reads past an array.
#pragma once

#include <cstdint>

#include "core/geometry/primitives_view.h"
#include "core/octree/array_span.h"

namespace oct {

enum class LeafOutcome : uint8_t {
    Done = 0,   // every entry tested; traversal goes on
    Found = 1,  // any-hit query: a hit in [tmin, tmax], traversal stops with it
    Fault = 2,  // the list leaves the arrays: traversal stops with faultHit()
};

// Tests entries [offset, offset + count) of `list` (ids into `prims`) and keeps the nearest in
// `best` (considerPrimitive's tie rule). kAnyHit: stop at the first hit.
template <bool kAnyHit, class Obs>
OCT_HD inline LeafOutcome testLeafList(const ArraySpan<uint32_t>& list, uint32_t offset,
                                       uint32_t count, const PrimitivesView& prims,
                                       const PreparedRay& q, Hit& best, TraceCost& cost, Obs& obs) {
    for (uint32_t k = 0; k < count; ++k) {
        const uint64_t at = uint64_t(offset) + k;
        if (at >= list.count) return LeafOutcome::Fault;
        const uint32_t prim = loadReadOnly(list.data + at);
        if (prim >= prims.count) return LeafOutcome::Fault;
        considerPrimitive(prims, prim, q, best, cost, obs);
        if (kAnyHit && best.prim >= 0) return LeafOutcome::Found;
    }
    return LeafOutcome::Done;
}

}  // namespace oct
