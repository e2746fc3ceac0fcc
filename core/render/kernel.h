// The one per-pixel function of octrace. The OpenMP backend (cpu_ref/) calls it in a parallel
// loop, the CUDA backend (gpu/) from a __global__ function, one thread per pixel; Embree's
// backend passes an accelerator whose hit queries call Embree. Everything else is this code.
#pragma once

#include <cstdint>
#include <cstring>

#include "core/geometry/primitives_view.h"
#include "core/geometry/ray.h"
#include "core/octree/traversal_observer.h"
#include "core/render/camera.h"
#include "core/render/film.h"

namespace oct {

// Geometric normal at a hit, facing the incoming ray.
OCT_HD inline Vec3 hitNormal(const PrimitivesView& p, int32_t prim, Vec3 pos, Vec3 dir) {
    Vec3 n;
    if (p.kind == PrimKind::Triangles) {
        const Triangle& t = loadReadOnly(p.tris + prim);  // as every primitive read (platform.h)
        n = cross(t.v1 - t.v0, t.v2 - t.v0);
    } else {
        n = pos - loadReadOnly(p.spheres + prim).center;
    }
    n = normalize(n);
    return dot(n, dir) > 0.0f ? -n : n;
}

// x^32 by five squarings: exactly the same bits on host and device (powf is not).
OCT_HD inline float pow32(float x) {
    x *= x;
    x *= x;
    x *= x;
    x *= x;
    return x * x;
}

OCT_HD inline uint8_t toByte(float c) {
    c = fminf(fmaxf(c, 0.0f), 1.0f);
    return static_cast<uint8_t>(c * 255.0f + 0.5f);
}

// The shadow ray: from the hit point, lifted along the normal, towards the light; anything
// between (excluding the light itself) occludes.
OCT_HD inline Ray shadowRay(Vec3 pos, Vec3 normal, const ShadingParams& s, float& lightDist) {
    Vec3 origin = pos + normal * s.shadowBias;
    Vec3 toLight = s.light - origin;
    lightDist = length(toLight);
    return {origin, toLight * (1.0f / lightDist), 0.0f, lightDist};
}

// Everything the kernel derives from a primary hit before shading it. Written once: the kernel
// and every check that rebuilds a pixel's shadow ray (validation, `octrace rays`) call this.
struct ShadowQuery {
    Ray ray;       // towards the light, tmax = the light's distance
    Vec3 normal;   // geometric normal facing the primary ray
    float facing;  // dot(normal, ray.dir)
    bool cast;     // false: the surface faces away from the light, unlit without asking
};

OCT_HD inline ShadowQuery shadowQuery(const ShadingParams& s, const PrimitivesView& prims,
                                      const Ray& primary, Hit hit) {
    ShadowQuery q;
    Vec3 pos = primary.org + primary.dir * hit.t;
    q.normal = hitNormal(prims, hit.prim, pos, primary.dir);
    float lightDist;
    q.ray = shadowRay(pos, q.normal, s, lightDist);
    q.facing = dot(q.normal, q.ray.dir);
    q.cast = q.facing > 0.0f;
    return q;
}

OCT_HD inline Vec3 phong(const ShadingParams& s, Vec3 normal, Vec3 toLight, Vec3 dir,
                         bool shadowed) {
    Vec3 c = s.surfaceColour * s.ambient;
    if (shadowed) return c;
    float nl = dot(normal, toLight);
    if (nl <= 0.0f) return c;
    Vec3 reflected = normal * (2.0f * nl) - toLight;
    float rv = fmaxf(0.0f, dot(reflected, -dir));
    return c + s.surfaceColour * (s.diffuse * nl) + makeVec3(s.specular * pow32(rv));
}

// Everything one pixel's rays produce, before it is written to the Film.
struct PixelSample {
    Ray primary;
    Hit hit;
    ShadowQuery shadowQuery;  // defined when hit.prim >= 0
    uint8_t shadow;           // kNoShadowRay, kLit or kOccluded
    Vec3 colour;
    TraceCost cost;  // primary and shadow ray together
};

// The pixel's primary ray, closest hit, shadow ray and Phong colour. `primaryObs` and
// `shadowObs` see each traversal step (traversal_observer.h): `octrace explain` records them,
// renderPixel passes NoObserver, so explain reports exactly the kernel's steps and costs.
template <class Accel, class Obs>
OCT_HD inline PixelSample tracePixel(int x, int y, const FrameParams& p, const Accel& accel,
                                     const PrimitivesView& prims, Obs& primaryObs, Obs& shadowObs) {
    PixelSample s;
    s.primary = primaryRay(p.camera, x, y, p.width, p.height);
    s.cost = {0, 0};
    s.hit = closestHit(accel, s.primary, s.cost, primaryObs);
    s.colour = p.shading.background;
    s.shadow = kNoShadowRay;
    if (s.hit.prim >= 0) {
        s.shadowQuery = shadowQuery(p.shading, prims, s.primary, s.hit);
        const ShadowQuery& sq = s.shadowQuery;
        if (sq.cast) s.shadow = anyHit(accel, sq.ray, s.cost, shadowObs) ? kOccluded : kLit;
        s.colour = phong(p.shading, sq.normal, sq.ray.dir, s.primary.dir, s.shadow == kOccluded);
    }
    return s;
}

template <class Accel>
OCT_HD inline void renderPixel(int x, int y, const FrameParams& p, const Accel& accel,
                               const PrimitivesView& prims, FilmView film) {
    int idx = filmRowOf(p, y) * film.width + x;  // the band's row (camera.h)
    NoObserver none;
    const PixelSample s = tracePixel(x, y, p, accel, prims, none, none);
    film.rgb[3 * idx + 0] = toByte(s.colour.x);
    film.rgb[3 * idx + 1] = toByte(s.colour.y);
    film.rgb[3 * idx + 2] = toByte(s.colour.z);
    film.t[idx] = s.hit.t;
    film.prim[idx] = s.hit.prim;
    film.nodes[idx] = s.cost.nodesVisited;
    film.primsTested[idx] = s.cost.primsTested;
    film.shadow[idx] = s.shadow;
}

// One ray of a user's ray set (octrace trace): closest hit with t in [tmin, tmax].
struct RayBatchView {
    const float* rays;  // N x 8 floats: ox oy oz dx dy dz tmin tmax
    float* t;           // N, +inf on a miss
    int32_t* prim;      // N, -1 on a miss
    uint64_t count;
    // Optional, N each (null: not written): the ray's traversal cost, node boxes tested and
    // ray-primitive tests (the Python module's cast_rays; trace writes neither). A backend with
    // its own structure (Embree) counts none: it writes zeros.
    uint32_t* nodes = nullptr;
    uint32_t* primsTested = nullptr;
};

// The ray's direction is scaled by the power of two 2^-e that brings its largest component into
// [0.5, 1), tmin and tmax by 2^e, and the hit's t back by 2^-e. Only exponents change, so this
// is exact: every tracer answers in the same bits as for the ray as given, except where the
// ray as given would overflow float inside the tests (the triangle test's t * det grows as
// 1 / |d|; Embree asserts |d| <= 1.8e19). The ray reader (core/io/ray_file.h) keeps the largest
// component within [1e-19, 1e19], so e is within [-63, 64] and t stays a normal float for any
// hit in the numeric range (core/geometry/numeric_range.h). A tmin or tmax past float range
// after scaling becomes +inf or 0 exactly where no hit of the scene can lie.
// The scaling is a multiplication by a float power of two, built from its exponent bits:
// correctly rounded like ldexpf (the same bits, overflow and underflow included), without a
// libm call per ray (docs/PERFORMANCE.md, "Kernel choices"). A largest
// component outside the normal exponents the fast form covers takes ldexpf.
OCT_HD inline float powerOfTwo(int k) {  // 2^k, k in [-126, 127]
    const uint32_t bits = uint32_t(k + 127) << 23;
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

// The ray traceRayAt traces for row r of a ray set (the scaling above); `e` receives the
// exponent, so that a t found on it is unscaledT(t, e) in the units of the row's direction.
// `octrace explain --ray` starts from the same ray, so it explains what trace traced.
OCT_HD inline Ray scaledRay(const float* r, int& e) {
    const float largest = fmaxf(fabsf(r[3]), fmaxf(fabsf(r[4]), fabsf(r[5])));
    uint32_t bits;
    memcpy(&bits, &largest, sizeof bits);
    const int biased = int((bits >> 23) & 0xffu);  // largest = 1.m * 2^(biased - 127)
    e = biased - 126;                              // frexpf's exponent: mantissa in [0.5, 1)
    Ray ray;
    ray.org = {r[0], r[1], r[2]};
    if (e >= -120 && e <= 120) {
        const float down = powerOfTwo(-e), up = powerOfTwo(e);
        ray.dir = {r[3] * down, r[4] * down, r[5] * down};
        ray.tmin = r[6] * up;
        ray.tmax = r[7] * up;
        return ray;
    }
    frexpf(largest, &e);
    ray.dir = {ldexpf(r[3], -e), ldexpf(r[4], -e), ldexpf(r[5], -e)};
    ray.tmin = ldexpf(r[6], e);
    ray.tmax = ldexpf(r[7], e);
    return ray;
}

// t on scaledRay's ray, back in the units of the row's direction.
OCT_HD inline float unscaledT(float t, int e) {
    return e >= -120 && e <= 120 ? t * powerOfTwo(-e) : ldexpf(t, -e);
}

template <class Accel>
OCT_HD inline void traceRayAt(uint64_t i, const Accel& accel, RayBatchView batch) {
    int e = 0;
    const Ray ray = scaledRay(batch.rays + 8 * i, e);
    TraceCost cost = {0, 0};
    const Hit hit = closestHit(accel, ray, cost);
    batch.t[i] = unscaledT(hit.t, e);
    batch.prim[i] = hit.prim;
    if (batch.nodes) batch.nodes[i] = cost.nodesVisited;
    if (batch.primsTested) batch.primsTested[i] = cost.primsTested;
}

}  // namespace oct
