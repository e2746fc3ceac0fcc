// Host owners of the three layouts, each converted from the canonical octree. They hold the
// node arrays; views (views.h) are made from them with the scene's primitives, on the host
// here or with device pointers in gpu/.
#pragma once

#include <cstdint>
#include <vector>

#include "core/octree/octree.h"
#include "core/octree/views.h"

namespace oct {

PrimitivesView primitivesView(const Scene& scene);

// --- linear ---------------------------------------------------------------------------------
struct LinearOctree {
    std::vector<OctreeNode> nodes;  // (8^(depth+1) - 1) / 7 records
};

// Nodes of a complete octree of the given depth, (8^(d+1) - 1) / 7, and its bytes. Both
// saturate at UINT64_MAX rather than overflow (depth 21 has 1.2e19 nodes).
uint64_t linearNodeCount(int depth);
uint64_t linearBytes(int depth);

// Default memory budget for the linear layout: 4 GiB.
constexpr uint64_t kDefaultLinearBudget = 4ull << 30;

// Throws OctreeError naming the bytes needed when they exceed budgetBytes; nothing is
// allocated before that check.
LinearOctree buildLinear(const Octree& tree, uint64_t budgetBytes = kDefaultLinearBudget);
LinearOctreeView linearView(const LinearOctree& lin, const Octree& tree, PrimitivesView prims);

// --- hash -----------------------------------------------------------------------------------
// Default memory budget for the hash layout's m * B slots: 4 GiB.
constexpr uint64_t kDefaultHashBudget = 4ull << 30;

struct HashParams {
    uint32_t bucketSlots = 4;  // B: the fixed-size list each bucket keeps instead of rehashing
    // m grows until no bucket holds more than B keys; a small B can need m far above the node
    // count (B = 1 is a perfect hash: m ~ n^2 / 2). Past this budget buildHash refuses.
    uint64_t budgetBytes = kDefaultHashBudget;
};

struct HashOctree {
    uint64_t bucketCount = 0;       // m
    uint32_t bucketSlots = 0;       // B
    std::vector<OctreeNode> slots;  // m * B records
    uint32_t maxOccupancy = 0;      // fullest bucket
    double meanOccupancy = 0.0;     // over non-empty buckets
    uint32_t growSteps = 0;         // times m was increased to avoid an overflowing bucket
};

// Picks m as the smallest prime >= nodes / B, then grows it (next prime >= m * 1.25) until no
// bucket holds more than B keys. Every node of the canonical tree is stored, empty leaves too.
HashOctree buildHash(const Octree& tree, const HashParams& params = {});
HashOctreeView hashView(const HashOctree& hash, const Octree& tree, PrimitivesView prims);

ExhaustiveView exhaustiveView(PrimitivesView prims);

}  // namespace oct
