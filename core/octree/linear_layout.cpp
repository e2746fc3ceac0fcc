#include "core/octree/linear_layout.h"

#include <chrono>
#include <cstdio>
#include <limits>
#include <new>
#include <string>

#include "core/octree/morton.h"
#include "core/system/resources.h"

namespace oct {

uint64_t linearNodeCount(int depth) {
    // (8^(d+1) - 1) / 7 = 1 + 8 + ... + 8^d; past d = 20 it exceeds 64 bits.
    if (depth < 0) return 0;
    if (depth > 20) return std::numeric_limits<uint64_t>::max();
    uint64_t total = 0, levelSize = 1;
    for (int d = 0; d <= depth; ++d, levelSize *= 8) total += levelSize;
    return total;
}

uint64_t linearBytes(int depth) {
    return saturatingMul(linearNodeCount(depth), sizeof(OctreeNode));
}

namespace {

OctreeNode invalidNode() {
    OctreeNode n{};
    n.type = static_cast<uint8_t>(NodeType::Invalid);
    return n;
}

// What the linear layout's view points into: its array, and the canonical tree whose leaf
// index list it shares.
struct LinearArrays {
    std::shared_ptr<const Octree> tree;
    LinearOctree lin;
};

}  // namespace

LinearOctree buildLinear(const Octree& tree, uint64_t budgetBytes) {
    uint64_t bytes = linearBytes(tree.depth);
    if (bytes > budgetBytes)
        throw OctreeError("the linear octree of depth " + std::to_string(tree.depth) + " needs " +
                          mibText(bytes) + ", over the budget of " + mibText(budgetBytes) +
                          ": lower --max-depth, raise --max-prims, or raise --linear-budget");
    if (linearNodeCount(tree.depth) > kMaxNodeRecords)
        throw OctreeError("the linear octree of depth " + std::to_string(tree.depth) + " has " +
                          std::to_string(linearNodeCount(tree.depth)) +
                          " records, more than the 2^32 its traversal indexes: lower --max-depth, "
                          "or use the hash or compact layout");
    // Within the budget but perhaps not within the machine (the budget goes to 16 TiB): the
    // array is filled at once, so past the memory left it would be the OOM killer's, not ours.
    checkMemory<OctreeError>(
        bytes, "the linear octree of depth " + std::to_string(tree.depth),
        "lower --max-depth or raise --max-prims (the array's size is set by the depth)");
    LinearOctree lin;
    try {
        lin.nodes.assign(linearNodeCount(tree.depth), invalidNode());
    } catch (const std::bad_alloc&) {
        throw OctreeError("cannot allocate the linear octree (" + mibText(bytes) +
                          "): lower --max-depth or --linear-budget");
    }
    // The canonical tree is breadth first; each node's linear position follows from its key.
    for (const OctreeNode& n : tree.nodes) lin.nodes[linearIndexOfKey(n.key)] = n;
    return lin;
}

LinearOctreeView linearView(const LinearOctree& lin, const Octree& tree, PrimitivesView prims) {
    return {spanOf(lin.nodes), spanOf(tree.primIndices), prims};
}

LayoutStorage LinearLayout::convert(const Scene& scene, const std::shared_ptr<const Octree>& tree,
                                    const LayoutOptions& o) {
    auto arrays = std::make_shared<LinearArrays>();
    arrays->tree = tree;
    arrays->lin = buildLinear(*tree, o.linearBudget);
    // The view first: it points into *arrays, which the storage then takes over.
    const auto view = linearView(arrays->lin, *tree, primitivesView(scene));
    return makeLayoutStorage(view, std::move(arrays));
}

void LinearLayout::limitBuild(BuildParams& build, const LayoutOptions& o) {
    auto fits = [&](int d) {
        return linearBytes(d) <= o.linearBudget && linearNodeCount(d) <= kMaxNodeRecords;
    };
    int deepest = 0;
    while (deepest < kMaxOctreeDepth && fits(deepest + 1)) ++deepest;
    const int past = deepest + 1;
    if (past > kMaxOctreeDepth) return;
    limitDepth(build, deepest,
               linearBytes(past) > o.linearBudget
                   ? "the linear layout's array of depth " + std::to_string(past) + " would need " +
                         mibText(linearBytes(past)) + ", over the budget of " +
                         mibText(o.linearBudget) +
                         ": lower --max-depth, raise --max-prims, or raise --linear-budget"
                   : "the linear layout's array of depth " + std::to_string(past) +
                         " would have more than the 2^32 records its traversal indexes: lower "
                         "--max-depth, raise --max-prims, or use the hash or compact layout");
}

LayoutReport LinearLayout::report(const Scene&, const Octree& tree, const LayoutOptions&) {
    const uint64_t indexBytes = tree.primIndices.size() * sizeof(uint32_t);
    LayoutReport r;
    r.bytes = saturatingAdd(linearBytes(tree.depth), indexBytes);
    r.facts = {countFact("nodes", linearNodeCount(tree.depth)),
               countFact("node_bytes", linearBytes(tree.depth)), countFact("bytes", r.bytes)};
    char line[128];
    std::snprintf(line, sizeof line, "%llu nodes, %.2f MiB (incl. leaf index array)",
                  (unsigned long long)linearNodeCount(tree.depth), double(r.bytes) / 1048576.0);
    r.summary = line;
    return r;
}

}  // namespace oct
