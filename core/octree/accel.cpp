#include "core/octree/accel.h"

#include <chrono>

namespace oct {

const char* layoutName(Layout l) {
    switch (l) {
        case Layout::Linear:
            return "linear";
        case Layout::Hash:
            return "hash";
        case Layout::Exhaustive:
        default:
            return "exhaustive";
    }
}

Layout parseLayout(const std::string& name) {
    if (name == "exhaustive") return Layout::Exhaustive;
    if (name == "linear") return Layout::Linear;
    if (name == "hash") return Layout::Hash;
    throw OctreeError("unknown --accel '" + name + "': use exhaustive, linear or hash");
}

uint64_t BuiltScene::layoutBytes() const {
    switch (layout) {
        case Layout::Linear:
            return linear.nodes.size() * sizeof(OctreeNode) +
                   tree.primIndices.size() * sizeof(uint32_t);
        case Layout::Hash:
            return hash.slots.size() * sizeof(OctreeNode) +
                   tree.primIndices.size() * sizeof(uint32_t);
        case Layout::Exhaustive:
        default:
            return 0;
    }
}

BuiltScene buildScene(const Scene& scene, Layout layout, const LayoutOptions& opt) {
    auto start = std::chrono::steady_clock::now();
    BuiltScene b;
    b.scene = &scene;
    b.layout = layout;
    if (layout != Layout::Exhaustive) {
        b.tree = buildOctree(scene, opt.build);
        if (layout == Layout::Linear) b.linear = buildLinear(b.tree, opt.linearBudget);
        if (layout == Layout::Hash) b.hash = buildHash(b.tree, opt.hash);
    }
    b.buildSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return b;
}

}  // namespace oct
