// A textbook scalar binary BVH over a triangle mesh: the yardstick of docs/PERFORMANCE.md's
// target "compact ≤ 1× a scalar binary BVH", traced by the `bvh` backend (bvh_backend.h).
// Built on the host with binned SAH (Wald, "On fast construction of SAH-based bounding volume
// hierarchies", IEEE RT 2007), traced depth first, nearer child first, with a small fixed
// stack, one ray at a time and no SIMD intrinsics. The triangle test and the nearest-hit rule
// are the octree kernel's own (intersectTriangle, keepNearer: core/geometry/), so its answers
// are the octree layouts' to the bit: the two structures differ only in which triangles they
// test. Host-only.
#pragma once

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/geometry/aabb.h"
#include "core/geometry/primitives_view.h"
#include "core/geometry/ray.h"
#include "core/scene/scene.h"

namespace oct {

class BvhError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// One node, 32 bytes, so two siblings (stored side by side) share 64 bytes:
//   bytes  0-23  box    the bounds of every triangle below, padded by 2^-20 of their largest
//                       coordinate (binary_bvh.cpp) (Aabb: lo xyz, hi xyz, floats)
//   bytes 24-27  index  inner node: its first child, the second is index + 1;
//                       leaf: its first triangle in BvhView::tris (and ids)
//   bytes 28-31  count  leaf: its triangles (1 or more); inner node: 0
// The root is node 0, so no inner node has index 0: a scene without triangles is a root of
// index 0 and count 0, a leaf with nothing to test.
struct BvhNode {
    Aabb box;
    uint32_t index;
    uint32_t count;

    bool leaf() const { return count > 0 || index == 0; }
};
static_assert(sizeof(BvhNode) == 32, "BvhNode byte layout is documented above");
static_assert(std::is_trivially_copyable<BvhNode>::value, "nodes are plain data");

// The builder makes a leaf at depth kBvhMaxDepth - 1 at the latest, so a walk never holds more
// than kBvhMaxDepth - 1 pending nodes (one per level above it): the traversal's fixed stack.
constexpr int kBvhMaxDepth = 64;
constexpr int kBvhBins = 16;                   // SAH bins per axis (Wald 2007 uses 16 or 32)
constexpr uint32_t kBvhLeafTriangles = 4;      // a node of at most this many is always a leaf
constexpr uint32_t kBvhMaxLeafTriangles = 16;  // above it, split even where SAH would not

// What the traversal reads: the nodes, and the triangles in leaf order with their scene ids.
// 24 bytes.
struct BvhView {
    const BvhNode* nodes;  // 8 bytes
    const Triangle* tris;  // 8 bytes: leaf order (a copy of the scene's, so a leaf is contiguous)
    const uint32_t* ids;   // 8 bytes: scene primitive id of tris[k]
};
static_assert(sizeof(void*) != 8 || sizeof(BvhView) == 24, "BvhView byte layout is above");

// Shape figures of a built BVH, for tests and reports.
struct BvhStats {
    uint64_t nodes = 0, leaves = 0;
    int depth = 0;             // of the deepest leaf, the root at 0
    uint32_t largestLeaf = 0;  // triangles
    uint64_t bytes = 0;        // nodes + triangle copies + ids
};

class BinaryBvh {
public:
    // Builds over scene's triangles (the scene may be released afterwards: the triangles are
    // copied). Throws BvhError naming the scene for a point cloud.
    explicit BinaryBvh(const Scene& scene);

    BvhView view() const { return {nodes_.data(), tris_.data(), ids_.data()}; }
    double buildSeconds() const { return buildSeconds_; }
    BvhStats stats() const;
    const std::vector<BvhNode>& nodes() const { return nodes_; }
    const std::vector<uint32_t>& ids() const { return ids_; }

private:
    std::vector<BvhNode> nodes_;
    std::vector<Triangle> tris_;
    std::vector<uint32_t> ids_;
    double buildSeconds_ = 0.0;
};

// The slab test against a node's box (Kay & Kajiya 1986; aabb.h's intersectBox, with the
// inverse direction prepared once per ray), its interval widened at both ends by kBvhBoxSlack
// relative. A BVH's boxes are tight: a triangle can lie in a box's face (a flat box around an
// axis-aligned wall, a mesh's extreme vertex), where the box's entry or exit t and the
// triangle's t are the same exact number rounded two ways. intersectTriangle's t is within
// kTriangleRefine (2^-20) relative of the exact one (it recomputes in double past that bound:
// primitives.h) and each slab's t within three roundings, so a box widened by 2^-18 holds
// every hit its triangles report, also on a segment that ends or starts exactly there (tmin,
// tmax, or the closest hit so far). Ize's 1 + 2 gamma(3) on the far end (aabb.h), enough
// against the exact interval, is not enough against a rounded triangle t. tmin >= 0 (the ray
// file's rule), so scaling the ends (not their magnitudes) widens every interval that matters:
// a box behind the origin stays behind. A zero direction component is decided exactly, as in
// intersectBox.
constexpr float kBvhBoxSlack = 0x1p-18f;

inline bool bvhSlab(float o, float inv, float lo, float hi, float& t0, float& t1) {
    if (std::isinf(inv)) return o >= lo && o <= hi;
    const float ta = (lo - o) * inv, tb = (hi - o) * inv;
    t0 = maxf(t0, minf(ta, tb) * (1.0f - kBvhBoxSlack));
    t1 = minf(t1, maxf(ta, tb) * (1.0f + kBvhBoxSlack));
    return true;
}

// True when the segment [tmin, tmax] meets the box (widened as above); tEnter: where it enters.
inline bool intersectBvhBox(const RaySlabs& r, const Aabb& b, float tmin, float tmax,
                            float& tEnter) {
    float t0 = tmin, t1 = tmax;
    if (!bvhSlab(r.org.x, r.inv.x, b.lo.x, b.hi.x, t0, t1)) return false;
    if (!bvhSlab(r.org.y, r.inv.y, b.lo.y, b.hi.y, t0, t1)) return false;
    if (!bvhSlab(r.org.z, r.inv.z, b.lo.z, b.hi.z, t0, t1)) return false;
    tEnter = t0;
    return t0 <= t1;
}

// Tests a leaf's triangles against the ray, keeping the nearest in `best` (tie: lower id, as
// every octree walk). True when kAnyHit and one was hit: the walk stops there.
template <bool kAnyHit>
inline bool testBvhLeaf(const BvhView& v, const BvhNode& leaf, const PreparedRay& q, Hit& best,
                        TraceCost& cost) {
    const uint32_t end = leaf.index + leaf.count;
    for (uint32_t k = leaf.index; k < end; ++k) {
        ++cost.primsTested;
        float t;
        // Up to best.t inclusive: a triangle at the same t with a lower id still replaces it.
        if (!intersectTriangle(q.sheared, v.tris[k], q.ray.tmin, best.t, t)) continue;
        keepNearer(best, t, v.ids[k]);
        if (kAnyHit) return true;
    }
    return false;
}

// The walk: depth first from the root; at an inner node both children's boxes are tested
// (intersectBvhBox), the
// nearer is visited at once and the farther pushed with its entry t; a popped node entered
// beyond the closest hit so far is skipped. Only nodes that cannot hold a nearer hit are
// skipped, so the answer is the nearest of all triangles (lower id on a tie), as exhaustive
// tracing gives.
template <bool kAnyHit>
inline Hit traverseBvh(const BvhView& v, const Ray& r, TraceCost& cost) {
    struct Pending {
        uint32_t node;
        float tEnter;
    };
    Pending stack[kBvhMaxDepth];
    int pending = 0;
    const PreparedRay q = prepareRay(r);
    Hit best = initialHit(r);
    float tEnter;
    ++cost.nodesVisited;
    if (!intersectBvhBox(q.slabs, v.nodes[0].box, r.tmin, r.tmax, tEnter)) return missHit();
    uint32_t at = 0;
    for (;;) {
        const BvhNode& n = v.nodes[at];
        if (n.leaf()) {
            if (testBvhLeaf<kAnyHit>(v, n, q, best, cost)) return best;
        } else {
            uint32_t nearChild = n.index, farChild = n.index + 1;
            float tNear = 0.0f, tFar = 0.0f;  // written on a hit only
            cost.nodesVisited += 2;
            const bool hitNear =
                intersectBvhBox(q.slabs, v.nodes[nearChild].box, r.tmin, best.t, tNear);
            const bool hitFar =
                intersectBvhBox(q.slabs, v.nodes[farChild].box, r.tmin, best.t, tFar);
            if (hitNear && hitFar) {
                if (tFar < tNear) {  // equal: the first child first
                    std::swap(nearChild, farChild);
                    std::swap(tNear, tFar);
                }
                stack[pending++] = {farChild, tFar};
                at = nearChild;
                continue;
            }
            if (hitNear || hitFar) {
                at = hitNear ? nearChild : farChild;
                continue;
            }
        }
        // Next: the most recently pushed node not entered beyond the closest hit.
        for (;;) {
            if (pending == 0) return finishHit(best);
            const Pending p = stack[--pending];
            if (p.tEnter <= best.t) {
                at = p.node;
                break;
            }
        }
    }
}

// The kernel's queries (core/render/kernel.h) on a BVH. It reports no steps to an observer
// (`octrace explain` walks octrees only).
inline Hit closestHit(const BvhView& v, const Ray& r, TraceCost& cost) {
    return traverseBvh<false>(v, r, cost);
}
inline bool anyHit(const BvhView& v, const Ray& r, TraceCost& cost) {
    return traverseBvh<true>(v, r, cost).prim >= 0;
}
template <class Obs>
Hit closestHit(const BvhView& v, const Ray& r, TraceCost& cost, Obs&) {
    return closestHit(v, r, cost);
}
template <class Obs>
bool anyHit(const BvhView& v, const Ray& r, TraceCost& cost, Obs&) {
    return anyHit(v, r, cost);
}

}  // namespace oct
