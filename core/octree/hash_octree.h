// Hash octree (paper, layout 2): the nodes that exist, keyed by Morton code (root 1, a child
// appends 3 bits), h(k) = k mod m, collisions kept in a fixed-size list of B slots per bucket
// instead of rehashing. Converted from the canonical octree; every node is stored, empty
// leaves too.
#pragma once

#include <cstdint>
#include <type_traits>
#include <vector>

#include "core/octree/layout.h"
#include "core/octree/morton.h"
#include "core/octree/traversal.h"

namespace oct {

// Bucket b occupies slots[b*B, b*B + B) and an unused slot has key 0 (no valid key is 0).
struct HashOctreeView {
    static constexpr bool kNodeRecords = true;  // traversed by traverseOctree (traversal.h)
    const OctreeNode* slots;                    // 8 bytes
    uint64_t bucketCount;                       // 8 bytes: m
    uint32_t bucketSlots;                       // 4 bytes: B (+4 padding)
    const uint32_t* primIndices;                // 8 bytes: the global leaf index array
    uint64_t primIndexCount;                    // 8 bytes: its entries (bounds, traversal.h)
    PrimitivesView prims;                       // 24 bytes

    template <class Obs>
    OCT_HD const OctreeNode* find(uint64_t key, Obs& obs) const {
        const uint64_t b = key % bucketCount;
        const OctreeNode* bucket = slots + b * bucketSlots;
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
static_assert(std::is_trivially_copyable<HashOctreeView>::value, "views are passed by value");

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

// Registry entry. Arrays: 0 the slots, 1 the leaf index list; scalars: 0 m, 1 B.
struct HashLayout {
    static constexpr const char* kName = "hash";
    static constexpr const char* kSummary =
        "the paper's hash octree: Morton keys, h(k) = k mod m, B slots a bucket";
    static constexpr bool kUsesOctree = true;
    using View = HashOctreeView;

    static LayoutStorage convert(const Scene&, const std::shared_ptr<const Octree>& tree,
                                 const LayoutOptions& o);
    static LayoutReport report(const Scene&, const Octree& tree, const LayoutOptions& o);
    static View view(const LayoutArrays& a, PrimitivesView prims) {
        return {a.array<OctreeNode>(0), a.scalars[0],         uint32_t(a.scalars[1]),
                a.array<uint32_t>(1),   a.count<uint32_t>(1), prims};
    }
};

}  // namespace oct
