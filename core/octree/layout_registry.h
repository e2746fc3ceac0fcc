// The one list of acceleration layouts. Everything that offers, builds, sizes, traces or tests
// a layout iterates this list; nothing outside core/ names a layout.
//
// Adding a layout: write its kernel header (its View) and its host entry (layout.h describes
// both), add the entry to `Layouts` below, and add its own tests. The CLI's --accel, `octrace
// info`, bench, validate, explain, the CPU and CUDA launchers and the registry-driven tests
// pick it up from here.
#pragma once

#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "core/octree/compact_layout.h"
#include "core/octree/exhaustive_layout.h"
#include "core/octree/hash_layout.h"
#include "core/octree/layout.h"
#include "core/octree/linear_layout.h"

namespace oct {

template <class... L>
struct LayoutList {};

// The list. Order is the order of help texts, `info` and `--accel all`.
using Layouts = LayoutList<ExhaustiveLayout, LinearLayout, HashLayout, CompactLayout>;

// A layout as the host sees it at run time: its registry entry without the types.
struct LayoutDesc {
    int index;  // position in Layouts
    const char* name;
    const char* summary;
    bool usesOctree;
    uint32_t skipReasons;  // skipReasonBits of the reasons its traversal reports (skip_reasons.h)
    LayoutStorage (*convert)(const Scene& scene, const std::shared_ptr<const Octree>& tree,
                             const LayoutOptions& o);
    LayoutReport (*report)(const Scene& scene, const Octree& tree, const LayoutOptions& o);
    // The node with Morton key `key` in a converted layout, found as its traversal finds it.
    NodeLookup (*lookup)(const LayoutStorage& storage, uint64_t key);
    // Tightens `build` to what the layout can store under `o` (its static limitBuild, where it
    // has one): the builder then refuses the first level past it before making it.
    void (*limitBuild)(BuildParams& build, const LayoutOptions& o);
};

// What commands trace when --accel is not given: the paper's two layouts (validate checks both;
// render, trace and explain draw the first).
constexpr const char* kDefaultLayouts = "linear,hash";
constexpr const char* kDefaultLayout = "linear";

// Every layout, in list order.
const std::vector<LayoutDesc>& layouts();
// The layout called `name`; throws OctreeError naming the value and the choices otherwise.
const LayoutDesc& findLayout(const std::string& name);
// "exhaustive, linear, hash, compact" (for help texts and messages).
std::string layoutNames();

template <class L>
struct LayoutTag {
    using Layout = L;
    using View = typename L::View;
};

namespace detail {
template <class F, class... L>
void visitLayoutType(LayoutList<L...>, int index, F& f) {
    int i = 0;
    const bool found = ((i++ == index && (f(LayoutTag<L>{}), true)) || ...);
    if (!found)
        throw std::logic_error("visitLayoutType: no layout at index " + std::to_string(index));
}
}  // namespace detail

// The one dispatch from the user's choice to the layout's types: calls f(LayoutTag<L>{}) for
// the registry entry L of `layout`.
template <class F>
void visitLayoutType(const LayoutDesc& layout, F&& f) {
    detail::visitLayoutType(Layouts{}, layout.index, f);
}

// Calls f(view) with the typed View held by `storage`, a conversion of `layout` (host pointers
// for the CPU, device pointers in the CUDA launcher).
template <class F>
void visitLayoutView(const LayoutDesc& layout, const LayoutStorage& storage, F&& f) {
    visitLayoutType(layout, [&](auto tag) {
        using View = typename decltype(tag)::View;
        f(storage.as<View>());
    });
}

}  // namespace oct
