// Four ray-triangle tests at once in SSE registers, for a leaf's list on the host: the common
// work of intersectTriangle (primitives.h) for four triangles, lane for lane the same operations
// on the same values in the same order (no contraction: the build compiles with
// -ffp-contract=off), so the same bits. What the batch leaves to the caller, in list order, is
// what depends on earlier hits (the range test against the closest hit so far) and the rare
// lanes intersectTriangle decides in double (an edge function exactly zero, an ill-conditioned
// t): those take intersectTriangle itself. CUDA's device pass and WebAssembly test one triangle
// a thread as before (leaf_list.h).
#pragma once

#include "core/geometry/primitives.h"

#if defined(__SSE2__) && !defined(__CUDA_ARCH__) && !defined(OCT_SCALAR_LANES)
#include <immintrin.h>
#define OCT_TRIANGLE_BATCH 1
#endif

namespace oct {

#if defined(OCT_TRIANGLE_BATCH)

// What a lane of the batch says about its triangle.
enum class LaneVerdict : uint8_t {
    Miss = 0,    // outside the triangle, or degenerate in the ray's projection: no hit at any t
    Range = 1,   // inside: a hit iff rangeHit(tScaled, det, tHit, tmin, tmax)
    Scalar = 2,  // intersectTriangle decides it (double precision on this lane)
};

struct TriangleBatch {
    float tScaled[4], det[4], tHit[4];
    LaneVerdict verdict[4];
};

// The ray's broadcasts, made once a leaf.
struct ShearedLanes {
    __m128 org[3];
    __m128 sx, sy, sz;
};

inline ShearedLanes makeShearedLanes(const ShearedRay& r) {
    return {{_mm_set1_ps(r.org.x), _mm_set1_ps(r.org.y), _mm_set1_ps(r.org.z)},
            _mm_set1_ps(r.sx),
            _mm_set1_ps(r.sy),
            _mm_set1_ps(r.sz)};
}

// Vertex `which` (0, 1, 2) of four triangles as x, y, z lanes. Each row is read with one 16-byte
// load that stays inside its 36-byte triangle (v2 from v1.z on: the array may end there).
inline void vertexLanes(const Triangle* const t[4], int which, __m128 out[3]) {
    __m128 row[4];
    for (int j = 0; j < 4; ++j) {
        const float* f = &t[j]->v0.x;
        if (which == 2) {
            const __m128 v = _mm_loadu_ps(f + 5);  // v1.z v2.x v2.y v2.z
            row[j] = _mm_shuffle_ps(v, v, _MM_SHUFFLE(0, 3, 2, 1));
        } else {
            row[j] = _mm_loadu_ps(f + 3 * which);
        }
    }
    _MM_TRANSPOSE4_PS(row[0], row[1], row[2], row[3]);
    out[0] = row[0];
    out[1] = row[1];
    out[2] = row[2];
}

inline __m128 absLanes(__m128 v) { return _mm_andnot_ps(_mm_set1_ps(-0.0f), v); }
// maxf(a, b) (vec3.h), operand for operand.
inline __m128 maxLanes(__m128 a, __m128 b) { return _mm_max_ps(b, a); }

// intersectTriangle's steps up to its range test, for four triangles (t[j] may repeat: a short
// list fills its batch with its last triangle, whose extra lanes the caller ignores).
inline TriangleBatch intersectTriangles4(const ShearedRay& r, const ShearedLanes& l,
                                         const Triangle* const t[4]) {
    __m128 v[3][3];  // v[vertex][axis]
    for (int k = 0; k < 3; ++k) vertexLanes(t, k, v[k]);
    // a = v0 - org, b = v1 - org, c = v2 - org, then the permutation kx, ky, kz of the ray.
    __m128 d[3][3];
    for (int k = 0; k < 3; ++k)
        for (int a = 0; a < 3; ++a) d[k][a] = _mm_sub_ps(v[k][a], l.org[a]);
    const int kx = r.kx, ky = r.ky, kz = r.kz;
    const __m128 ax = _mm_sub_ps(d[0][kx], _mm_mul_ps(l.sx, d[0][kz]));
    const __m128 ay = _mm_sub_ps(d[0][ky], _mm_mul_ps(l.sy, d[0][kz]));
    const __m128 bx = _mm_sub_ps(d[1][kx], _mm_mul_ps(l.sx, d[1][kz]));
    const __m128 by = _mm_sub_ps(d[1][ky], _mm_mul_ps(l.sy, d[1][kz]));
    const __m128 cx = _mm_sub_ps(d[2][kx], _mm_mul_ps(l.sx, d[2][kz]));
    const __m128 cy = _mm_sub_ps(d[2][ky], _mm_mul_ps(l.sy, d[2][kz]));
    const __m128 u = _mm_sub_ps(_mm_mul_ps(cx, by), _mm_mul_ps(cy, bx));
    const __m128 vv = _mm_sub_ps(_mm_mul_ps(ax, cy), _mm_mul_ps(ay, cx));
    const __m128 w = _mm_sub_ps(_mm_mul_ps(bx, ay), _mm_mul_ps(by, ax));
    const __m128 zero = _mm_setzero_ps();
    // An edge function exactly zero: intersectTriangle recomputes the three in double.
    const __m128 anyZero =
        _mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(u, zero), _mm_cmpeq_ps(vv, zero)), _mm_cmpeq_ps(w, zero));
    const __m128 anyNeg =
        _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(u, zero), _mm_cmplt_ps(vv, zero)), _mm_cmplt_ps(w, zero));
    const __m128 anyPos =
        _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(u, zero), _mm_cmpgt_ps(vv, zero)), _mm_cmpgt_ps(w, zero));
    // Four lanes outside their triangles (an edge function of each sign, none zero): four
    // misses, whatever t and its error would be. Most batches of a walk are so; they skip the
    // division and the error terms (docs/PERFORMANCE.md, "Kernel choices").
    const int outsideNotZero = _mm_movemask_ps(_mm_andnot_ps(anyZero, _mm_and_ps(anyNeg, anyPos)));
    if (outsideNotZero == 15) {
        TriangleBatch miss;
        for (int j = 0; j < 4; ++j) miss.verdict[j] = LaneVerdict::Miss;
        return miss;
    }
    const __m128 det = _mm_add_ps(_mm_add_ps(u, vv), w);
    const __m128 az = _mm_mul_ps(l.sz, d[0][kz]);
    const __m128 bz = _mm_mul_ps(l.sz, d[1][kz]);
    const __m128 cz = _mm_mul_ps(l.sz, d[2][kz]);
    const __m128 tScaled =
        _mm_add_ps(_mm_add_ps(_mm_mul_ps(u, az), _mm_mul_ps(vv, bz)), _mm_mul_ps(w, cz));
    const __m128 tHit = _mm_div_ps(tScaled, det);
    // The error estimate of intersectTriangle, term for term.
    const __m128 maxX = maxLanes(maxLanes(absLanes(ax), absLanes(bx)), absLanes(cx));
    const __m128 maxY = maxLanes(maxLanes(absLanes(ay), absLanes(by)), absLanes(cy));
    const __m128 maxZ = maxLanes(maxLanes(absLanes(az), absLanes(bz)), absLanes(cz));
    const __m128 spread =
        maxLanes(maxLanes(absLanes(_mm_sub_ps(az, tHit)), absLanes(_mm_sub_ps(bz, tHit))),
                 absLanes(_mm_sub_ps(cz, tHit)));
    const __m128 fiveEps = _mm_mul_ps(_mm_set1_ps(5.0f), _mm_set1_ps(0x1p-24f));
    const __m128 twoEps = _mm_mul_ps(_mm_set1_ps(2.0f), _mm_set1_ps(0x1p-24f));
    const __m128 dx = _mm_mul_ps(fiveEps, _mm_add_ps(maxX, maxZ));
    const __m128 dy = _mm_mul_ps(fiveEps, _mm_add_ps(maxY, maxZ));
    const __m128 de = _mm_mul_ps(
        _mm_set1_ps(2.0f),
        _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_mul_ps(twoEps, maxX), maxY), _mm_mul_ps(dy, maxX)),
                   _mm_mul_ps(dx, maxY)));
    const __m128 illConditioned =
        _mm_cmpgt_ps(_mm_mul_ps(_mm_mul_ps(_mm_set1_ps(3.0f), de), spread),
                     _mm_mul_ps(_mm_set1_ps(kTriangleRefine), absLanes(tScaled)));

    TriangleBatch out;
    _mm_storeu_ps(out.tScaled, tScaled);
    _mm_storeu_ps(out.det, det);
    _mm_storeu_ps(out.tHit, tHit);
    const int zeroMask = _mm_movemask_ps(anyZero);
    const int outside =
        _mm_movemask_ps(_mm_and_ps(anyNeg, anyPos)) | _mm_movemask_ps(_mm_cmpeq_ps(det, zero));
    const int ill = _mm_movemask_ps(illConditioned);
    for (int j = 0; j < 4; ++j) {
        const int bit = 1 << j;
        out.verdict[j] = (zeroMask & bit)  ? LaneVerdict::Scalar
                         : (outside & bit) ? LaneVerdict::Miss
                         : (ill & bit)     ? LaneVerdict::Scalar
                                           : LaneVerdict::Range;
    }
    return out;
}

// intersectTriangle's range test for a well-conditioned lane inside its triangle, in its order:
// t * det against the range as the paper does, then the division's result.
inline bool rangeHit(float tScaled, float det, float tHit, float tmin, float tmax) {
    if (det < 0.0f) {
        if (tScaled > tmin * det || tScaled < tmax * det) return false;
    } else {
        if (tScaled < tmin * det || tScaled > tmax * det) return false;
    }
    return tHit >= tmin && tHit <= tmax && tHit < INFINITY;
}

#endif  // OCT_TRIANGLE_BATCH

}  // namespace oct
