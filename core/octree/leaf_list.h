// A leaf's primitive list tested against a ray: the one bounds-checked loop every octree
// traversal runs at a leaf (traversal.h, compact_octree.h). A list entry past the global index
// array, or an id past the primitives, is a broken structure: the traversal then answers
// faultHit() (core/geometry/ray.h), never reads past an array.
#pragma once

#include <cstdint>
#include <type_traits>

#include "core/geometry/primitives_view.h"
#include "core/geometry/triangle_batch.h"
#include "core/octree/array_span.h"
#include "core/octree/traversal_observer.h"

namespace oct {

enum class LeafOutcome : uint8_t {
    Done = 0,   // every entry tested; traversal goes on
    Found = 1,  // any-hit query: a hit in [tmin, tmax], traversal stops with it
    Fault = 2,  // the list leaves the arrays: traversal stops with faultHit()
};

#if defined(OCT_TRIANGLE_BATCH)
// testLeafList of a triangle list on the host without an observer: four triangles a batch
// (triangle_batch.h), each lane then taken in list order as considerPrimitive takes it, against
// the closest hit so far, so the same hit, costs and fault as one triangle at a time.
template <bool kAnyHit>
inline LeafOutcome testTriangleListBatched(const ArraySpan<uint32_t>& list, uint32_t offset,
                                           uint32_t count, const PrimitivesView& prims,
                                           const PreparedRay& q, Hit& best, TraceCost& cost) {
    const ShearedLanes lanes = makeShearedLanes(q.sheared);
    for (uint32_t k = 0; k < count; k += 4) {
        const uint32_t n = count - k < 4 ? count - k : 4;
        const Triangle* tri[4];
        uint32_t id[4];
        uint32_t valid = 0;  // the entries before the first that leaves the arrays
        for (; valid < n; ++valid) {
            const uint64_t at = uint64_t(offset) + k + valid;
            if (at >= list.count) break;
            const uint32_t prim = loadReadOnly(list.data + at);
            if (prim >= prims.count) break;
            id[valid] = prim;
            tri[valid] = prims.tris + prim;
        }
        if (valid == 0) return LeafOutcome::Fault;
        for (uint32_t j = valid; j < 4; ++j) tri[j] = tri[valid - 1];
        const TriangleBatch b = intersectTriangles4(q.sheared, lanes, tri);
        for (uint32_t j = 0; j < valid; ++j) {
            ++cost.primsTested;
            float t = b.tHit[j];
            bool hit = false;
            if (b.verdict[j] == LaneVerdict::Range)
                hit = rangeHit(b.tScaled[j], b.det[j], b.tHit[j], q.ray.tmin, best.t);
            else if (b.verdict[j] == LaneVerdict::Scalar)
                hit = intersectTriangle(q.sheared, *tri[j], q.ray.tmin, best.t, t);
            if (hit) keepNearer(best, t, id[j]);
            if (kAnyHit && best.prim >= 0) return LeafOutcome::Found;
        }
        if (valid < n) return LeafOutcome::Fault;
    }
    return LeafOutcome::Done;
}
#endif

// Tests entries [offset, offset + count) of `list` (ids into `prims`) and keeps the nearest in
// `best` (considerPrimitive's tie rule). kAnyHit: stop at the first hit.
template <bool kAnyHit, class Obs>
OCT_HD inline LeafOutcome testLeafList(const ArraySpan<uint32_t>& list, uint32_t offset,
                                       uint32_t count, const PrimitivesView& prims,
                                       const PreparedRay& q, Hit& best, TraceCost& cost, Obs& obs) {
#if defined(OCT_TRIANGLE_BATCH)
    if constexpr (std::is_same<Obs, NoObserver>::value) {
        if (prims.kind == PrimKind::Triangles)
            return testTriangleListBatched<kAnyHit>(list, offset, count, prims, q, best, cost);
    }
#endif
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
