// The one per-pixel function of octrace. The OpenMP backend (cpu_ref/) calls it in a parallel
// loop, the CUDA backend (gpu/) from a __global__ function, one thread per pixel; Embree's
// backend passes an accelerator whose hit queries call Embree. Everything else is this code.
#pragma once

#include "core/octree/traversal.h"
#include "core/render/camera.h"
#include "core/render/film.h"

namespace oct {

// Geometric normal at a hit, facing the incoming ray.
OCT_HD inline Vec3 hitNormal(const PrimitivesView& p, int32_t prim, Vec3 pos, Vec3 dir) {
    Vec3 n;
    if (p.kind == PrimKind::Triangles) {
        const Triangle& t = p.tris[prim];
        n = cross(t.v1 - t.v0, t.v2 - t.v0);
    } else {
        n = pos - p.spheres[prim].center;
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

template <class Accel>
OCT_HD inline void renderPixel(int x, int y, const FrameParams& p, const Accel& accel,
                               const PrimitivesView& prims, FilmView film) {
    int idx = y * film.width + x;
    Ray ray = primaryRay(p.camera, x, y, p.width, p.height);
    TraceCost cost = {0, 0};
    Hit hit = closestHit(accel, ray, cost);
    Vec3 colour = p.shading.background;
    uint8_t shadow = kNoShadowRay;
    if (hit.prim >= 0) {
        Vec3 pos = ray.org + ray.dir * hit.t;
        Vec3 n = hitNormal(prims, hit.prim, pos, ray.dir);
        float lightDist;
        Ray sray = shadowRay(pos, n, p.shading, lightDist);
        // A surface facing away from the light is unlit without asking: no shadow ray.
        if (dot(n, sray.dir) > 0.0f) shadow = anyHit(accel, sray, cost) ? kOccluded : kLit;
        colour = phong(p.shading, n, sray.dir, ray.dir, shadow == kOccluded);
    }
    film.rgb[3 * idx + 0] = toByte(colour.x);
    film.rgb[3 * idx + 1] = toByte(colour.y);
    film.rgb[3 * idx + 2] = toByte(colour.z);
    film.t[idx] = hit.t;
    film.prim[idx] = hit.prim;
    film.nodes[idx] = cost.nodesVisited;
    film.primsTested[idx] = cost.primsTested;
    film.shadow[idx] = shadow;
}

// One ray of a user's ray set (octrace trace): closest hit with t in [tmin, tmax].
struct RayBatchView {
    const float* rays;  // N x 8 floats: ox oy oz dx dy dz tmin tmax
    float* t;           // N, +inf on a miss
    int32_t* prim;      // N, -1 on a miss
    uint64_t count;
};

template <class Accel>
OCT_HD inline void traceRayAt(uint64_t i, const Accel& accel, RayBatchView batch) {
    const float* r = batch.rays + 8 * i;
    Ray ray = {{r[0], r[1], r[2]}, {r[3], r[4], r[5]}, r[6], r[7]};
    TraceCost cost = {0, 0};
    Hit hit = closestHit(accel, ray, cost);
    batch.t[i] = hit.t;
    batch.prim[i] = hit.prim;
}

}  // namespace oct
