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

struct StackEntry {
    const OctreeNode* node;
    float tEnter;
};

// Sorts up to 8 (node, tEnter) pairs by tEnter, descending, so the nearest is pushed last and
// popped first. Insertion sort: at most 8 elements.
OCT_HD inline void sortFarToNear(StackEntry* e, int n) {
    for (int i = 1; i < n; ++i) {
        StackEntry x = e[i];
        int j = i - 1;
        while (j >= 0 && e[j].tEnter < x.tEnter) {
            e[j + 1] = e[j];
            --j;
        }
        e[j + 1] = x;
    }
}

// Depth-first traversal with an explicit stack of kTraversalStackSize entries; the builder
// refuses depths beyond kMaxOctreeDepth, which bounds the stack (7 per level + 8).
// kAnyHit: stop at the first primitive hit in [tmin, tmax] (shadow rays).
// OctView needs: root(obs) -> const OctreeNode* (null: no tree), child(node, key, octant, obs)
// -> const OctreeNode* (null: absent), and the members primIndices (ArraySpan) and prims.
// child() must never hand back a node the walk has passed (linear: an index after the parent's
// and inside the array; hash: the node whose key is the child key, and keys only grow), so the
// walk cannot cycle and its work is bounded by the tree; a wrong but in-order node (a faulty
// index) is a wrong answer that validation's hit and structure checks report. Not checking
// each child's key here keeps the paper's linear walk at its cost (docs/PERFORMANCE.md).
// An inconsistent structure returns faultHit() (core/geometry/ray.h). `obs` sees every
// step (traversal_observer.h); the kernels pass NoObserver.
template <bool kAnyHit, class OctView, class Obs>
OCT_HD inline Hit traverseOctree(const OctView& v, const Ray& r, TraceCost& cost, Obs& obs) {
    PreparedRay q = prepareRay(r);
    Hit best = initialHit(r);
    StackEntry stack[kTraversalStackSize];
    int top = 0;

    const OctreeNode* root = v.root(obs);
    float t0, t1;
    ++cost.nodesVisited;
    if (root == nullptr) {
        obs.childSkipped(kRootKey, SkipReason::Absent);
        return missHit();
    }
    const OctreeNode& rn = loadReadOnly(root);
    if (rn.key != kRootKey) return faultHit();
    const bool rootHit = intersectBox(q.slabs, rn.box, r.tmin, r.tmax, t0, t1);
    obs.boxTested(kRootKey, 0, rn.box, rootHit, t0, t1);
    if (!rootHit) return missHit();
    stack[top++] = {root, t0};

    while (top > 0) {
        StackEntry e = stack[--top];
        const OctreeNode& n = loadReadOnly(e.node);
        if (e.tEnter > best.t) {  // a nearer hit is already known
            obs.nodePopped(n.key, e.tEnter, false);
            continue;
        }
        obs.nodePopped(n.key, e.tEnter, true);
        NodeType type = n.nodeType();
        if (type == NodeType::Leaf) {
            const LeafOutcome out = testLeafList<kAnyHit>(v.primIndices, n.primOffset, n.primCount,
                                                          v.prims, q, best, cost, obs);
            if (out == LeafOutcome::Fault) return faultHit();
            if (out == LeafOutcome::Found) return best;
            continue;
        }
        if (type != NodeType::Internal) continue;
        StackEntry kids[8];
        int count = 0;
        for (int i = 0; i < 8; ++i) {
            const OctreeNode* c = v.child(e.node, n.key, i, obs);
            // Empty leaves and absent nodes hold nothing to hit.
            if (c == nullptr) {
                obs.childSkipped(childKey(n.key, i), SkipReason::Absent);
                continue;
            }
            const OctreeNode& cn = loadReadOnly(c);
            NodeType ct = cn.nodeType();
            if (ct != NodeType::Leaf && ct != NodeType::Internal) {
                obs.childSkipped(childKey(n.key, i), ct == NodeType::EmptyLeaf
                                                         ? SkipReason::Empty
                                                         : SkipReason::Absent);
                continue;
            }
            ++cost.nodesVisited;
            const bool hit = intersectBox(q.slabs, cn.box, r.tmin, best.t, t0, t1);
            obs.boxTested(childKey(n.key, i), cn.depth, cn.box, hit, t0, t1);
            if (hit) kids[count++] = {c, t0};
        }
        sortFarToNear(kids, count);
        if (top + count > kTraversalStackSize) return faultHit();  // deeper than the builder allows
        for (int i = 0; i < count; ++i) stack[top++] = kids[i];
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
