// The one list of acceleration layouts. Everything that offers, builds, sizes, traces or tests
// a layout iterates this list; nothing outside core/ names a layout.
//
// Adding a layout: write its header and source (a struct as described in layout.h, its View and
// the closestHit/anyHit overloads for it), add it to `Layouts` below, and add its own tests.
// The CLI's --accel, `octrace info`, bench, validate, the CPU and CUDA launchers and the
// registry-driven tests pick it up from here.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "core/octree/compact_octree.h"
#include "core/octree/exhaustive_layout.h"
#include "core/octree/hash_octree.h"
#include "core/octree/layout.h"
#include "core/octree/linear_octree.h"

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
    LayoutStorage (*convert)(const Scene& scene, const std::shared_ptr<const Octree>& tree,
                             const LayoutOptions& o);
    LayoutReport (*report)(const Scene& scene, const Octree& tree, const LayoutOptions& o);
};

// Every layout, in list order.
const std::vector<LayoutDesc>& layouts();
// The layout called `name`; throws OctreeError naming the value and the choices otherwise.
const LayoutDesc& findLayout(const std::string& name);
// "exhaustive, linear, hash" (for help texts and messages).
std::string layoutNames();

namespace detail {
template <class F, class... L>
void visitLayoutView(LayoutList<L...>, int index, const LayoutArrays& a, PrimitivesView p, F& f) {
    int i = 0;
    const bool found = ((i++ == index && (f(L::view(a, p)), true)) || ...);
    if (!found)
        throw std::logic_error("visitLayoutView: no layout at index " + std::to_string(index));
}
}  // namespace detail

// The one dispatch from the user's choice to a typed view: calls f(view) with the layout's View
// built from `arrays` (host pointers for the CPU, device pointers in the CUDA launcher).
template <class F>
void visitLayoutView(const LayoutDesc& layout, const LayoutArrays& arrays, PrimitivesView prims,
                     F&& f) {
    detail::visitLayoutView(Layouts{}, layout.index, arrays, prims, f);
}

}  // namespace oct
