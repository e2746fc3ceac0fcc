// A scene with its acceleration structure, ready to trace: the canonical octree (built once,
// shareable between layouts) and one layout converted from it. Host-only; the kernels receive
// the layout's View (visit()).
#pragma once

#include <memory>

#include "core/octree/layout_registry.h"

namespace oct {

// The Scene must outlive it.
struct BuiltScene {
    const Scene* scene = nullptr;
    const LayoutDesc* layout = nullptr;
    std::shared_ptr<const Octree> tree;  // canonical octree; null for layouts that need none
    LayoutStorage storage;               // the layout's arrays (host memory)
    double treeSeconds = 0.0;            // building the canonical octree (0 when shared)
    double convertSeconds = 0.0;         // converting it to this layout

    double buildSeconds() const { return treeSeconds + convertSeconds; }
    PrimitivesView prims() const { return primitivesView(*scene); }
    // Bytes of the layout's own arrays: nodes (or hash slots) plus the leaf index array.
    uint64_t layoutBytes() const { return storage.bytes; }
    // Calls f with the layout's typed View over host memory.
    template <class F>
    void visit(F&& f) const {
        visitLayoutView(*layout, storage, f);
    }
    // The node with Morton key `key` as the layout's traversal finds it (validate's structural
    // check); not found for a layout without an octree.
    NodeLookup lookupNode(uint64_t key) const { return layout->lookup(storage, key); }
};

// The canonical octree, shareable between layouts.
std::shared_ptr<const Octree> buildSharedOctree(const Scene& scene, const BuildParams& params);

// Converts an existing canonical octree (null for a layout that needs none) to `layout`; the
// row's treeSeconds stays 0. Throws OctreeError when the layout's budget is exceeded.
BuiltScene convertLayout(const Scene& scene, std::shared_ptr<const Octree> tree,
                         const LayoutDesc& layout, const LayoutOptions& options);

// The scene with no structure of ours (the registry's first layout that needs no octree, the
// exhaustive one): what a backend tracing with its own structure (Embree) is given.
BuiltScene bareScene(const Scene& scene);

// Builds the canonical octree when the layout needs one, then converts it.
BuiltScene buildScene(const Scene& scene, const LayoutDesc& layout, const LayoutOptions& options);

}  // namespace oct
