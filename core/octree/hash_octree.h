// Hash octree (paper, layout 2), the kernel's view: the nodes that exist, keyed by Morton code
// (root 1, a child appends 3 bits), h(k) = k mod m, collisions kept in a fixed-size list of B
// slots per bucket instead of rehashing. Device code only; building it is hash_layout.h.
#pragma once

#include <cstdint>
#include <type_traits>

#include "core/octree/array_span.h"
#include "core/octree/morton.h"
#include "core/octree/traversal.h"

namespace oct {

// Bucket b occupies slots[b*B, b*B + B) and an unused slot has key 0 (no valid key is 0).
// 72 bytes.
struct HashOctreeView {
    static constexpr bool kNodeRecords = true;  // traversed by traverseOctree (traversal.h)
    ArraySpan<OctreeNode> slots;                // 16 bytes: m * B records
    uint64_t bucketCount;                       // 8 bytes: m
    uint32_t bucketSlots;                       // 4 bytes: B (+4 padding)
    ArraySpan<uint32_t> primIndices;            // 16 bytes: the global leaf index array
    PrimitivesView prims;                       // 24 bytes

    // The arrays, each once (layout.h): host view, CUDA upload and byte count derive from it.
    template <class V, class F>
    static void forEachArray(V& v, F&& f) {
        f("the hash octree's slots", v.slots);
        f("the leaf index list", v.primIndices);
    }

    template <class Obs>
    OCT_HD const OctreeNode* find(uint64_t key, Obs& obs) const {
        const uint64_t b = key % bucketCount;
        const OctreeNode* bucket = slots.data + b * bucketSlots;
        for (uint32_t s = 0; s < bucketSlots; ++s) {
            const uint64_t k = loadReadOnly(&bucket[s].key);
            obs.hashProbe(key, b, s, k);
            if (k == key) return bucket + s;
            if (k == 0) return nullptr;  // slots fill front to back
        }
        return nullptr;
    }
    OCT_HD const OctreeNode* find(uint64_t key) const {
        NoObserver none;
        return find(key, none);
    }
    // The array the traversal's record indices count in (at most kMaxNodeRecords).
    OCT_HD const OctreeNode* records() const { return slots.data; }
    OCT_HD const OctreeNode* root() const {
        NoObserver none;
        return root(none);
    }
    template <class Obs>
    OCT_HD const OctreeNode* root(Obs& obs) const {
        return find(kRootKey, obs);
    }
    // The child of the internal node with Morton key `key` (its address is not needed here).
    template <class Obs>
    OCT_HD const OctreeNode* child(const OctreeNode* /*at*/, uint64_t key, int octant,
                                   Obs& obs) const {
        return find(childKey(key, octant), obs);
    }
};
// The layout above is for 64-bit pointers (hosts, CUDA); the explain page's WebAssembly kernel
// (32-bit pointers) has smaller spans.
static_assert(sizeof(void*) != 8 || sizeof(HashOctreeView) == 72,
              "HashOctreeView byte layout is documented above");
static_assert(std::is_trivially_copyable<HashOctreeView>::value, "views are passed by value");

}  // namespace oct
