// The paper's traversal (Barboza & Clua 2011, sec. 5), written once as OCT_HD code for every
// layout that stores the paper's node record: test the node's box; internal: visit every
// intersected child; leaf: test its primitives; keep the minimum t. A layout supplies root()
// and child(); linear_octree.h and hash_octree.h differ only there.
//
// Beyond the paper, children are visited nearest-first and a node whose box is entered beyond
// the closest hit found so far is skipped. This returns the same closest hit (only nodes that
// cannot hold a nearer one are skipped) with fewer visits. Ties in t go to the lower primitive
// id (considerPrimitive), so every layout reports the same primitive as exhaustive tracing.
#pragma once

#include <type_traits>

#include "core/geometry/aabb.h"
#include "core/geometry/primitives_view.h"
#include "core/geometry/ray.h"
#include "core/octree/leaf_list.h"
#include "core/octree/morton.h"
#include "core/octree/node.h"
#include "core/octree/octree_limits.h"
#include "core/octree/traversal_observer.h"

namespace oct {

// The traversal's state is one entry a level, not one a pushed child (after Laine & Karras,
// "Efficient Sparse Voxel Octrees", 2010, whose stack holds one parent a level and re-derives
// its siblings): the internal node whose children are still to visit, and the octants of those
// children in the order they will be visited. A child's record is looked up again when its
// turn comes (linear: 8p + 1 + i; hash: its key) and its entry t recomputed from its box, the
// same bits the first test gave; the nearest child is visited straight away, with the entry t
// just computed. kMaxOctreeDepth levels hold every internal node of a tree the builder allows
// (depths 0 .. kMaxOctreeDepth - 1): 8 bytes a level (a 32-bit record index, kMaxNodeRecords,
// and the order word), 168 bytes in all, against 16 bytes a pushed child (7 a level + 8:
// 2,480 bytes) before, which CUDA kept in local memory.
//
// Byte layout of an order word (uint32): the octants still to visit, nearest first, one 4-bit
// nibble each from the lowest: bit 3 set (a nibble is in use), bits 0-2 the octant. 0: no child
// left at this level.
constexpr uint32_t kOrderInUse = 8;

// Index of the lowest set bit of a non-zero mask.
OCT_HD inline int lowestBit(uint32_t m) {
#if defined(__CUDA_ARCH__)
    return __ffs(m) - 1;
#else
    return __builtin_ctz(m);
#endif
}

// The order word of the children in `hitMask` entered at tEnter[i]: nearest first; equal entry
// t, the higher octant first (the order in which a far-to-near sort of the octant-ordered
// children, stable on ties, would pop them from a stack). Two ways to the same word, tested
// equal (tests/core/traversal_test.cpp): CUDA ranks by counting, every index known at
// compile time, so the eight values stay in registers; the host sorts the few hit children by
// insertion, which costs less than 64 comparisons when two to four are hit.
OCT_HD inline uint32_t nearFirstOrderByRank(const float* tEnter, uint32_t hitMask) {
    uint32_t order = 0;
#if defined(__CUDA_ARCH__)
#pragma unroll
#endif
    for (int i = 0; i < 8; ++i) {
        int rank = 0;
#if defined(__CUDA_ARCH__)
#pragma unroll
#endif
        for (int j = 0; j < 8; ++j) {
            const bool before = tEnter[j] < tEnter[i] || (tEnter[j] == tEnter[i] && j > i);
            rank += int(((hitMask >> j) & 1u) != 0 && before);
        }
        if ((hitMask >> i) & 1u) order |= uint32_t(i | kOrderInUse) << (4 * rank);
    }
    return order;
}

OCT_HD inline uint32_t nearFirstOrderBySort(const float* tEnter, uint32_t hitMask) {
    // Hit children in ascending octant order, then sorted nearest first, ties to the higher
    // octant: an insertion moves an entry before those entered later or at the same t.
    float t[8];
    int octant[8];
    int n = 0;
    for (uint32_t m = hitMask & 0xffu; m != 0; m &= m - 1u) {
        const int i = lowestBit(m);
        int j = n++;
        while (j > 0 && t[j - 1] >= tEnter[i]) {
            t[j] = t[j - 1];
            octant[j] = octant[j - 1];
            --j;
        }
        t[j] = tEnter[i];
        octant[j] = i;
    }
    uint32_t order = 0;
    for (int k = n - 1; k >= 0; --k) order = order << 4 | uint32_t(octant[k] | kOrderInUse);
    return order;
}

OCT_HD inline uint32_t nearFirstOrder(const float* tEnter, uint32_t hitMask) {
#if defined(__CUDA_ARCH__)
    return nearFirstOrderByRank(tEnter, hitMask);
#else
    return nearFirstOrderBySort(tEnter, hitMask);
#endif
}

// Depth-first traversal, one state entry a level (above); the builder refuses depths beyond
// kMaxOctreeDepth, which bounds the levels.
// kAnyHit: stop at the first primitive hit in [tmin, tmax] (shadow rays).
// OctView needs: root(obs) -> const OctreeNode* (null: no tree), child(node, key, octant, obs)
// -> const OctreeNode* (null: absent), records() (the array they point into), and the members
// primIndices (ArraySpan) and prims.
// child() must never hand back a node the walk has passed (linear: an index after the parent's
// and inside the array; hash: the node whose key is the child key, and keys only grow), so the
// walk cannot cycle and its work is bounded by the tree; a wrong but in-order node (a faulty
// index) is a wrong answer that validation's hit and structure checks report. Not checking
// each child's key here keeps the paper's linear walk at its cost (docs/PERFORMANCE.md).
// An inconsistent structure returns faultHit() (core/geometry/ray.h). `obs` sees every
// step (traversal_observer.h); the kernels pass NoObserver.
template <bool kAnyHit, class OctView, class Obs>
OCT_HD inline Hit traverseOctree(const OctView& v, const Ray& r, TraceCost& cost, Obs& obs) {
    constexpr bool kSilent = std::is_same<Obs, NoObserver>::value;
    PreparedRay q = prepareRay(r);
    Hit best = initialHit(r);
    uint32_t levelNode[kMaxOctreeDepth];   // the internal node of each level (index)
    uint32_t levelOrder[kMaxOctreeDepth];  // its children left (order word, above)
    int levels = 0;

    const OctreeNode* at = v.root(obs);
    float tEnter, t1;
    ++cost.nodesVisited;
    if (at == nullptr) {
        obs.childSkipped(kRootKey, SkipReason::Absent);
        return missHit();
    }
    const OctreeNode& rn = loadReadOnly(at);
    if (rn.key != kRootKey) return faultHit();
    const bool rootHit = intersectBox(q.slabs, rn.box, r.tmin, r.tmax, tEnter, t1);
    obs.boxTested(kRootKey, 0, rn.box, rootHit, tEnter, t1);
    if (!rootHit) return missHit();

    for (;;) {
        const OctreeNode& n = loadReadOnly(at);
        if (tEnter > best.t) {  // a nearer hit is already known
            obs.nodePopped(n.key, tEnter, false);
            // Its siblings left are entered no nearer (nearest first): without an observer to
            // tell of each, drop them together. (The root is never dropped: tEnter <= tmax.)
            if (kSilent) levelOrder[levels - 1] = 0;
        } else {
            obs.nodePopped(n.key, tEnter, true);
            const NodeType type = n.nodeType();
            if (type == NodeType::Leaf) {
                const LeafOutcome out = testLeafList<kAnyHit>(
                    v.primIndices, n.primOffset, n.primCount, v.prims, q, best, cost, obs);
                if (out == LeafOutcome::Fault) return faultHit();
                if (out == LeafOutcome::Found) return best;
            } else if (type == NodeType::Internal) {
                float childEnter[8] = {0, 0, 0, 0, 0, 0, 0, 0};
                uint32_t hitMask = 0;
                for (int i = 0; i < 8; ++i) {
                    const OctreeNode* c = v.child(at, n.key, i, obs);
                    // Empty leaves and absent nodes hold nothing to hit.
                    if (c == nullptr) {
                        obs.childSkipped(childKey(n.key, i), SkipReason::Absent);
                        continue;
                    }
                    const OctreeNode& cn = loadReadOnly(c);
                    const NodeType ct = cn.nodeType();
                    if (ct != NodeType::Leaf && ct != NodeType::Internal) {
                        obs.childSkipped(childKey(n.key, i), ct == NodeType::EmptyLeaf
                                                                 ? SkipReason::Empty
                                                                 : SkipReason::Absent);
                        continue;
                    }
                    ++cost.nodesVisited;
                    float c0, c1;
                    const bool hit = intersectBox(q.slabs, cn.box, r.tmin, best.t, c0, c1);
                    obs.boxTested(childKey(n.key, i), cn.depth, cn.box, hit, c0, c1);
                    if (hit) {
                        childEnter[i] = c0;
                        hitMask |= 1u << i;
                    }
                }
                if (hitMask != 0) {
                    // One level a node on the path (bounding the depth, so the walk ends even
                    // on a broken tree); the nearest child is visited at once, with the
                    // pointer and entry t just found, and the rest wait at this level.
                    if (levels == kMaxOctreeDepth) return faultHit();  // deeper than allowed
                    const uint32_t order = nearFirstOrder(childEnter, hitMask);
                    const int nearest = int(order & 7u);
                    levelNode[levels] = uint32_t(at - v.records());
                    levelOrder[levels] = order >> 4;
                    ++levels;
                    NoObserver silent;  // the observer saw this lookup a moment ago
                    at = v.child(at, n.key, nearest, silent);
                    tEnter = childEnter[nearest];
                    continue;
                }
            }
        }
        // Next: the nearest child left at the deepest level that has one.
        while (levels > 0 && levelOrder[levels - 1] == 0) --levels;
        if (levels == 0) break;
        const int octant = int(levelOrder[levels - 1] & 7u);
        levelOrder[levels - 1] >>= 4;
        const OctreeNode* parent = v.records() + levelNode[levels - 1];
        NoObserver silent;  // the observer saw this lookup when the child was tested
        at = v.child(parent, loadReadOnly(parent).key, octant, silent);
        // The same box and ray as its first test: the same entry t (the interval's near end
        // does not depend on tmax).
        tEnter = boxEntry(q.slabs, loadReadOnly(at).box, r.tmin);
    }
    return finishHit(best);
}

// The closest-hit and any-hit queries of every View that declares
// `static constexpr bool kNodeRecords = true` (it stores the paper's node record and provides
// root() and child()), with an observer, and the forms the kernels call, with none.
template <class View, class Obs, std::enable_if_t<View::kNodeRecords, int> = 0>
OCT_HD inline Hit closestHit(const View& v, const Ray& r, TraceCost& cost, Obs& obs) {
    return traverseOctree<false>(v, r, cost, obs);
}
template <class View, class Obs, std::enable_if_t<View::kNodeRecords, int> = 0>
OCT_HD inline bool anyHit(const View& v, const Ray& r, TraceCost& cost, Obs& obs) {
    return traverseOctree<true>(v, r, cost, obs).prim != -1;  // a fault is no light
}
template <class View, std::enable_if_t<View::kNodeRecords, int> = 0>
OCT_HD inline Hit closestHit(const View& v, const Ray& r, TraceCost& cost) {
    NoObserver none;
    return traverseOctree<false>(v, r, cost, none);
}
template <class View, std::enable_if_t<View::kNodeRecords, int> = 0>
OCT_HD inline bool anyHit(const View& v, const Ray& r, TraceCost& cost) {
    NoObserver none;
    return traverseOctree<true>(v, r, cost, none).prim != -1;
}

}  // namespace oct
