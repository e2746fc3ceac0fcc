#include "core/octree/built_scene.h"

#include <chrono>

#include "core/time_spread.h"

namespace oct {

std::shared_ptr<const Octree> buildSharedOctree(const Scene& scene, const BuildParams& params) {
    return std::make_shared<const Octree>(buildOctree(scene, params));
}

BuiltScene convertLayout(const Scene& scene, std::shared_ptr<const Octree> tree,
                         const LayoutDesc& layout, const LayoutOptions& options) {
    BuiltScene b;
    b.scene = &scene;
    b.layout = &layout;
    if (layout.usesOctree && !tree)
        throw OctreeError(std::string("the ") + layout.name +
                          " layout is converted from an octree, and none was built");
    auto t0 = std::chrono::steady_clock::now();
    b.storage = layout.convert(scene, tree, options);
    b.convertSeconds = secondsSince(t0);
    if (layout.usesOctree) b.tree = std::move(tree);
    return b;
}

BuiltScene bareScene(const Scene& scene) {
    for (const LayoutDesc& d : layouts())
        if (!d.usesOctree) return convertLayout(scene, nullptr, d, LayoutOptions{});
    throw OctreeError("the layout list has no layout that traces without an octree");
}

BuiltScene buildScene(const Scene& scene, const LayoutDesc& layout, const LayoutOptions& options) {
    std::shared_ptr<const Octree> tree;
    auto t0 = std::chrono::steady_clock::now();
    BuildParams build = options.build;
    layout.limitBuild(build, options);
    if (layout.usesOctree) tree = buildSharedOctree(scene, build);
    const double treeSeconds = secondsSince(t0);
    BuiltScene b = convertLayout(scene, std::move(tree), layout, options);
    b.treeSeconds = treeSeconds;
    return b;
}

}  // namespace oct
