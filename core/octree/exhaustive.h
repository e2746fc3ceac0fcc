// Exhaustive tracing, the paper's baseline, the kernel's view: every ray against every
// primitive, no structure. Device code only; its registry entry is exhaustive_layout.h.
#pragma once

#include <type_traits>

#include "core/geometry/primitives_view.h"
#include "core/octree/traversal_observer.h"

namespace oct {

// 24 bytes.
struct ExhaustiveView {
    PrimitivesView prims;  // 24 bytes

    // No arrays of its own (layout.h).
    template <class V, class F>
    static void forEachArray(V&, F&&) {}
};
// The layout above is for 64-bit pointers (hosts, CUDA); the explain page's WebAssembly kernel
// (32-bit pointers) has smaller spans.
static_assert(sizeof(void*) != 8 || sizeof(ExhaustiveView) == 24,
              "ExhaustiveView byte layout is documented above");
static_assert(std::is_trivially_copyable<ExhaustiveView>::value, "views are passed by value");

template <class Obs>
OCT_HD inline Hit closestHit(const ExhaustiveView& v, const Ray& r, TraceCost& cost, Obs& obs) {
    PreparedRay q = prepareRay(r);
    Hit best = initialHit(r);
    for (uint32_t i = 0; i < v.prims.count; ++i) considerPrimitive(v.prims, i, q, best, cost, obs);
    return finishHit(best);
}

template <class Obs>
OCT_HD inline bool anyHit(const ExhaustiveView& v, const Ray& r, TraceCost& cost, Obs& obs) {
    PreparedRay q = prepareRay(r);
    for (uint32_t i = 0; i < v.prims.count; ++i) {
        float t = INFINITY;  // written on a hit only; the observer is handed it either way
        ++cost.primsTested;
        const bool hit = intersectPrimitive(v.prims, i, q, r.tmax, t);
        obs.primTested(i, hit, t);
        if (hit) return true;
    }
    return false;
}

OCT_HD inline Hit closestHit(const ExhaustiveView& v, const Ray& r, TraceCost& cost) {
    NoObserver none;
    return closestHit(v, r, cost, none);
}
OCT_HD inline bool anyHit(const ExhaustiveView& v, const Ray& r, TraceCost& cost) {
    NoObserver none;
    return anyHit(v, r, cost, none);
}

}  // namespace oct
