#include "core/octree/layouts.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <string>

#include "core/octree/morton.h"

namespace oct {

PrimitivesView primitivesView(const Scene& scene) {
    PrimitivesView v{};
    v.kind = scene.kind;
    v.count = scene.primitiveCount();
    v.tris = scene.kind == PrimKind::Triangles ? scene.triangles.data() : nullptr;
    v.spheres = scene.kind == PrimKind::Spheres ? scene.spheres.data() : nullptr;
    return v;
}

ExhaustiveView exhaustiveView(PrimitivesView prims) { return {prims}; }

// --- linear ---------------------------------------------------------------------------------

uint64_t linearNodeCount(int depth) {
    // (8^(d+1) - 1) / 7 = 1 + 8 + ... + 8^d; past d = 20 it exceeds 64 bits.
    if (depth < 0) return 0;
    if (depth > 20) return std::numeric_limits<uint64_t>::max();
    uint64_t total = 0, levelSize = 1;
    for (int d = 0; d <= depth; ++d, levelSize *= 8) total += levelSize;
    return total;
}

uint64_t linearBytes(int depth) {
    uint64_t n = linearNodeCount(depth);
    if (n > std::numeric_limits<uint64_t>::max() / sizeof(OctreeNode))
        return std::numeric_limits<uint64_t>::max();
    return n * sizeof(OctreeNode);
}

namespace {

std::string mib(uint64_t bytes) {
    if (bytes == std::numeric_limits<uint64_t>::max()) return "more than 2^64 bytes";
    return std::to_string(bytes / (1024 * 1024)) + " MiB (" + std::to_string(bytes) + " bytes)";
}

OctreeNode invalidNode() {
    OctreeNode n{};
    n.type = static_cast<uint8_t>(NodeType::Invalid);
    return n;
}

}  // namespace

LinearOctree buildLinear(const Octree& tree, uint64_t budgetBytes) {
    uint64_t bytes = linearBytes(tree.depth);
    if (bytes > budgetBytes)
        throw OctreeError("the linear octree of depth " + std::to_string(tree.depth) + " needs " +
                          mib(bytes) + ", over the budget of " + mib(budgetBytes) +
                          ": lower --max-depth, raise --max-prims, or raise --linear-budget");
    LinearOctree lin;
    try {
        lin.nodes.assign(linearNodeCount(tree.depth), invalidNode());
    } catch (const std::bad_alloc&) {
        throw OctreeError("cannot allocate the linear octree (" + mib(bytes) +
                          "): lower --max-depth or --linear-budget");
    }
    // The canonical tree is breadth first; each node's linear position follows from its key.
    for (const OctreeNode& n : tree.nodes) lin.nodes[linearIndexOfKey(n.key)] = n;
    return lin;
}

LinearOctreeView linearView(const LinearOctree& lin, const Octree& tree, PrimitivesView prims) {
    return {lin.nodes.data(), lin.nodes.size(), tree.primIndices.data(), prims};
}

// --- hash -----------------------------------------------------------------------------------

namespace {

bool isPrime(uint64_t n) {
    if (n < 2) return false;
    for (uint64_t d = 2; d * d <= n; ++d)
        if (n % d == 0) return false;
    return true;
}

uint64_t nextPrime(uint64_t n) {
    while (!isPrime(n)) ++n;
    return n;
}

// Occupancy of each bucket for a given m; false as soon as one exceeds B.
bool fits(const Octree& tree, uint64_t m, uint32_t B, std::vector<uint32_t>& fill) {
    fill.assign(m, 0);
    for (const OctreeNode& n : tree.nodes)
        if (++fill[n.key % m] > B) return false;
    return true;
}

}  // namespace

HashOctree buildHash(const Octree& tree, const HashParams& params) {
    if (params.bucketSlots == 0)
        throw OctreeError("--hash-slots 0: each bucket needs at least one slot");
    const uint32_t B = params.bucketSlots;
    const uint64_t slotBytes = uint64_t(B) * sizeof(OctreeNode);
    auto overBudget = [&](uint64_t m, bool grown) {
        std::string head = "hash octree of " + std::to_string(tree.nodes.size()) + " nodes: ";
        std::string need = "m = " + std::to_string(m) + " buckets of B = " + std::to_string(B) +
                           " slots, " + mib(m * slotBytes);
        return OctreeError(
            head +
            (grown ? "a bucket still overflows at every m within the budget of " +
                         mib(params.budgetBytes) + "; the next try is " + need
                   : "needs " + need + ", over the budget of " + mib(params.budgetBytes)) +
            ": raise --hash-slots, lower --max-depth, or raise --hash-budget");
    };
    HashOctree h;
    h.bucketSlots = B;
    const uint64_t n = tree.nodes.size();
    // Start at the load factor B (every slot used) and grow m by 1.25 until no bucket of
    // h(k) = k mod m overflows (the paper keeps collisions in the bucket's list, never rehashes
    // into other buckets).
    uint64_t m = nextPrime(std::max<uint64_t>(1, (n + B - 1) / B));
    std::vector<uint32_t> fill;
    try {
        while (true) {
            if (m > params.budgetBytes / slotBytes) throw overBudget(m, h.growSteps > 0);
            if (fits(tree, m, B, fill)) break;
            m = nextPrime(m + std::max<uint64_t>(1, m / 4));
            ++h.growSteps;
        }
        h.bucketCount = m;
        h.slots.assign(m * B, OctreeNode{});  // key 0 marks an unused slot
    } catch (const std::bad_alloc&) {
        throw OctreeError("hash octree: out of memory allocating m = " + std::to_string(m) +
                          " buckets (" + mib(m * slotBytes) +
                          "): lower --hash-budget or --max-depth");
    }
    std::vector<uint32_t> used(m, 0);
    for (const OctreeNode& node : tree.nodes) {
        uint64_t b = node.key % m;
        h.slots[b * B + used[b]++] = node;
    }
    uint64_t nonEmpty = 0;
    for (uint32_t f : fill) {
        h.maxOccupancy = std::max(h.maxOccupancy, f);
        nonEmpty += f > 0;
    }
    h.meanOccupancy = nonEmpty ? double(n) / double(nonEmpty) : 0.0;
    return h;
}

HashOctreeView hashView(const HashOctree& hash, const Octree& tree, PrimitivesView prims) {
    return {hash.slots.data(), hash.bucketCount, hash.bucketSlots, tree.primIndices.data(), prims};
}

}  // namespace oct
