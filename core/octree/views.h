// Plain view structs: what a kernel receives, by value, for each acceleration layout. They hold
// pointers and counts only (host or device memory alike) and are trivially copyable.
#pragma once

#include <cstdint>
#include <type_traits>

#include "core/geometry/primitives.h"
#include "core/octree/morton.h"
#include "core/octree/node.h"
#include "core/scene/scene.h"

namespace oct {

// The scene's primitives: exactly one of tris/spheres is non-null, as kind says.
struct PrimitivesView {
    const Triangle* tris;   // 8 bytes
    const Sphere* spheres;  // 8 bytes
    uint32_t count;         // 4 bytes
    PrimKind kind;          // 1 byte (+3 padding)
};

// Exhaustive tracing, the paper's baseline: every ray against every primitive.
struct ExhaustiveView {
    PrimitivesView prims;
};

// Linear octree (paper, layout 1): the complete array, root at 0, the children of p at
// 8p+1 .. 8p+8. Positions below a leaf hold NodeType::Invalid records.
struct LinearOctreeView {
    const OctreeNode* nodes;
    uint64_t nodeCount;
    const uint32_t* primIndices;
    PrimitivesView prims;

    OCT_HD const OctreeNode* root() const { return nodes; }
    // The child of the internal node stored at `at` (its Morton key is not needed here).
    // Children of an internal node always exist in the complete array (it has depth+1 levels).
    OCT_HD const OctreeNode* child(const OctreeNode* at, uint64_t /*key*/, int octant) const {
        uint64_t p = static_cast<uint64_t>(at - nodes);
        return nodes + (8 * p + 1 + octant);
    }
};

// Hash octree (paper, layout 2): the nodes that exist, keyed by Morton code, h(k) = k mod m;
// bucket b occupies slots[b*B, b*B + B) and an unused slot has key 0 (no valid key is 0).
struct HashOctreeView {
    const OctreeNode* slots;
    uint64_t bucketCount;  // m
    uint32_t bucketSlots;  // B
    const uint32_t* primIndices;
    PrimitivesView prims;

    OCT_HD const OctreeNode* find(uint64_t key) const {
        const OctreeNode* bucket = slots + (key % bucketCount) * bucketSlots;
        for (uint32_t s = 0; s < bucketSlots; ++s) {
            const uint64_t k = loadReadOnly(&bucket[s].key);
            if (k == key) return bucket + s;
            if (k == 0) return nullptr;  // slots fill front to back
        }
        return nullptr;
    }
    OCT_HD const OctreeNode* root() const { return find(kRootKey); }
    // The child of the internal node with Morton key `key` (its address is not needed here).
    OCT_HD const OctreeNode* child(const OctreeNode* /*at*/, uint64_t key, int octant) const {
        return find(childKey(key, octant));
    }
};

static_assert(std::is_trivially_copyable<LinearOctreeView>::value, "views are passed by value");
static_assert(std::is_trivially_copyable<HashOctreeView>::value, "views are passed by value");
static_assert(std::is_trivially_copyable<ExhaustiveView>::value, "views are passed by value");

}  // namespace oct
