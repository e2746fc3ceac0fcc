// Ray queries over every layout, written once as OCT_HD code (paper, sec. 5: test the node's
// box; internal: visit every intersected child; leaf: test its primitives; keep the minimum t).
//
// Beyond the paper, children are visited nearest-first and a node whose box is entered beyond
// the closest hit found so far is skipped. This returns the same closest hit (only nodes that
// cannot hold a nearer one are skipped) with fewer visits. Ties in t go to the lower primitive
// id, so every layout reports the same primitive as exhaustive tracing for the same t.
#pragma once

#include "core/geometry/aabb.h"
#include "core/geometry/primitives.h"
#include "core/octree/octree_limits.h"
#include "core/octree/views.h"

namespace oct {

struct Ray {
    Vec3 org;
    Vec3 dir;
    float tmin;
    float tmax;
};

struct Hit {
    float t;       // +inf on a miss
    int32_t prim;  // -1 on a miss
};

// Work done for one query: the paper's cost measure, reported per pixel in the Film.
struct TraceCost {
    uint32_t nodesVisited;  // node boxes tested
    uint32_t primsTested;   // ray-primitive tests
};

// A ray with everything the inner loops reuse computed once.
struct PreparedRay {
    Ray ray;
    ShearedRay sheared;
    RaySlabs slabs;
};

OCT_HD inline PreparedRay prepareRay(const Ray& r) {
    return {r, makeShearedRay(r.org, r.dir), makeRaySlabs(r.org, r.dir)};
}

OCT_HD inline bool intersectPrimitive(const PrimitivesView& p, uint32_t i, const PreparedRay& q,
                                      float tmax, float& t) {
    if (p.kind == PrimKind::Triangles)
        return intersectTriangle(q.sheared, loadReadOnly(p.tris + i), q.ray.tmin, tmax, t);
    return intersectSphere(q.ray.org, q.ray.dir, loadReadOnly(p.spheres + i), q.ray.tmin, tmax, t);
}

// Closest-hit update with the deterministic tie rule (equal t: lower primitive id wins).
OCT_HD inline void considerPrimitive(const PrimitivesView& p, uint32_t i, const PreparedRay& q,
                                     Hit& best, TraceCost& cost) {
    float t;
    ++cost.primsTested;
    if (!intersectPrimitive(p, i, q, best.t, t)) return;
    // best starts at (tmax, no primitive): the first hit at exactly tmax must still count.
    if (best.prim < 0 || t < best.t || (t == best.t && static_cast<int32_t>(i) < best.prim)) {
        best.t = t;
        best.prim = static_cast<int32_t>(i);
    }
}

OCT_HD inline Hit missHit() { return {INFINITY, -1}; }
OCT_HD inline Hit initialHit(const Ray& r) {
    // Searching up to tmax inclusive: a hit at exactly tmax is accepted.
    return {r.tmax, -1};
}
OCT_HD inline Hit finishHit(Hit h) { return h.prim < 0 ? missHit() : h; }

// --- exhaustive -----------------------------------------------------------------------------

OCT_HD inline Hit closestHit(const ExhaustiveView& v, const Ray& r, TraceCost& cost) {
    PreparedRay q = prepareRay(r);
    Hit best = initialHit(r);
    for (uint32_t i = 0; i < v.prims.count; ++i) considerPrimitive(v.prims, i, q, best, cost);
    return finishHit(best);
}

OCT_HD inline bool anyHit(const ExhaustiveView& v, const Ray& r, TraceCost& cost) {
    PreparedRay q = prepareRay(r);
    for (uint32_t i = 0; i < v.prims.count; ++i) {
        float t;
        ++cost.primsTested;
        if (intersectPrimitive(v.prims, i, q, r.tmax, t)) return true;
    }
    return false;
}

// --- octrees (linear and hash share this; they differ only in root() and child()) -----------

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
template <bool kAnyHit, class OctView>
OCT_HD inline Hit traverseOctree(const OctView& v, const Ray& r, TraceCost& cost) {
    PreparedRay q = prepareRay(r);
    Hit best = initialHit(r);
    StackEntry stack[kTraversalStackSize];
    int top = 0;

    const OctreeNode* root = v.root();
    float t0, t1;
    ++cost.nodesVisited;
    if (root == nullptr || !intersectBox(q.slabs, loadReadOnly(root).box, r.tmin, r.tmax, t0, t1))
        return missHit();
    stack[top++] = {root, t0};

    while (top > 0) {
        StackEntry e = stack[--top];
        if (e.tEnter > best.t) continue;  // a nearer hit is already known
        const OctreeNode& n = loadReadOnly(e.node);
        NodeType type = n.nodeType();
        if (type == NodeType::Leaf) {
            for (uint32_t k = 0; k < n.primCount; ++k) {
                const uint32_t prim = loadReadOnly(v.primIndices + n.primOffset + k);
                considerPrimitive(v.prims, prim, q, best, cost);
                if (kAnyHit && best.prim >= 0) return best;
            }
            continue;
        }
        if (type != NodeType::Internal) continue;
        StackEntry kids[8];
        int count = 0;
        for (int i = 0; i < 8; ++i) {
            const OctreeNode* c = v.child(e.node, n.key, i);
            // Empty leaves and absent nodes hold nothing to hit.
            if (c == nullptr) continue;
            const OctreeNode& cn = loadReadOnly(c);
            NodeType ct = cn.nodeType();
            if (ct != NodeType::Leaf && ct != NodeType::Internal) continue;
            ++cost.nodesVisited;
            if (intersectBox(q.slabs, cn.box, r.tmin, best.t, t0, t1)) kids[count++] = {c, t0};
        }
        sortFarToNear(kids, count);
        for (int i = 0; i < count; ++i) stack[top++] = kids[i];
    }
    return finishHit(best);
}

OCT_HD inline Hit closestHit(const LinearOctreeView& v, const Ray& r, TraceCost& cost) {
    return traverseOctree<false>(v, r, cost);
}
OCT_HD inline Hit closestHit(const HashOctreeView& v, const Ray& r, TraceCost& cost) {
    return traverseOctree<false>(v, r, cost);
}
OCT_HD inline bool anyHit(const LinearOctreeView& v, const Ray& r, TraceCost& cost) {
    return traverseOctree<true>(v, r, cost).prim >= 0;
}
OCT_HD inline bool anyHit(const HashOctreeView& v, const Ray& r, TraceCost& cost) {
    return traverseOctree<true>(v, r, cost).prim >= 0;
}

}  // namespace oct
