// The two primitive kinds of the paper: triangles (meshes) and spheres (point clouds, each point
// a sphere of radius R), and the per-ray intersection routines used by every layout.
#pragma once

#include <cstdint>

#include "core/geometry/aabb.h"
#include "core/geometry/vec3.h"
#include "core/geometry/vec3t.h"

namespace oct {

// Which of the two a scene (and every view of its primitives a kernel receives) holds.
enum class PrimKind : uint8_t { Triangles = 0, Spheres = 1 };

struct Triangle {
    Vec3 v0, v1, v2;  // 36 bytes
};
static_assert(sizeof(Triangle) == 36, "Triangle is three packed vertices");

// The triangle's box: the float bounds of its vertices (host code: the builder, the BVH).
inline Aabb boundsOf(const Triangle& t) {
    Aabb b = emptyAabb();
    grow(b, t.v0);
    grow(b, t.v1);
    grow(b, t.v2);
    return b;
}

struct Sphere {
    Vec3 center;   // 12 bytes
    float radius;  // 4 bytes
};
static_assert(sizeof(Sphere) == 16, "Sphere is centre + radius");

// Ray prepared for the watertight test of Woop, Benthin and Wald, "Watertight Ray/Triangle
// Intersection", JCGT 2(1), 2013: the ray is sheared so that it points along +z, which makes
// the edge tests exact sign tests shared by neighbouring triangles (no cracks at edges).
struct ShearedRay {
    Vec3 org;
    int kx, ky, kz;  // permutation making |dir[kz]| the largest component
    float sx, sy, sz;
};

OCT_HD inline ShearedRay makeShearedRay(Vec3 org, Vec3 dir) {
    ShearedRay r;
    r.org = org;
    float ax = fabsf(dir.x), ay = fabsf(dir.y), az = fabsf(dir.z);
    r.kz = (ax > ay) ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
    r.kx = r.kz + 1 == 3 ? 0 : r.kz + 1;
    r.ky = r.kx + 1 == 3 ? 0 : r.kx + 1;
    if (dir[r.kz] < 0.0f) {  // keep the winding so the sign tests below stay the same
        int t = r.kx;
        r.kx = r.ky;
        r.ky = t;
    }
    r.sx = dir[r.kx] / dir[r.kz];
    r.sy = dir[r.ky] / dir[r.kz];
    r.sz = 1.0f / dir[r.kz];
    return r;
}

// The hit recomputed in double by the same steps as intersectTriangle (translate, shear, edge
// functions, scaled distance), on the same float inputs: for a hit whose float t is
// ill-conditioned (a sliver, a grazing ray), see intersectTriangle. False when the double
// determinant is zero (the ray in the plane: Woop et al.'s miss) and, with `decide`, when the
// double edge functions have mixed signs (the ray passes outside).
OCT_HD inline bool triangleTInDouble(const ShearedRay& r, const Triangle& tri, bool decide,
                                     double& t) {
    const Vec3 v[3] = {tri.v0, tri.v1, tri.v2};
    double x[3], y[3], z[3];
    for (int i = 0; i < 3; ++i) {
        const double pz = double(v[i][r.kz]) - double(r.org[r.kz]);
        x[i] = (double(v[i][r.kx]) - double(r.org[r.kx])) - double(r.sx) * pz;
        y[i] = (double(v[i][r.ky]) - double(r.org[r.ky])) - double(r.sy) * pz;
        z[i] = double(r.sz) * pz;
    }
    const double u = x[2] * y[1] - y[2] * x[1];
    const double w = x[1] * y[0] - y[1] * x[0];
    const double v2 = x[0] * y[2] - y[0] * x[2];
    if (decide && (u < 0.0 || v2 < 0.0 || w < 0.0) && (u > 0.0 || v2 > 0.0 || w > 0.0))
        return false;
    const double det = u + v2 + w;
    if (det == 0.0) return false;
    t = (u * z[0] + v2 * z[1] + w * z[2]) / det;
    return true;
}

// Whether the ray lies in the triangle's plane to within the rounding of its direction:
// |cos(d, n)| <= 2^-21 (8 float ulps), the normal and the sheared direction (sx, sy, 1) in
// double, so that a sliver's ill-conditioned float normal does not count.
OCT_HD inline bool rayInPlane(const ShearedRay& r, const Triangle& tri) {
    const DVec3 n = cross(toDouble(tri.v1) - toDouble(tri.v0), toDouble(tri.v2) - toDouble(tri.v0));
    // The sheared direction back in x, y, z order: component kx is sx, ky is sy, kz is 1.
    const auto along = [&r](int axis) {
        return axis == r.kx ? double(r.sx) : axis == r.ky ? double(r.sy) : 1.0;
    };
    const DVec3 dir{along(0), along(1), along(2)};
    const double nd = dot(n, dir);
    return nd * nd <= 0x1p-42 * dot(n, n) * dot(dir, dir);
}

// The relative error of t above which intersectTriangle recomputes it in double: 2^-20, some
// 16 float ulps, where a well-shaped triangle's t is off by a few.
constexpr float kTriangleRefine = 0x1p-20f;

// Returns true and the distance t when the ray hits the triangle with tmin <= t <= tmax.
// Both faces count. Edge functions that are exactly zero are recomputed in double, as Woop,
// Benthin & Wald (2013) prescribe, so a ray through a shared edge hits at least one of the two.
// Which triangles are hit is decided in float, so that two triangles sharing an edge compute
// its edge function alike (watertightness); only a ray in the triangle's plane to within
// rounding is decided in double. The distance of a hit is recomputed in double when its float
// error bound exceeds kTriangleRefine relative: the edge functions' error (Pharr,
// Jakob & Humphreys, PBRT 3rd ed., sec. 3.9.6: delta_e, grown by the sheared z as shear and
// translation round) moves t by at most 3 delta_e / |det| times the vertices' spread in z
// around t, which slivers and grazing rays make large (docs/VALIDATION.md, "The surface
// bound").
OCT_HD inline bool intersectTriangle(const ShearedRay& r, const Triangle& tri, float tmin,
                                     float tmax, float& tHit) {
    // const: the run-time indexed reads below take Vec3's const operator[] (one indexed load on
    // the host, vec3.h), not the select chain of the writable one.
    const Vec3 a = tri.v0 - r.org, b = tri.v1 - r.org, c = tri.v2 - r.org;
    float ax = a[r.kx] - r.sx * a[r.kz], ay = a[r.ky] - r.sy * a[r.kz];
    float bx = b[r.kx] - r.sx * b[r.kz], by = b[r.ky] - r.sy * b[r.kz];
    float cx = c[r.kx] - r.sx * c[r.kz], cy = c[r.ky] - r.sy * c[r.kz];
    float u = cx * by - cy * bx;
    float v = ax * cy - ay * cx;
    float w = bx * ay - by * ax;
    if (u == 0.0f || v == 0.0f || w == 0.0f) {
        u = (float)((double)cx * (double)by - (double)cy * (double)bx);
        v = (float)((double)ax * (double)cy - (double)ay * (double)cx);
        w = (float)((double)bx * (double)ay - (double)by * (double)ax);
    }
    if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return false;
    float det = u + v + w;
    if (det == 0.0f) return false;  // degenerate in the ray's projection, or the ray in its plane
    float az = r.sz * a[r.kz], bz = r.sz * b[r.kz], cz = r.sz * c[r.kz];
    float tScaled = u * az + v * bz + w * cz;
    tHit = tScaled / det;
    // The error estimate, in float without another division: 3 delta_e x the spread of z around
    // t against kTriangleRefine x |t det|. gamma(n) ~ n 2^-24 (the 1 - n u denominators only
    // round it). An ill-conditioned t is judged against the range only once recomputed, so that
    // the order primitives are tested in cannot change which of two at the same t is kept.
    const float maxX = maxf(maxf(fabsf(ax), fabsf(bx)), fabsf(cx));
    const float maxY = maxf(maxf(fabsf(ay), fabsf(by)), fabsf(cy));
    const float maxZ = maxf(maxf(fabsf(az), fabsf(bz)), fabsf(cz));
    const float spread = maxf(maxf(fabsf(az - tHit), fabsf(bz - tHit)), fabsf(cz - tHit));
    const float eps = 0x1p-24f;
    const float dx = 5.0f * eps * (maxX + maxZ), dy = 5.0f * eps * (maxY + maxZ);
    const float de = 2.0f * (2.0f * eps * maxX * maxY + dy * maxX + dx * maxY);
    if (3.0f * de * spread > kTriangleRefine * fabsf(tScaled)) {
        // Ill-conditioned. A ray in the triangle's plane to within rounding projects it onto a
        // segment through the origin: the float signs are noise, so the double decides (a hit
        // was once reported at the plane's crossing, 12 ulps off the triangle). Elsewhere, a
        // sliver included, the float decision stands, shared with the neighbours.
        double t;
        if (!triangleTInDouble(r, tri, rayInPlane(r, tri), t)) return false;
        tHit = float(t);
    } else if (det < 0.0f) {
        // Compare t*det against the range as the paper does (the division above is only used
        // once this passes).
        if (tScaled > tmin * det || tScaled < tmax * det) return false;
    } else {
        if (tScaled < tmin * det || tScaled > tmax * det) return false;
    }
    // tScaled grows as the cube of the coordinates: past float range it is +inf and so is tHit,
    // which the range test above lets through when tmax is +inf. Never a hit at +inf (inside
    // the numeric range of numeric_range.h it cannot happen; outside it, no answer is a lie).
    return tHit >= tmin && tHit <= tmax && tHit < INFINITY;
}

// Ray-sphere in the numerically careful form of Haines et al., "Precision Improvements for
// Ray/Sphere Intersection" (Ray Tracing Gems, ch. 7): the discriminant is computed from the
// closest-approach vector, and the two roots from the stable quadratic formula. The nearest
// root inside [tmin, tmax] is returned; a ray starting inside the sphere hits its far side.
OCT_HD inline bool intersectSphere(Vec3 org, Vec3 dir, const Sphere& s, float tmin, float tmax,
                                   float& tHit) {
    Vec3 f = org - s.center;
    float a = dot(dir, dir);
    float bPrime = -dot(f, dir);
    Vec3 l = f + dir * (bPrime / a);
    float r2 = s.radius * s.radius;
    float disc = r2 - dot(l, l);
    if (disc < 0.0f) return false;
    float c = dot(f, f) - r2;
    float q = bPrime + copysignf(sqrtf(a * disc), bPrime);
    float t0, t1;
    if (q == 0.0f) {  // origin at the centre's tangent point: both roots at zero
        t0 = t1 = 0.0f;
    } else {
        t0 = c / q;
        t1 = q / a;
    }
    if (t0 > t1) {
        float t = t0;
        t0 = t1;
        t1 = t;
    }
    // An overflowed c or q makes a root +inf: never a hit there (see intersectTriangle).
    if (t0 >= tmin && t0 <= tmax && t0 < INFINITY) {
        tHit = t0;
        return true;
    }
    if (t1 >= tmin && t1 <= tmax && t1 < INFINITY) {
        tHit = t1;
        return true;
    }
    return false;
}

}  // namespace oct
