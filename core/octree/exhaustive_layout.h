// Exhaustive tracing, the paper's baseline: every ray against every primitive, no structure.
#pragma once

#include <cstdio>
#include <type_traits>

#include "core/geometry/primitives_view.h"
#include "core/octree/layout.h"
#include "core/octree/node_lookup.h"
#include "core/octree/traversal_observer.h"

namespace oct {

struct ExhaustiveView {
    PrimitivesView prims;
};
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
        float t;
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

inline ExhaustiveView exhaustiveView(PrimitivesView prims) { return {prims}; }

// No tree: nothing to look up (the structural check skips layouts without an octree).
inline NodeLookup lookupNode(const ExhaustiveView&, uint64_t) { return {}; }

struct ExhaustiveLayout {
    static constexpr const char* kName = "exhaustive";
    static constexpr const char* kSummary =
        "every ray against every primitive (the paper's baseline; no structure)";
    static constexpr bool kUsesOctree = false;
    using View = ExhaustiveView;

    static LayoutStorage convert(const Scene&, const std::shared_ptr<const Octree>&,
                                 const LayoutOptions&) {
        return {};
    }
    static LayoutReport report(const Scene&, const Octree& tree, const LayoutOptions&) {
        const uint64_t primBytes =
            uint64_t(tree.primitiveCount) *
            (tree.kind == PrimKind::Triangles ? sizeof(Triangle) : sizeof(Sphere));
        LayoutReport r;
        r.facts = {countFact("primitive_bytes", primBytes)};
        char line[96];
        std::snprintf(line, sizeof line, "%.2f MiB of primitives, no tree",
                      double(primBytes) / 1048576.0);
        r.summary = line;
        return r;
    }
    static View view(const LayoutArrays&, PrimitivesView prims) { return {prims}; }
};

}  // namespace oct
