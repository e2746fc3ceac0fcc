#include "core/octree/hash_layout.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <new>
#include <string>

#include "core/system/resources.h"

namespace oct {
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

// What the hash layout's view points into: its slots, and the canonical tree whose leaf index
// list it shares.
struct HashArrays {
    std::shared_ptr<const Octree> tree;
    HashOctree hash;
};

}  // namespace

HashOctree buildHash(const Octree& tree, const HashParams& params) {
    if (params.bucketSlots == 0)
        throw OctreeError("--hash-slots 0: each bucket needs at least one slot");
    const uint32_t B = params.bucketSlots;
    const uint64_t slotBytes = uint64_t(B) * sizeof(OctreeNode);
    auto overBudget = [&](uint64_t m, bool grown) {
        std::string head = "hash octree of " + std::to_string(tree.nodes.size()) + " nodes: ";
        std::string need = "m = " + std::to_string(m) + " buckets of B = " + std::to_string(B) +
                           " slots, " + mibText(m * slotBytes);
        return OctreeError(
            head +
            (grown ? "a bucket still overflows at every m within the budget of " +
                         mibText(params.budgetBytes) + "; the next try is " + need
                   : "needs " + need + ", over the budget of " + mibText(params.budgetBytes)) +
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
            if (m * B > kMaxNodeRecords)
                throw OctreeError("hash octree of " + std::to_string(n) + " nodes: m = " +
                                  std::to_string(m) + " buckets of B = " + std::to_string(B) +
                                  " slots, more than the 2^32 slots its traversal indexes: "
                                  "lower --max-depth or raise --max-prims");
            if (fits(tree, m, B, fill)) break;
            m = nextPrime(m + std::max<uint64_t>(1, m / 4));
            ++h.growSteps;
        }
        h.bucketCount = m;
        checkMemory<OctreeError>(m * slotBytes, "the hash octree (m = " + std::to_string(m) + ")",
                                 "lower --max-depth, raise --max-prims, or raise --hash-slots");
        h.slots.assign(m * B, OctreeNode{});  // key 0 marks an unused slot
    } catch (const std::bad_alloc&) {
        throw OctreeError("hash octree: out of memory allocating m = " + std::to_string(m) +
                          " buckets (" + mibText(m * slotBytes) +
                          "): lower --max-depth, raise --max-prims, or raise --hash-slots");
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

void HashLayout::limitBuild(BuildParams& build, const LayoutOptions& o) {
    const uint64_t B = o.hash.bucketSlots;
    if (B == 0) return;  // buildHash refuses it by name before building anything
    const uint64_t nodes =
        std::min(saturatingMul(B, o.hash.budgetBytes / (B * sizeof(OctreeNode))), kMaxNodeRecords);
    limitNodes(build, nodes,
               "the hash layout holds at most " + std::to_string(nodes) +
                   " nodes (at least nodes / B buckets of B = " + std::to_string(B) +
                   " slots) within the budget of " + mibText(o.hash.budgetBytes) +
                   " and its 2^32 slots: lower --max-depth, raise --max-prims, or raise "
                   "--hash-budget");
}

HashOctreeView hashView(const HashOctree& hash, const Octree& tree, PrimitivesView prims) {
    return {spanOf(hash.slots), hash.bucketCount, hash.bucketSlots, spanOf(tree.primIndices),
            prims};
}

LayoutStorage HashLayout::convert(const Scene& scene, const std::shared_ptr<const Octree>& tree,
                                  const LayoutOptions& o) {
    auto arrays = std::make_shared<HashArrays>();
    arrays->tree = tree;
    arrays->hash = buildHash(*tree, o.hash);
    // The view first: it points into *arrays, which the storage then takes over.
    const auto view = hashView(arrays->hash, *tree, primitivesView(scene));
    return makeLayoutStorage(view, std::move(arrays));
}

LayoutReport HashLayout::report(const Scene&, const Octree& tree, const LayoutOptions& o) {
    auto start = std::chrono::steady_clock::now();
    const HashOctree h = buildHash(tree, o.hash);
    LayoutReport r;
    r.convertSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const uint64_t slotBytes = h.slots.size() * sizeof(OctreeNode);
    r.bytes = slotBytes + tree.primIndices.size() * sizeof(uint32_t);
    r.facts = {countFact("buckets_m", h.bucketCount),
               countFact("slots_per_bucket_B", h.bucketSlots),
               countFact("max_bucket_occupancy", h.maxOccupancy),
               realFact("mean_bucket_occupancy", h.meanOccupancy),
               countFact("grow_steps", h.growSteps),
               countFact("node_bytes", slotBytes),
               countFact("bytes", r.bytes),
               realFact("build_seconds", r.convertSeconds)};
    char line[160];
    std::snprintf(line, sizeof line,
                  "m %llu, B %u, max occupancy %u, mean %.2f, %.2f MiB, built in %.3f s",
                  (unsigned long long)h.bucketCount, h.bucketSlots, h.maxOccupancy, h.meanOccupancy,
                  double(r.bytes) / 1048576.0, r.convertSeconds);
    r.summary = line;
    return r;
}

}  // namespace oct
