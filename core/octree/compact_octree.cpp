#include "core/octree/compact_octree.h"

#include <chrono>
#include <cstdio>
#include <string>

namespace oct {
namespace {

// The compact layout's storage: its records, and the canonical tree whose leaf index list it
// shares.
struct CompactStorage {
    std::shared_ptr<const Octree> tree;
    CompactOctree compact;
};

bool stored(const OctreeNode& n) {
    return n.nodeType() == NodeType::Internal ||
           (n.nodeType() == NodeType::Leaf && n.primCount > 0);
}

}  // namespace

CompactOctree buildCompact(const Octree& tree) {
    CompactOctree c;
    c.rootBox = tree.root;
    if (tree.nodes.empty() || !stored(tree.nodes[0])) return c;  // nothing to hit
    c.rootIsLeaf = tree.nodes[0].nodeType() == NodeType::Leaf;
    // Breadth first: a queue of canonical node indices in the order their records are placed;
    // an internal node's stored children are appended together, so they are adjacent.
    std::vector<uint32_t> order = {0};
    c.nodes.reserve(tree.nodes.size());
    for (size_t at = 0; at < order.size(); ++at) {
        const OctreeNode& n = tree.nodes[order[at]];
        CompactNode rec{};
        if (n.nodeType() == NodeType::Leaf) {
            rec.a = n.primOffset;
            rec.b = n.primCount;
        } else {
            const uint32_t first = tree.firstChild[order[at]];
            uint32_t mask = 0, leaves = 0;
            rec.a = uint32_t(order.size());
            for (int i = 0; i < 8; ++i) {
                const OctreeNode& ch = tree.nodes[first + i];
                if (!stored(ch)) continue;
                mask |= 1u << i;
                if (ch.nodeType() == NodeType::Leaf) leaves |= 1u << i;
                order.push_back(first + i);
            }
            rec.b = mask | leaves << 8;
        }
        c.nodes.push_back(rec);
    }
    return c;
}

CompactOctreeView compactView(const CompactOctree& c, const Octree& tree, PrimitivesView prims) {
    CompactOctreeView v;
    v.nodes = c.nodes.data();
    v.primIndices = tree.primIndices.data();
    v.prims = prims;
    v.rootBox = c.rootBox;
    v.rootIsLeaf = c.rootIsLeaf;
    v.nodeCount = uint32_t(c.nodes.size());
    return v;
}

LayoutStorage CompactLayout::convert(const std::shared_ptr<const Octree>& tree,
                                     const LayoutOptions&) {
    if (tree->nodes.size() > 0xffffffffull)
        throw OctreeError("the compact layout addresses at most 2^32 nodes; this octree has " +
                          std::to_string(tree->nodes.size()) + ": lower --max-depth");
    auto owner = std::make_shared<CompactStorage>();
    owner->tree = tree;
    owner->compact = buildCompact(*tree);
    const CompactOctree& c = owner->compact;
    LayoutStorage s;
    s.arrays.arrays[0] = layoutArray(c.nodes);
    s.arrays.arrays[1] = layoutArray(tree->primIndices);
    const float box[6] = {c.rootBox.lo.x, c.rootBox.lo.y, c.rootBox.lo.z,
                          c.rootBox.hi.x, c.rootBox.hi.y, c.rootBox.hi.z};
    std::memcpy(s.arrays.scalars, box, sizeof box);
    s.arrays.scalars[3] = c.rootIsLeaf ? 1 : 0;
    s.bytes = s.arrays.arrays[0].bytes + s.arrays.arrays[1].bytes;
    s.owner = std::move(owner);
    return s;
}

LayoutReport CompactLayout::report(const Octree& tree, const LayoutOptions& o) {
    auto start = std::chrono::steady_clock::now();
    LayoutStorage s = convert(std::shared_ptr<const Octree>(&tree, [](const Octree*) {}), o);
    LayoutReport r;
    r.convertSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const uint64_t records = s.arrays.arrays[0].bytes / sizeof(CompactNode);
    r.bytes = s.bytes;
    r.facts = {countFact("nodes", records), countFact("node_bytes", s.arrays.arrays[0].bytes),
               countFact("bytes_per_node", sizeof(CompactNode)), countFact("bytes", r.bytes),
               realFact("build_seconds", r.convertSeconds)};
    char line[160];
    std::snprintf(line, sizeof line,
                  "%llu nodes of %zu bytes (empty leaves not stored), %.2f MiB, built in %.3f s",
                  (unsigned long long)records, sizeof(CompactNode), double(r.bytes) / 1048576.0,
                  r.convertSeconds);
    r.summary = line;
    return r;
}

}  // namespace oct
