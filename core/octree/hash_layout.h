// The hash layout on the host: m and the buckets built from the canonical octree within a
// memory budget, and its registry entry (layout.h).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/octree/hash_octree.h"
#include "core/octree/layout.h"
#include "core/octree/node_lookup.h"
#include "core/octree/skip_reasons.h"

namespace oct {

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

struct HashLayout {
    static constexpr const char* kName = "hash";
    static constexpr const char* kSummary =
        "the paper's hash octree: Morton keys, h(k) = k mod m, B slots a bucket";
    static constexpr bool kUsesOctree = true;
    // A key not found is absent; empty leaves are stored and skipped.
    static constexpr uint32_t kSkipReasons = skipReasonBits(
        SkipReason::Missed, SkipReason::BeyondHit, SkipReason::Empty, SkipReason::Absent);
    using View = HashOctreeView;

    static LayoutStorage convert(const Scene& scene, const std::shared_ptr<const Octree>& tree,
                                 const LayoutOptions& o);
    static LayoutReport report(const Scene&, const Octree& tree, const LayoutOptions& o);
    // m is at least nodes / B, so --hash-budget and the 2^32 slots bound the nodes.
    static void limitBuild(BuildParams& build, const LayoutOptions& o);
};

}  // namespace oct
