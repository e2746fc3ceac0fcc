#include "validation/exact/layout_structure.h"

#include <algorithm>
#include <cstring>

namespace oct {

StructureReport checkLayoutStructure(const Octree& tree, const NodeLookupFn& lookup) {
    StructureReport rep;
    auto fail = [&rep, &tree](uint64_t& counter, uint32_t k, const char* why) {
        ++counter;
        if (rep.errors.size() < 16)
            rep.errors.push_back("node " + std::to_string(k) + " (key " +
                                 std::to_string(tree.nodes[k].key) + ", depth " +
                                 std::to_string(tree.nodes[k].depth) + "): " + why);
    };
    for (uint32_t k = 0; k < tree.nodes.size(); ++k) {
        const OctreeNode& nd = tree.nodes[k];
        const NodeType type = nd.nodeType();
        ++rep.nodes;
        const NodeLookup got = lookup(nd.key);
        if (got.broken) {
            fail(rep.broken, k, "its lookup leaves the layout's arrays");
            continue;
        }
        // An empty leaf holds nothing to hit: a layout may leave it out (compact does).
        const bool empty = type == NodeType::EmptyLeaf || (type == NodeType::Leaf && !nd.primCount);
        if (!got.found) {
            if (!empty) fail(rep.missing, k, "not found");
            continue;
        }
        const bool gotEmpty =
            got.type == NodeType::EmptyLeaf || (got.type == NodeType::Leaf && got.count == 0);
        if (empty ? !gotEmpty : got.type != type) {
            fail(rep.wrongType, k, "found as another kind of node");
            continue;
        }
        if (std::memcmp(&got.box, &nd.box, sizeof(Aabb)) != 0) {
            fail(rep.wrongBox, k, "found with another box");
            continue;
        }
        if (type != NodeType::Leaf || empty) continue;
        if (uint64_t(nd.primOffset) + nd.primCount > tree.primIndices.size())
            continue;  // the canonical list itself is broken: the replication check names it
        std::vector<uint32_t> want(tree.primIndices.begin() + nd.primOffset,
                                   tree.primIndices.begin() + nd.primOffset + nd.primCount);
        std::vector<uint32_t> have(got.list, got.list + got.count);
        std::sort(want.begin(), want.end());
        std::sort(have.begin(), have.end());
        if (want != have) fail(rep.wrongList, k, "found with another leaf list");
    }
    return rep;
}

}  // namespace oct
