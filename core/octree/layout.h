// What every acceleration layout provides, so that one list (layout_registry.h) names them all
// and nothing outside core/ switches on a layout. Host code.
//
// A layout is two parts:
//  - its View (the kernel header, device code only: NAME_octree.h, exhaustive.h): a plain,
//    trivially copyable struct of typed arrays (ArraySpan, array_span.h), scalars and the
//    scene's PrimitivesView `prims`, with the closestHit/anyHit overloads the kernel calls and
//    a static forEachArray(view, f) that names each array once: f("what it holds", span).
//    The View *is* the layout's storage with pointers into one memory: the host builds it over
//    its vectors, the CUDA launcher copies it with every span re-pointed to device memory
//    (rebindArrays), and the layout's bytes are the spans' sum (arrayBytes).
//  - its registry entry (the host file, NAME_layout.h): kName, kSummary, kUsesOctree,
//    kSkipReasons (every SkipReason its traversal reports to an observer), `using View`,
//    convert(scene, tree, options) -> LayoutStorage (the View over arrays it owns) and
//    report(scene, tree, options) -> LayoutReport (its size and shape for `octrace info`,
//    allocating no more than convert would), and a host lookupNode(View, key) overload
//    (node_lookup.h) for validate's structural check. Optional: limitBuild(build, options),
//    the deepest level or most nodes it can store (limitDepth / limitNodes, below), when that
//    follows from its options alone, so that the builder refuses a tree it cannot store
//    before building it.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/geometry/primitives_view.h"
#include "core/octree/array_span.h"
#include "core/octree/octree.h"

namespace oct {

// Default memory budgets of the layouts that can grow past any machine: 4 GiB each.
constexpr uint64_t kDefaultLinearBudget = 4ull << 30;
constexpr uint64_t kDefaultHashBudget = 4ull << 30;

struct HashParams {
    uint32_t bucketSlots = 4;  // B: the fixed-size list each bucket keeps instead of rehashing
    // m grows until no bucket holds more than B keys; a small B can need m far above the node
    // count (B = 1 is a perfect hash: m ~ n^2 / 2). Past this budget buildHash refuses.
    uint64_t budgetBytes = kDefaultHashBudget;
};

// Everything a layout's conversion may be told: the canonical build, and each layout's own
// shape and memory limits.
struct LayoutOptions {
    BuildParams build;
    HashParams hash;
    uint64_t linearBudget = kDefaultLinearBudget;
};

// A layout's bound on the tree it can store, tightening a build's (BuildParams::storableDepth,
// storableNodes) where it is the tighter: `why` is the refusal's reason and advice.
inline void limitDepth(BuildParams& b, int depth, std::string why) {
    if (depth >= b.storableDepth) return;
    b.storableDepth = depth;
    b.depthLimit = std::move(why);
}
inline void limitNodes(BuildParams& b, uint64_t nodes, std::string why) {
    if (nodes >= b.storableNodes) return;
    b.storableNodes = nodes;
    b.nodeLimit = std::move(why);
}

// A figure of a layout's shape, for `octrace info` (JSON key and value): a count or bytes
// (exact, 64-bit) or a real number.
struct LayoutFact {
    std::string key;
    bool integer;
    uint64_t count;  // when integer
    double value;    // otherwise
};
inline LayoutFact countFact(std::string key, uint64_t n) { return {std::move(key), true, n, 0.0}; }
inline LayoutFact realFact(std::string key, double v) { return {std::move(key), false, 0, v}; }

// Size and shape of a layout over one canonical octree.
struct LayoutReport {
    uint64_t bytes = 0;  // the layout's own arrays (nodes, slots, leaf index list)
    std::vector<LayoutFact> facts;
    std::string summary;  // one line for `octrace info`
    double convertSeconds = 0.0;
};

// Bytes of a view's arrays, from its forEachArray.
template <class View>
uint64_t arrayBytes(const View& v) {
    uint64_t bytes = 0;
    View::forEachArray(v, [&](const char*, const auto& span) { bytes += span.bytes(); });
    return bytes;
}

// A copy of `v` whose every array is re-pointed by `rebind(what, span)`, which returns the new
// data pointer for that span (the CUDA launcher: a device copy of it), and whose primitives are
// `prims`. Names no layout: the CUDA upload is this call.
template <class View, class F>
View rebindArrays(View v, PrimitivesView prims, F&& rebind) {
    View::forEachArray(v, [&](const char* what, auto& span) { span.data = rebind(what, span); });
    v.prims = prims;
    return v;
}

// A span over a vector's elements (null data when empty).
template <class T>
ArraySpan<T> spanOf(const std::vector<T>& v) {
    return {v.empty() ? nullptr : v.data(), uint64_t(v.size())};
}

// A converted layout on the host, its View type erased so that one value holds any layout:
// `owner` keeps the View and the arrays it points into alive (the layout's own vectors and,
// where it shares them, the canonical octree's leaf index list). Made by makeLayoutStorage;
// read back through the registry (layout_registry.h), which knows each index's View type.
struct LayoutStorage {
    std::shared_ptr<const void> owner;
    const void* view = nullptr;  // the layout's View, inside owner
    uint64_t bytes = 0;          // arrayBytes(view)

    template <class View>
    const View& as() const {
        return *static_cast<const View*>(view);
    }
};

template <class View>
LayoutStorage makeLayoutStorage(const View& view, std::shared_ptr<const void> arrays) {
    struct Held {
        View view;
        std::shared_ptr<const void> arrays;
    };
    auto held = std::make_shared<const Held>(Held{view, std::move(arrays)});
    LayoutStorage s;
    s.view = &held->view;
    s.bytes = arrayBytes(view);
    s.owner = std::move(held);
    return s;
}

// The scene's primitives as kernels see them (host pointers).
PrimitivesView primitivesView(const Scene& scene);

// "12 MiB (12582912 bytes)", or "more than 2^64 bytes" for a saturated figure.
std::string mibText(uint64_t bytes);

}  // namespace oct
