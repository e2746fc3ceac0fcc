// The scene's primitives as a kernel sees them: plain pointers and a count (host or device
// memory alike), plus the one intersection entry point every acceleration layout calls.
#pragma once

#include <cstdint>

#include "core/geometry/aabb.h"
#include "core/geometry/primitives.h"
#include "core/geometry/ray.h"

namespace oct {

// Exactly one of tris/spheres is non-null, as kind says. 24 bytes.
struct PrimitivesView {
    const Triangle* tris;   // 8 bytes
    const Sphere* spheres;  // 8 bytes
    uint32_t count;         // 4 bytes
    PrimKind kind;          // 1 byte (+3 padding)
};

// A ray with everything the inner loops reuse computed once.
struct PreparedRay {
    Ray ray;
    ShearedRay sheared;
    RaySlabs slabs;
};

OCT_HD inline PreparedRay prepareRay(const Ray& r) {
    return {r, makeShearedRay(r.org, r.dir), makeRaySlabs(r.org, r.dir)};
}

OCT_HD inline bool intersectPrimitive(const PrimitivesView& p, uint32_t i, const PreparedRay& q,
                                      float tmax, float& t) {
    if (p.kind == PrimKind::Triangles)
        return intersectTriangle(q.sheared, loadReadOnly(p.tris + i), q.ray.tmin, tmax, t);
    return intersectSphere(q.ray.org, q.ray.dir, loadReadOnly(p.spheres + i), q.ray.tmin, tmax, t);
}

// Searching up to tmax inclusive: a hit at exactly tmax is accepted, so the search starts at
// (tmax, no primitive) and the first hit at tmax still counts (considerPrimitive).
OCT_HD inline Hit initialHit(const Ray& r) { return {r.tmax, -1}; }
OCT_HD inline Hit finishHit(Hit h) { return h.prim < 0 ? missHit() : h; }

// Primitive i hit at t replaces `best` when nearer, or at the same t with a lower id.
OCT_HD inline void keepNearer(Hit& best, float t, uint32_t i) {
    if (best.prim < 0 || t < best.t || (t == best.t && static_cast<int32_t>(i) < best.prim)) {
        best.t = t;
        best.prim = static_cast<int32_t>(i);
    }
}

// Closest-hit update with the deterministic tie rule (equal t: lower primitive id wins), so
// every layout reports the same primitive as exhaustive tracing for the same t. `obs` sees the
// test (traversal_observer.h; NoObserver compiles to nothing).
template <class Obs>
OCT_HD inline void considerPrimitive(const PrimitivesView& p, uint32_t i, const PreparedRay& q,
                                     Hit& best, TraceCost& cost, Obs& obs) {
    float t = INFINITY;  // written on a hit only; the observer sees it either way
    ++cost.primsTested;
    const bool hit = intersectPrimitive(p, i, q, best.t, t);
    obs.primTested(i, hit, t);
    if (hit) keepNearer(best, t, i);
}

}  // namespace oct
