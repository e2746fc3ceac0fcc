// The exhaustive baseline's registry entry (layout.h): no structure, nothing to convert.
#pragma once

#include <memory>

#include "core/octree/exhaustive.h"
#include "core/octree/layout.h"
#include "core/octree/node_lookup.h"
#include "core/octree/skip_reasons.h"

namespace oct {

inline ExhaustiveView exhaustiveView(PrimitivesView prims) { return {prims}; }

// No tree: nothing to look up (the structural check skips layouts without an octree).
inline NodeLookup lookupNode(const ExhaustiveView&, uint64_t) { return {}; }

struct ExhaustiveLayout {
    static constexpr const char* kName = "exhaustive";
    static constexpr const char* kSummary =
        "every ray against every primitive (the paper's baseline; no structure)";
    static constexpr bool kUsesOctree = false;
    static constexpr uint32_t kSkipReasons = 0;  // no nodes: nothing is ever skipped
    using View = ExhaustiveView;

    static LayoutStorage convert(const Scene& scene, const std::shared_ptr<const Octree>&,
                                 const LayoutOptions&) {
        return makeLayoutStorage(exhaustiveView(primitivesView(scene)), nullptr);
    }
    static LayoutReport report(const Scene&, const Octree& tree, const LayoutOptions&);
};

}  // namespace oct
