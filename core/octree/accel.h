// The user's choice of acceleration layout, built once on the host, and the one switch that
// turns it into a typed view for the templated kernels (DESIGN.md: dispatch happens once).
#pragma once

#include <string>

#include "core/octree/layouts.h"

namespace oct {

enum class Layout { Exhaustive, Linear, Hash };

const char* layoutName(Layout l);
// Accepts "exhaustive", "linear", "hash"; throws OctreeError naming the value otherwise.
Layout parseLayout(const std::string& name);

struct LayoutOptions {
    BuildParams build;
    HashParams hash;
    uint64_t linearBudget = kDefaultLinearBudget;
};

// A scene with its acceleration structure, ready to trace. The Scene must outlive it.
struct BuiltScene {
    const Scene* scene = nullptr;
    Layout layout = Layout::Exhaustive;
    Octree tree;                // empty for Exhaustive
    LinearOctree linear;        // filled for Linear
    HashOctree hash;            // filled for Hash
    double buildSeconds = 0.0;  // octree build plus layout conversion

    PrimitivesView prims() const { return primitivesView(*scene); }
    // Bytes of the layout's own arrays: nodes (or hash slots) plus the leaf index array.
    uint64_t layoutBytes() const;
};

BuiltScene buildScene(const Scene& scene, Layout layout, const LayoutOptions& opt);

// Calls f with the layout's view (ExhaustiveView, LinearOctreeView or HashOctreeView).
template <class F>
decltype(auto) visitView(const BuiltScene& b, F&& f) {
    switch (b.layout) {
        case Layout::Linear:
            return f(linearView(b.linear, b.tree, b.prims()));
        case Layout::Hash:
            return f(hashView(b.hash, b.tree, b.prims()));
        case Layout::Exhaustive:
        default:
            return f(exhaustiveView(b.prims()));
    }
}

}  // namespace oct
