// Axis-aligned box and the ray-box slab test (Kay & Kajiya 1986, in the form of Williams et
// al. 2005), written so that zero direction components and origins inside the box are exact.
#pragma once

#include "core/geometry/vec3.h"

namespace oct {

struct Aabb {
    Vec3 lo;  // 12 bytes
    Vec3 hi;  // 12 bytes

    OCT_HD Vec3 center() const { return (lo + hi) * 0.5f; }
    OCT_HD Vec3 extent() const { return hi - lo; }
    OCT_HD bool contains(Vec3 p) const {
        return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z &&
               p.z <= hi.z;
    }
};
static_assert(sizeof(Aabb) == 24, "Aabb is two Vec3");

// An empty box that any grow() replaces.
inline Aabb emptyAabb() {
    return {{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
}
// The same box as vmin/vmax would give (fminf/fmaxf keep their first operand on a tie, and a
// NaN point never replaces a bound), by compare and select, which GCC inlines and vectorises
// instead of calling libm: Scene::bounds over a million triangles is called a few dozen times
// per certify run.
inline void grow(Aabb& b, Vec3 p) {
    b.lo = {p.x < b.lo.x ? p.x : b.lo.x, p.y < b.lo.y ? p.y : b.lo.y, p.z < b.lo.z ? p.z : b.lo.z};
    b.hi = {b.hi.x < p.x ? p.x : b.hi.x, b.hi.y < p.y ? p.y : b.hi.y, b.hi.z < p.z ? p.z : b.hi.z};
}

// Child i of a box split at its centre. Bit 0 of i selects the upper half in x, bit 1 in y,
// bit 2 in z: the same digit the Morton key appends (see morton.h).
OCT_HD inline Aabb childBox(const Aabb& parent, int i) {
    Vec3 c = parent.center();
    Aabb b;
    b.lo.x = (i & 1) ? c.x : parent.lo.x;
    b.hi.x = (i & 1) ? parent.hi.x : c.x;
    b.lo.y = (i & 2) ? c.y : parent.lo.y;
    b.hi.y = (i & 2) ? parent.hi.y : c.y;
    b.lo.z = (i & 4) ? c.z : parent.lo.z;
    b.hi.z = (i & 4) ? parent.hi.z : c.z;
    return b;
}

// Reciprocal direction prepared once per ray. A zero component gives +-inf, which the slab
// test below handles without NaN because the origin-outside-slab case is tested separately.
constexpr float kSlabFarScale = 1.0000004f;  // 1 + 2 * gamma(3), gamma(n) = n*u / (1 - n*u)

struct RaySlabs {
    Vec3 org;
    Vec3 inv;
};

OCT_HD inline RaySlabs makeRaySlabs(Vec3 o, Vec3 d) {
    return {o, {1.0f / d.x, 1.0f / d.y, 1.0f / d.z}};
}

// Intersects [tmin, tmax] with the box's slabs. Returns true and the clipped interval when the
// ray's segment meets the box (touching counts). For a zero direction component the ray is
// parallel to that slab: it is inside for all t when the origin lies within the slab, else
// never; (lo - o) * inf would give NaN when lo == o, so that axis is decided explicitly.
OCT_HD inline bool intersectSlab(float o, float inv, float lo, float hi, float& t0, float& t1) {
    if (std::isinf(inv)) return o >= lo && o <= hi;
    float ta = (lo - o) * inv;
    float tb = (hi - o) * inv;
    float tNear = minf(ta, tb);
    // Ize 2013, "Robust BVH Ray Traversal": scaling the far distance by 1 + 2*gamma(3) makes the
    // rounded slab interval contain the exact one, so a ray grazing a node's face is never culled.
    float tFar = maxf(ta, tb) * kSlabFarScale;
    t0 = maxf(t0, tNear);
    t1 = minf(t1, tFar);
    return true;
}

OCT_HD inline bool intersectBox(const RaySlabs& r, const Aabb& b, float tmin, float tmax,
                                float& tEnter, float& tExit) {
    float t0 = tmin, t1 = tmax;
    if (!intersectSlab(r.org.x, r.inv.x, b.lo.x, b.hi.x, t0, t1)) return false;
    if (!intersectSlab(r.org.y, r.inv.y, b.lo.y, b.hi.y, t0, t1)) return false;
    if (!intersectSlab(r.org.z, r.inv.z, b.lo.z, b.hi.z, t0, t1)) return false;
    tEnter = t0;
    tExit = t1;
    return t0 <= t1;
}

// The near end of intersectBox's interval, for a box the ray is known to meet (its slabs all
// admit the ray: the traversal re-deriving the entry t of a child it tested before): the same
// operations on the same values, so the same bits, without the far end.
OCT_HD inline float boxEntry(const RaySlabs& r, const Aabb& b, float tmin) {
    float t0 = tmin;
    if (!std::isinf(r.inv.x))
        t0 = maxf(t0, minf((b.lo.x - r.org.x) * r.inv.x, (b.hi.x - r.org.x) * r.inv.x));
    if (!std::isinf(r.inv.y))
        t0 = maxf(t0, minf((b.lo.y - r.org.y) * r.inv.y, (b.hi.y - r.org.y) * r.inv.y));
    if (!std::isinf(r.inv.z))
        t0 = maxf(t0, minf((b.lo.z - r.org.z) * r.inv.z, (b.hi.z - r.org.z) * r.inv.z));
    return t0;
}

}  // namespace oct
