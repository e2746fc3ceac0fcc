// Compact octree (beyond the paper): the same canonical octree, same leaves and leaf lists,
// stored the way a modern engineer would, for speed and memory.
//
// - Nodes hold what traversal needs and nothing else (ESVO child descriptors, Laine & Karras,
//   "Efficient Sparse Voxel Octrees", 2010): an internal node holds a child mask, a leaf mask
//   and the index of its first child; its non-empty children are stored contiguously in octant
//   order. Empty leaves are not stored at all. 8 bytes a node.
// - No boxes are stored: a cell's box follows from the root's by halving. Traversal halves with
//   exactly the float operations the builder used (childBox, core/geometry/aabb.h), so every
//   derived box is bit for bit the canonical node's box, and every leaf list the builder made
//   for that box applies unchanged.
// - Children are tested from parametric t-values (after Revelles, Urena & Lastra, "An
//   Efficient Parametric Algorithm for Octree Traversal", 2000): per internal node the t of the
//   three mid-planes only, then each child's interval by min/max selections, eight lanes at
//   once (vectorised on the CPU, one thread's loop on CUDA). The t-values are those the slab test
//   would compute for the child's box, so the decisions are the slab test's own.
// - Front to back with early exit: children are visited in the ray's octant order, a node
//   entered beyond the closest hit is dropped, any-hit queries stop at the first hit. The
//   traversal keeps one 8-byte entry a level, no boxes (traverseCompact).
// Device code only; converting the canonical octree is compact_layout.h.
#pragma once

#include <cstdint>
#include <type_traits>

#include "core/octree/array_span.h"
#include "core/octree/morton.h"
#include "core/octree/traversal.h"

namespace oct {

// Byte layout (8 bytes). Which form a record takes is known from its parent's leafMask (the
// root's from CompactOctreeView::rootIsLeaf).
//   internal: 0 uint32 firstChild  index of its first child record
//             4 uint8  childMask   bit i: octant i holds an internal node or a non-empty leaf
//             5 uint8  leafMask    bit i: that child is a leaf (a subset of childMask)
//             6 uint16 zero
//   leaf:     0 uint32 primOffset  first entry of its list in the global primIndices array
//             4 uint32 primCount   entries in that list (> 0: empty leaves are not stored)
struct CompactNode {
    uint32_t a;  // firstChild | primOffset
    uint32_t b;  // childMask | leafMask << 8 | primCount

    OCT_HD uint32_t firstChild() const { return a; }
    OCT_HD uint32_t childMask() const { return b & 0xffu; }
    OCT_HD uint32_t leafMask() const { return (b >> 8) & 0xffu; }
    OCT_HD uint32_t primOffset() const { return a; }
    OCT_HD uint32_t primCount() const { return b; }
};
static_assert(sizeof(CompactNode) == 8, "CompactNode byte layout is documented above");

// The geometry inside a record's cell, quantised to 1/255 of the cell along each axis, rounded
// outwards (after Ylitie, Karras & Laine, "Efficient Incoherent Ray Traversal on GPUs Through
// Compressed Wide BVHs", 2017, who quantise child boxes to 8 bits a plane). Octree cells are
// loose around triangles; these bounds cull rays that cross a cell but miss what it holds.
// Byte layout (8 bytes):
//   0 uint8 lo[3]  plane = cellLo + lo * step            step = (cellHi - cellLo) * (1 / 255)
//   3 uint8 hi[3]  plane = cellHi - (255 - hi) * step
//   6 uint8 zero[2]
// lo = 0 and hi = 255 give the cell's own planes exactly.
struct QuantBounds {
    uint8_t lo[3];
    uint8_t hi[3];
    uint8_t zero[2];
};
static_assert(sizeof(QuantBounds) == 8, "QuantBounds byte layout is documented above");

// The planes of QuantBounds within `cell`, computed the one way the converter checks them
// against the geometry (compact_octree.cpp), fused multiply-add or not.
OCT_HD inline Aabb dequantize(const QuantBounds& qb, const Aabb& cell) {
    Aabb b;
    for (int a = 0; a < 3; ++a) {
        const float step = (cell.hi[a] - cell.lo[a]) * (1.0f / 255.0f);
        b.lo[a] = cell.lo[a] + float(qb.lo[a]) * step;
        b.hi[a] = cell.hi[a] - float(255 - qb.hi[a]) * step;
    }
    return b;
}

// 104 bytes.
struct CompactOctreeView {
    ArraySpan<CompactNode> nodes;     // 16 bytes; root at 0, breadth first
    ArraySpan<uint32_t> primIndices;  // 16 bytes: the global leaf index array
    ArraySpan<QuantBounds> bounds;    // 16 bytes: per record; none: cells only
    PrimitivesView prims;             // 24 bytes
    Aabb rootBox;                     // 24 bytes: the canonical root cube
    uint32_t rootIsLeaf;              // 4 bytes: 1 when the whole tree is one leaf (+4 padding)

    // The arrays, each once (layout.h): host view, CUDA upload and byte count derive from it.
    template <class V, class F>
    static void forEachArray(V& v, F&& f) {
        f("the compact octree's nodes", v.nodes);
        f("the leaf index list", v.primIndices);
        f("the compact octree's bounds", v.bounds);
    }
};
// The layout above is for 64-bit pointers (hosts, CUDA); the explain page's WebAssembly kernel
// (32-bit pointers) has smaller spans.
static_assert(sizeof(void*) != 8 || sizeof(CompactOctreeView) == 104,
              "CompactOctreeView byte layout is given above");
static_assert(std::is_trivially_copyable<CompactOctreeView>::value, "views are passed by value");

// --- traversal ---------------------------------------------------------------------------------

// Host loops over the eight lanes are written for the vectoriser; CUDA runs them per thread.
// childIntervals is forced inline on the host: GCC kept it out of line once it became a function
// of its own, although it is one loop body (docs/PERFORMANCE.md, "Kernel choices").
#if defined(__CUDA_ARCH__)
#define OCT_SIMD_LOOP
#define OCT_LANES_INLINE
#else
#define OCT_SIMD_LOOP _Pragma("omp simd")
#define OCT_LANES_INLINE __attribute__((always_inline))
#endif

namespace compact_detail {

// The slab interval [near, far] of the lower and the upper half of a box along one axis, as
// intersectSlab (aabb.h) computes it for the half's own box: t at its two planes, near the
// smaller, far the larger scaled by kSlabFarScale. A zero direction component (inv = +-inf)
// never forms 0 * inf: the half contains the origin's coordinate for all t, or never.
OCT_HD inline void halfSlabs(float o, float inv, float lo, float mid, float hi, float* nearT,
                             float* farT) {
    if (std::isinf(inv)) {
        const bool inLo = o >= lo && o <= mid, inHi = o >= mid && o <= hi;
        nearT[0] = inLo ? -INFINITY : INFINITY;
        farT[0] = inLo ? INFINITY : -INFINITY;
        nearT[1] = inHi ? -INFINITY : INFINITY;
        farT[1] = inHi ? INFINITY : -INFINITY;
        return;
    }
    const float tl = (lo - o) * inv, tm = (mid - o) * inv, th = (hi - o) * inv;
    nearT[0] = minf(tl, tm);
    farT[0] = maxf(tl, tm) * kSlabFarScale;
    nearT[1] = minf(tm, th);
    farT[1] = maxf(tm, th) * kSlabFarScale;
}

// The slab intervals of the eight children of `box` (the builder's halving, childBox, so the
// same bits) clipped to [tLo, tHi]: enter[i], exit[i] for octant i, and the mask of the children
// the ray meets (touching counts, as intersectBox). validate's box-test contract checks exactly
// this function (validation/exact/box_contract.h).
OCT_HD OCT_LANES_INLINE inline uint32_t childIntervals(const RaySlabs& s, const Aabb& box,
                                                       float tLo, float tHi, float* enter,
                                                       float* exit) {
    const Vec3 mid = box.center();
    float nearX[2], farX[2], nearY[2], farY[2], nearZ[2], farZ[2];
    halfSlabs(s.org.x, s.inv.x, box.lo.x, mid.x, box.hi.x, nearX, farX);
    halfSlabs(s.org.y, s.inv.y, box.lo.y, mid.y, box.hi.y, nearY, farY);
    halfSlabs(s.org.z, s.inv.z, box.lo.z, mid.z, box.hi.z, nearZ, farZ);
    // Eight lanes, octant i taking the upper half along x when bit 0 is set, and so on,
    // laid out as arrays so the vectoriser sees plain element-wise min/max (SoA lanes).
    const float nx[8] = {nearX[0], nearX[1], nearX[0], nearX[1],
                         nearX[0], nearX[1], nearX[0], nearX[1]};
    const float ny[8] = {nearY[0], nearY[0], nearY[1], nearY[1],
                         nearY[0], nearY[0], nearY[1], nearY[1]};
    const float nz[8] = {nearZ[0], nearZ[0], nearZ[0], nearZ[0],
                         nearZ[1], nearZ[1], nearZ[1], nearZ[1]};
    const float fx[8] = {farX[0], farX[1], farX[0], farX[1], farX[0], farX[1], farX[0], farX[1]};
    const float fy[8] = {farY[0], farY[0], farY[1], farY[1], farY[0], farY[0], farY[1], farY[1]};
    const float fz[8] = {farZ[0], farZ[0], farZ[0], farZ[0], farZ[1], farZ[1], farZ[1], farZ[1]};
    OCT_SIMD_LOOP
    for (int i = 0; i < 8; ++i) {
        enter[i] = maxf(maxf(maxf(tLo, nx[i]), ny[i]), nz[i]);
        exit[i] = minf(minf(minf(tHi, fx[i]), fy[i]), fz[i]);
    }
    uint32_t hitMask = 0;
    for (int i = 0; i < 8; ++i) hitMask |= uint32_t(enter[i] <= exit[i]) << i;
    return hitMask;
}

// Set bits of an 8-bit mask. The host reads a 256-entry table (popcount is a library call on
// x86-64 without -mpopcnt, and the SWAR form costs more: docs/PERFORMANCE.md, "Kernel
// choices"); the device has an instruction for it.
struct BitCounts {
    uint8_t n[256];
    constexpr BitCounts() : n() {
        for (int i = 0; i < 256; ++i) n[i] = uint8_t((i & 1) + n[i >> 1]);
    }
};
inline constexpr BitCounts kBitCounts{};

OCT_HD inline uint32_t bitCount8(uint32_t x) {
#if defined(__CUDA_ARCH__)
    return uint32_t(__popc(x));
#else
    return kBitCounts.n[x & 0xffu];
#endif
}

// The mask whose bit j is bit (j ^ flip) of m, for an 8-bit m and flip in [0, 8).
OCT_HD inline uint32_t xorPermute(uint32_t m, int flip) {
    if (flip & 1) m = ((m & 0x55u) << 1) | ((m >> 1) & 0x55u);
    if (flip & 2) m = ((m & 0x33u) << 2) | ((m >> 2) & 0x33u);
    if (flip & 4) m = ((m & 0x0fu) << 4) | ((m >> 4) & 0x0fu);
    return m;
}

// Index of the highest set bit of a non-zero mask.
OCT_HD inline int highestBit(uint32_t m) {
#if defined(__CUDA_ARCH__)
    return 31 - __clz(m);
#else
    return 31 - __builtin_clz(m);
#endif
}

}  // namespace compact_detail

// The record of internal node n's child in `octant` (a bit of n's childMask): its non-empty
// children are stored contiguously in octant order from firstChild, so it is firstChild plus
// the stored octants below it.
OCT_HD inline uint32_t compactChildIndex(const CompactNode& n, int octant) {
    return n.firstChild() + compact_detail::bitCount8(n.childMask() & ((1u << octant) - 1u));
}

// The box of the cell with Morton key `key` at `depth`: the root's halved along the key's path,
// the builder's operations in the builder's order (childBox), so the same bits as the canonical
// node's box.
OCT_HD inline Aabb compactCellBox(const Aabb& rootBox, uint64_t key, int depth) {
    Aabb box = rootBox;
    for (int d = depth - 1; d >= 0; --d) box = childBox(box, int((key >> (3 * d)) & 7u));
    return box;
}

// Traversal with one 8-byte entry a level (after Laine & Karras 2010, ESVO, whose stack is one
// parent a level): the internal node's first child and masks, and which hit children are left.
// Boxes are not kept: the current level's parent box is held, a child's box is halved from it
// when the child's turn comes, and on going back up a level the parent's box is halved again
// from the root along the key (compactCellBox). The nearest child is visited straight away;
// a later one's entry t is recomputed from its box, the slab test's own bits (childIntervals'
// comment). 21 levels x 8 bytes = 168 bytes, against a
// 36-byte box and entry a pushed child (155 of them, 5.6 KB) before.
//
// A level entry is the parent's own record (CompactNode, internal form), its zero bits 16-23
// holding the hit children not yet visited, in front-to-back position j (octant j ^ dirMask),
// so a child's record and leaf bit come from it as from the record (compactChildIndex).
template <bool kAnyHit, class Obs>
OCT_HD inline Hit traverseCompact(const CompactOctreeView& v, const Ray& r, TraceCost& cost,
                                  Obs& obs) {
    constexpr bool kSilent = std::is_same<Obs, NoObserver>::value;
    PreparedRay q = prepareRay(r);
    Hit best = initialHit(r);
    CompactNode level[kMaxOctreeDepth];  // the internal node of each level, children left above
    int levels = 0;

    // Bit a set when the ray runs towards -a: octant order j ^ dirMask is front to back.
    const int dirMask =
        (r.dir.x < 0.0f ? 1 : 0) | (r.dir.y < 0.0f ? 2 : 0) | (r.dir.z < 0.0f ? 4 : 0);
    float tEnter, t1;
    ++cost.nodesVisited;
    if (v.nodes.count == 0) {
        obs.childSkipped(kRootKey, SkipReason::Absent);
        return missHit();
    }
    const bool rootHit = intersectBox(q.slabs, v.rootBox, r.tmin, r.tmax, tEnter, t1);
    obs.boxTested(kRootKey, 0, v.rootBox, rootHit, tEnter, t1);
    if (!rootHit) return missHit();

    // The node to visit: its record, whether it is a leaf, key, depth and cell; and the box of
    // the parent at the deepest level (levelBox, of depth levels - 1 when levels > 0).
    uint32_t index = 0;
    bool leaf = v.rootIsLeaf != 0;
    uint64_t key = kRootKey;
    int depth = 0;
    Aabb box = v.rootBox, levelBox = v.rootBox;
    int levelBoxDepth = -1;
    for (;;) {
        // Entered beyond the closest hit: nothing nearer below. Without an observer and with
        // bounds, the bounds test below decides it alone (the bounds lie within the cell, so a
        // cell entered beyond the hit has bounds entered beyond it too).
        if ((!kSilent || v.bounds.count == 0) && tEnter > best.t) {
            obs.nodePopped(key, tEnter, false);
        } else if (v.bounds.count != 0 &&
                   !intersectBox(q.slabs, dequantize(loadReadOnly(v.bounds.data + index), box),
                                 r.tmin, best.t, t1, t1)) {
            // The geometry's bounds within the cell: a ray that crosses the cell but misses
            // them meets nothing stored below it.
            obs.childSkipped(key, SkipReason::OutsideBounds);
        } else {
            obs.nodePopped(key, tEnter, true);
            const CompactNode n = loadReadOnly(v.nodes.data + index);
            if (leaf) {
                const LeafOutcome out = testLeafList<kAnyHit>(
                    v.primIndices, n.primOffset(), n.primCount(), v.prims, q, best, cost, obs);
                if (out == LeafOutcome::Fault) return faultHit();
                if (out == LeafOutcome::Found) return best;
            } else {
                const uint32_t mask = n.childMask(), leafMask = n.leafMask();
                float enter[8], exit[8];
                uint32_t hitMask =
                    compact_detail::childIntervals(q.slabs, box, r.tmin, best.t, enter, exit);
                hitMask &= mask;
                cost.nodesVisited += compact_detail::bitCount8(mask);
                if (!kSilent) {
                    for (int i = 0; i < 8; ++i) {
                        const uint64_t k = childKey(key, i);
                        if (mask & (1u << i))
                            obs.boxTested(k, depth + 1, childBox(box, i), (hitMask >> i) & 1u,
                                          enter[i], exit[i]);
                        else
                            obs.childSkipped(k, SkipReason::Empty);
                    }
                }
                if (hitMask != 0) {
                    // A child's record is firstChild + the stored octants below it; records are
                    // breadth first, so every child lies after its parent and inside the array
                    // (else the structure is broken: fail, and never cycle). Records grow
                    // with the octant: the lowest and highest hit children bound them all.
                    const uint32_t first = compactChildIndex(n, lowestBit(hitMask));
                    const uint32_t last = compactChildIndex(n, compact_detail::highestBit(hitMask));
                    if (first <= index || last >= v.nodes.count) return faultHit();
                    if (levels == kMaxOctreeDepth) return faultHit();  // deeper than allowed
                    // Octant order j ^ dirMask (ascending j) is front to back for any ray:
                    // along each axis the ray crosses from the half it starts in to the other,
                    // never back, so a child whose octant differs from another's in bits the
                    // ray flips later cannot be entered earlier. Bit j of the order is octant
                    // j ^ dirMask; its set bits from the lowest up are the visits, no sort.
                    // The nearest child is visited at once, with the entry t just found; the
                    // rest wait at this level (one level a node on the path, bounding the depth).
                    const uint32_t order = compact_detail::xorPermute(hitMask, dirMask);
                    const int i = lowestBit(order) ^ dirMask;
                    level[levels] = {n.a, n.b | (order & (order - 1u)) << 16};
                    ++levels;
                    levelBox = box;
                    levelBoxDepth = depth;
                    index = compactChildIndex(n, i);
                    leaf = ((leafMask >> i) & 1u) != 0;
                    key = childKey(key, i);
                    depth = depth + 1;
                    box = childBox(levelBox, i);
                    tEnter = enter[i];
                    continue;
                }
            }
        }
        // Next: the nearest child left at the deepest level that has one.
        while (levels > 0 && (level[levels - 1].b >> 16) == 0) --levels;
        if (levels == 0) break;
        const int parentDepth = levels - 1;
        const uint64_t parentKey = key >> (3 * (depth - parentDepth));
        if (levelBoxDepth != parentDepth) {  // back up a level: halve the parent's box again
            levelBox = compactCellBox(v.rootBox, parentKey, parentDepth);
            levelBoxDepth = parentDepth;
        }
        CompactNode& parent = level[parentDepth];
        const int j = lowestBit(parent.b >> 16);
        parent.b ^= 1u << (16 + j);
        const int i = j ^ dirMask;
        index = compactChildIndex(parent, i);
        leaf = ((parent.leafMask() >> i) & 1u) != 0;
        key = childKey(parentKey, i);
        depth = parentDepth + 1;
        box = childBox(levelBox, i);
        if (!kSilent || v.bounds.count == 0)  // the same entry t as its test among its siblings
            tEnter = boxEntry(q.slabs, box, r.tmin);
    }
    return finishHit(best);
}

template <class Obs>
OCT_HD inline Hit closestHit(const CompactOctreeView& v, const Ray& r, TraceCost& cost, Obs& obs) {
    return traverseCompact<false>(v, r, cost, obs);
}
template <class Obs>
OCT_HD inline bool anyHit(const CompactOctreeView& v, const Ray& r, TraceCost& cost, Obs& obs) {
    return traverseCompact<true>(v, r, cost, obs).prim != -1;  // a fault is no light
}
OCT_HD inline Hit closestHit(const CompactOctreeView& v, const Ray& r, TraceCost& cost) {
    NoObserver none;
    return traverseCompact<false>(v, r, cost, none);
}
OCT_HD inline bool anyHit(const CompactOctreeView& v, const Ray& r, TraceCost& cost) {
    NoObserver none;
    return traverseCompact<true>(v, r, cost, none).prim != -1;
}

}  // namespace oct
