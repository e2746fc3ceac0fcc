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

// The host's lanes in SSE registers where the compiler targets x86-64 (SSE2 is its baseline);
// every other target (CUDA's device pass, WebAssembly) runs the scalar form of the same lanes.
#if defined(__SSE2__) && !defined(__CUDA_ARCH__) && !defined(OCT_SCALAR_LANES)
#include <immintrin.h>
#define OCT_HOST_SSE 1
#endif

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
// Written out per axis: a loop over Vec3's run-time index compiled to select chains on the
// host (docs/PERFORMANCE.md, "Kernel choices").
OCT_HD inline void dequantizeAxis(float lo, float hi, uint8_t qLo, uint8_t qHi, float& outLo,
                                  float& outHi) {
    const float step = (hi - lo) * (1.0f / 255.0f);
    outLo = lo + float(qLo) * step;
    outHi = hi - float(255 - qHi) * step;
}
OCT_HD inline Aabb dequantize(const QuantBounds& qb, const Aabb& cell) {
    Aabb b;
    dequantizeAxis(cell.lo.x, cell.hi.x, qb.lo[0], qb.hi[0], b.lo.x, b.hi.x);
    dequantizeAxis(cell.lo.y, cell.hi.y, qb.lo[1], qb.hi[1], b.lo.y, b.hi.y);
    dequantizeAxis(cell.lo.z, cell.hi.z, qb.lo[2], qb.hi[2], b.lo.z, b.hi.z);
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

#if defined(OCT_HOST_SSE)
// The host's SSE form of the node step. Every lane computes the scalar form's operations on the
// same values in the same order, so the same bits: maxf(a, b) is _mm_max_ps(b, a) and minf(a, b)
// is _mm_min_ps(b, a), operand for operand (ties and signed zeros included). Lanes x, y, z, and
// a fourth that no result reads (the bounds test makes it neutral).
struct SseRay {
    __m128 org, inv;
    __m128 parallel;   // all ones where the direction component is zero (inv = +-inf), and lane 3
    bool anyParallel;  // lanes 0-2 of parallel: most rays have none, and skip the selects below
};

inline SseRay makeSseRay(const RaySlabs& s) {
    SseRay r;
    r.org = _mm_setr_ps(s.org.x, s.org.y, s.org.z, 0.0f);
    r.inv = _mm_setr_ps(s.inv.x, s.inv.y, s.inv.z, 0.0f);
    const __m128 absInv = _mm_andnot_ps(_mm_set1_ps(-0.0f), r.inv);
    const __m128 lane3 = _mm_castsi128_ps(_mm_setr_epi32(0, 0, 0, -1));
    r.parallel = _mm_or_ps(_mm_cmpeq_ps(absInv, _mm_set1_ps(INFINITY)), lane3);
    r.anyParallel = (_mm_movemask_ps(r.parallel) & 7) != 0;
    return r;
}

// A box's corners as lanes x, y, z, 0. Built from the floats, not loaded as 16 bytes: the box
// was just written float by float (childBox), and a wide load of narrower stores cannot be
// forwarded from the store buffer (it waits for them to retire; that stall made a first form
// 10 % slower in spite of fewer instructions).
inline __m128 lowCorner(const Aabb& b) { return _mm_setr_ps(b.lo.x, b.lo.y, b.lo.z, 0.0f); }
inline __m128 highCorner(const Aabb& b) { return _mm_setr_ps(b.hi.x, b.hi.y, b.hi.z, 0.0f); }

inline __m128 select(__m128 mask, __m128 ifSet, __m128 ifClear) {
    return _mm_or_ps(_mm_and_ps(mask, ifSet), _mm_andnot_ps(mask, ifClear));
}

// halfSlabs for the three axes at once: near and far of the lower half (0) and the upper (1).
inline void halfSlabsSse(const SseRay& r, __m128 lo, __m128 mid, __m128 hi, __m128& near0,
                         __m128& far0, __m128& near1, __m128& far1) {
    const __m128 scale = _mm_set1_ps(kSlabFarScale);
    const __m128 tl = _mm_mul_ps(_mm_sub_ps(lo, r.org), r.inv);
    const __m128 tm = _mm_mul_ps(_mm_sub_ps(mid, r.org), r.inv);
    const __m128 th = _mm_mul_ps(_mm_sub_ps(hi, r.org), r.inv);
    near0 = _mm_min_ps(tm, tl);
    far0 = _mm_mul_ps(_mm_max_ps(tm, tl), scale);
    near1 = _mm_min_ps(th, tm);
    far1 = _mm_mul_ps(_mm_max_ps(th, tm), scale);
    if (!r.anyParallel) return;  // lane 3 is read by no caller of this function
    // A parallel axis: the half holds the origin's coordinate for all t, or never.
    const __m128 inf = _mm_set1_ps(INFINITY), minusInf = _mm_set1_ps(-INFINITY);
    const __m128 inLo = _mm_and_ps(_mm_cmpge_ps(r.org, lo), _mm_cmple_ps(r.org, mid));
    const __m128 inHi = _mm_and_ps(_mm_cmpge_ps(r.org, mid), _mm_cmple_ps(r.org, hi));
    near0 = select(r.parallel, select(inLo, minusInf, inf), near0);
    far0 = select(r.parallel, select(inLo, inf, minusInf), far0);
    near1 = select(r.parallel, select(inHi, minusInf, inf), near1);
    far1 = select(r.parallel, select(inHi, inf, minusInf), far1);
}

// childIntervals below, in SSE registers: the eight lanes in two halves, the hit mask by one
// compare and movemask each (the scalar mask loop was 7 % of a trace's instructions).
inline uint32_t childIntervalsSse(const SseRay& r, const Aabb& box, float tLo, float tHi,
                                  float* enter, float* exit) {
    const __m128 lo = lowCorner(box), hi = highCorner(box);
    const __m128 mid = _mm_mul_ps(_mm_add_ps(lo, hi), _mm_set1_ps(0.5f));  // Aabb::center
    __m128 n0, f0, n1, f1;
    halfSlabsSse(r, lo, mid, hi, n0, f0, n1, f1);
    // Octant i takes the upper half along x when bit 0 is set, y bit 1, z bit 2: lanes 0-3
    // are octants 0-3 (x: 0 1 0 1, y: 0 0 1 1) in the lower half along z, lanes 4-7 the upper.
    const __m128 nxy = _mm_unpacklo_ps(n0, n1), fxy = _mm_unpacklo_ps(f0, f1);  // x0 x1 y0 y1
    const __m128 nx = _mm_movelh_ps(nxy, nxy), fx = _mm_movelh_ps(fxy, fxy);
    const __m128 ny = _mm_shuffle_ps(nxy, nxy, _MM_SHUFFLE(3, 3, 2, 2));
    const __m128 fy = _mm_shuffle_ps(fxy, fxy, _MM_SHUFFLE(3, 3, 2, 2));
    const __m128 e = _mm_max_ps(ny, _mm_max_ps(nx, _mm_set1_ps(tLo)));
    const __m128 f = _mm_min_ps(fy, _mm_min_ps(fx, _mm_set1_ps(tHi)));
    const __m128 e0 = _mm_max_ps(_mm_shuffle_ps(n0, n0, _MM_SHUFFLE(2, 2, 2, 2)), e);
    const __m128 e1 = _mm_max_ps(_mm_shuffle_ps(n1, n1, _MM_SHUFFLE(2, 2, 2, 2)), e);
    const __m128 x0 = _mm_min_ps(_mm_shuffle_ps(f0, f0, _MM_SHUFFLE(2, 2, 2, 2)), f);
    const __m128 x1 = _mm_min_ps(_mm_shuffle_ps(f1, f1, _MM_SHUFFLE(2, 2, 2, 2)), f);
    _mm_storeu_ps(enter, e0);
    _mm_storeu_ps(enter + 4, e1);
    _mm_storeu_ps(exit, x0);
    _mm_storeu_ps(exit + 4, x1);
    return uint32_t(_mm_movemask_ps(_mm_cmple_ps(e0, x0))) |
           uint32_t(_mm_movemask_ps(_mm_cmple_ps(e1, x1))) << 4;
}

// Whether the ray meets the dequantized bounds within [tmin, tmax]: intersectBox(r,
// dequantize(qb, cell), tmin, tmax, ...)'s answer, the planes computed by the same operations
// (dequantizeAxis), the slab interval's ends reduced across the lanes.
inline bool boundsHitSse(const SseRay& r, const QuantBounds& qb, const Aabb& cell, float tmin,
                         float tmax) {
    const __m128 lo = lowCorner(cell), hi = highCorner(cell);
    const __m128 step = _mm_mul_ps(_mm_sub_ps(hi, lo), _mm_set1_ps(1.0f / 255.0f));
    // The 8 bytes lo[3] hi[3] zero[2] as 32-bit lanes: lo0 lo1 lo2 hi0, and hi0 hi1 hi2 0.
    const __m128i zero = _mm_setzero_si128();
    const __m128i bytes =
        _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(&qb)), zero);
    const __m128 qLo = _mm_cvtepi32_ps(_mm_unpacklo_epi16(bytes, zero));
    const __m128 qHi = _mm_cvtepi32_ps(_mm_unpacklo_epi16(_mm_srli_si128(bytes, 6), zero));
    const __m128 bLo = _mm_add_ps(lo, _mm_mul_ps(qLo, step));
    const __m128 bHi = _mm_sub_ps(hi, _mm_mul_ps(_mm_sub_ps(_mm_set1_ps(255.0f), qHi), step));
    const __m128 ta = _mm_mul_ps(_mm_sub_ps(bLo, r.org), r.inv);
    const __m128 tb = _mm_mul_ps(_mm_sub_ps(bHi, r.org), r.inv);
    __m128 nearT = _mm_min_ps(tb, ta);
    __m128 farT = _mm_mul_ps(_mm_max_ps(tb, ta), _mm_set1_ps(kSlabFarScale));
    // Lane 3 (inv 0, a finite plane) gives t = 0 there; a parallel axis admits the ray for all t
    // when the origin lies within its slab, else never. Both are made neutral: r.parallel holds
    // lane 3 and the parallel axes.
    if (r.anyParallel) {
        const __m128 inside = _mm_and_ps(_mm_cmpge_ps(r.org, bLo), _mm_cmple_ps(r.org, bHi));
        if (_mm_movemask_ps(_mm_andnot_ps(inside, r.parallel)) & 7) return false;
    }
    nearT = select(r.parallel, _mm_set1_ps(-INFINITY), nearT);
    farT = select(r.parallel, _mm_set1_ps(INFINITY), farT);
    nearT = _mm_max_ps(nearT, _mm_shuffle_ps(nearT, nearT, _MM_SHUFFLE(2, 3, 0, 1)));
    nearT = _mm_max_ps(nearT, _mm_shuffle_ps(nearT, nearT, _MM_SHUFFLE(1, 0, 3, 2)));
    farT = _mm_min_ps(farT, _mm_shuffle_ps(farT, farT, _MM_SHUFFLE(2, 3, 0, 1)));
    farT = _mm_min_ps(farT, _mm_shuffle_ps(farT, farT, _MM_SHUFFLE(1, 0, 3, 2)));
    return maxf(tmin, _mm_cvtss_f32(nearT)) <= minf(tmax, _mm_cvtss_f32(farT));
}
#endif

// The ray as the node step reads it: its slabs, and on the host its SSE lanes, made once a ray.
struct LaneRay {
    RaySlabs slabs;
#if defined(OCT_HOST_SSE)
    SseRay sse;
#endif
};
OCT_HD inline LaneRay makeLaneRay(const RaySlabs& s) {
#if defined(OCT_HOST_SSE)
    return {s, makeSseRay(s)};
#else
    return {s};
#endif
}

// The slab intervals of the eight children of `box` (the builder's halving, childBox, so the
// same bits) clipped to [tLo, tHi]: enter[i], exit[i] for octant i, and the mask of the children
// the ray meets (touching counts, as intersectBox). validate's box-test contract checks exactly
// this function (validation/exact/box_contract.h).
OCT_HD OCT_LANES_INLINE inline uint32_t childIntervals(const LaneRay& lr, const Aabb& box,
                                                       float tLo, float tHi, float* enter,
                                                       float* exit) {
#if defined(OCT_HOST_SSE)
    return childIntervalsSse(lr.sse, box, tLo, tHi, enter, exit);
#else
    const RaySlabs& s = lr.slabs;
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
#endif
}
OCT_HD inline uint32_t childIntervals(const RaySlabs& s, const Aabb& box, float tLo, float tHi,
                                      float* enter, float* exit) {
    return childIntervals(makeLaneRay(s), box, tLo, tHi, enter, exit);
}

// Whether the ray meets the bounds `qb` of `cell` within [tmin, tmax] (intersectBox of the
// dequantized box).
OCT_HD inline bool boundsHit(const LaneRay& lr, const QuantBounds& qb, const Aabb& cell, float tmin,
                             float tmax) {
#if defined(OCT_HOST_SSE)
    return boundsHitSse(lr.sse, qb, cell, tmin, tmax);
#else
    float t0, t1;
    return intersectBox(lr.slabs, dequantize(qb, cell), tmin, tmax, t0, t1);
#endif
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

// The box of the parent at each level of the walk below. CUDA keeps none and halves it again
// from the root along the key when the walk goes back up (compactCellBox): 24 bytes a level
// would be 504 bytes of local memory a thread, the GPU budget (docs/PERFORMANCE.md, "GPU
// budget"). The host has the stack to spare and keeps them: the re-derivation was 3.4 % of a
// trace's instructions (docs/PERFORMANCE.md, "Kernel choices"). The same bits either way: the
// kept box is the one the builder's halving gave on the way down.
struct CompactLevelBoxes {
#if !defined(__CUDA_ARCH__)
    Aabb box[kMaxOctreeDepth];
#endif
    OCT_HD void keep(int depth, const Aabb& b) {
#if !defined(__CUDA_ARCH__)
        box[depth] = b;
#else
        (void)depth;
        (void)b;
#endif
    }
    OCT_HD Aabb recall(const Aabb& rootBox, uint64_t key, int depth) const {
#if !defined(__CUDA_ARCH__)
        (void)rootBox;
        (void)key;
        return box[depth];
#else
        return compactCellBox(rootBox, key, depth);
#endif
    }
};

// The entry t of every child tested at each level of the walk, as childIntervals wrote them.
// The host keeps them (32 bytes a level), so a child whose turn comes after the closest hit has
// moved in front of it is dropped by one compare, before its bounds test (which would drop it
// too, a cell's bounds being entered no earlier than the cell: the same decisions, fewer
// instructions; docs/PERFORMANCE.md, "Kernel choices"). CUDA keeps none, the GPU budget again,
// and its bounds test decides alone. One row more than the levels: a corrupt record below the
// deepest level is tested before the walk's depth check refuses it.
struct CompactLevelEntries {
#if !defined(__CUDA_ARCH__)
    static constexpr bool kKept = true;
    float t[kMaxOctreeDepth + 1][8];
    // Where childIntervals writes the entries of level `level` (`scratch` where none are kept).
    OCT_HD float* row(int level, float* /*scratch*/) { return t[level]; }
    OCT_HD float entry(int level, int octant) const { return t[level][octant]; }
#else
    static constexpr bool kKept = false;
    OCT_HD float* row(int /*level*/, float* scratch) { return scratch; }
    OCT_HD float entry(int /*level*/, int /*octant*/) const { return INFINITY; }  // not called
#endif
};

// Traversal with one 8-byte entry a level (after Laine & Karras 2010, ESVO, whose stack is one
// parent a level): the internal node's first child and masks, and which hit children are left.
// Boxes are not kept: the current level's parent box is held, a child's box is halved from it
// when the child's turn comes, and on going back up a level the parent's box is halved again
// from the root along the key (compactCellBox). The nearest child is visited straight away;
// a later one's entry t is recomputed from its box, the slab test's own bits (childIntervals'
// comment), or on the host read from where its test left it (CompactLevelEntries).
// 21 levels x 8 bytes = 168 bytes, against a
// 36-byte box and entry a pushed child (155 of them, 5.6 KB) before.
//
// A level entry is the parent's own record (CompactNode, internal form), its zero bits 16-23
// holding the hit children not yet visited, in front-to-back position j (octant j ^ dirMask),
// so a child's record and leaf bit come from it as from the record (compactChildIndex).
template <bool kAnyHit, class Obs>
OCT_HD inline Hit traverseCompact(const CompactOctreeView& v, const Ray& r, TraceCost& cost,
                                  Obs& obs) {
    constexpr bool kSilent = std::is_same<Obs, NoObserver>::value;
    // The root's cell is tested with the slabs alone: half the rays of a camera around a scan
    // miss it, and the triangle test's shear (prepareRay) is made only for the rest. prepareRay
    // makes the slabs again: handing these on to it compiled to a walk slower for every ray
    // that meets the cell (docs/PERFORMANCE.md, "Kernel choices").
    const RaySlabs rootSlabs = makeRaySlabs(r.org, r.dir);
    Hit best = initialHit(r);
    CompactNode level[kMaxOctreeDepth];  // the internal node of each level, children left above
    int levels = 0;
    // Where a child's entry t comes from when its turn comes: kept at its test (host, no
    // observer, closest hit), or recomputed from its box (an observer's walk, the check of the
    // kept value; CUDA where there are no bounds to decide alone). An any-hit walk keeps none:
    // its closest hit stays at tmax until the first hit ends the walk, so no kept entry would
    // ever drop a child there.
    constexpr bool kEntriesKept = kSilent && !kAnyHit && CompactLevelEntries::kKept;
    CompactLevelEntries entries;

    // Bit a set when the ray runs towards -a: octant order j ^ dirMask is front to back.
    const int dirMask =
        (r.dir.x < 0.0f ? 1 : 0) | (r.dir.y < 0.0f ? 2 : 0) | (r.dir.z < 0.0f ? 4 : 0);
    float tEnter, t1;
    ++cost.nodesVisited;
    if (v.nodes.count == 0) {
        obs.childSkipped(kRootKey, SkipReason::Absent);
        return missHit();
    }
    const bool rootHit = intersectBox(rootSlabs, v.rootBox, r.tmin, r.tmax, tEnter, t1);
    obs.boxTested(kRootKey, 0, v.rootBox, rootHit, tEnter, t1);
    if (!rootHit) return missHit();
    PreparedRay q = prepareRay(r);
    const compact_detail::LaneRay lanes = compact_detail::makeLaneRay(q.slabs);

    // The node to visit: its record, whether it is a leaf, key, depth and cell; and the box of
    // the parent at the deepest level (levelBox, of depth levels - 1 when levels > 0).
    uint32_t index = 0;
    bool leaf = v.rootIsLeaf != 0;
    uint64_t key = kRootKey;
    int depth = 0;
    Aabb box = v.rootBox, levelBox = v.rootBox;
    int levelBoxDepth = -1;
    CompactLevelBoxes kept;
    for (;;) {
        // Entered beyond the closest hit: nothing nearer below. On CUDA without an observer and
        // with bounds, the bounds test below decides it alone (the bounds lie within the cell, so
        // a cell entered beyond the hit has bounds entered beyond it too); the host compares the
        // kept entry first (CompactLevelEntries).
        if ((kEntriesKept || !kSilent || v.bounds.count == 0) && tEnter > best.t) {
            obs.nodePopped(key, tEnter, false);
        } else if (v.bounds.count != 0 &&
                   !compact_detail::boundsHit(lanes, loadReadOnly(v.bounds.data + index), box,
                                              r.tmin, best.t)) {
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
                float scratch[8], exit[8];
                float* const enter = entries.row(levels, scratch);
                uint32_t hitMask =
                    compact_detail::childIntervals(lanes, box, r.tmin, best.t, enter, exit);
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
                    kept.keep(depth, box);
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
            levelBox = kept.recall(v.rootBox, parentKey, parentDepth);
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
        if (kEntriesKept)
            tEnter = entries.entry(parentDepth, i);
        else if (!kSilent || v.bounds.count == 0)  // the same bits as its test among its siblings
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
