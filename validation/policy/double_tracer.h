// The double-precision "truth" of the per-ray recheck: the primitives tested against the ray in
// double, sharing no code with our traversal or our float intersection routines. A BVH in
// double (box_bvh.h) hands each query the primitives it may concern; the per-primitive tests
// decide, exactly as the brute force over every primitive (kept as the tests' oracle) would.
// Besides hit and distance it says how touchy a ray/primitive configuration is: a ray that passes
// within the edge tolerance of a triangle's boundary, grazes its plane, meets a degenerate
// triangle, is tangent to a sphere or ends on the primitive is one whose answer two correct float
// tracers may legitimately disagree on (docs/VALIDATION.md, the per-pixel policy).
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/geometry/ray.h"
#include "core/geometry/vec3t.h"
#include "core/scene/scene.h"
#include "validation/policy/box_bvh.h"

namespace oct {

// Why a mismatch is ambiguous rather than wrong (a bit set; 0 = no reason).
enum AmbiguityReason : uint32_t {
    kEdgeOrVertex = 1u << 0,   // the ray passes within the edge tolerance of a triangle's edge
    kGrazing = 1u << 1,        // |cos(ray, normal)| <= grazing threshold, ray on the triangle
    kDegenerate = 1u << 2,     // triangle's smallest altitude <= edge tolerance
    kTangent = 1u << 3,        // the ray is within the edge tolerance of a sphere's silhouette
    kRangeEnd = 1u << 4,       // the primitive lies within tolerance of the segment's ends
    kReferenceOff = 1u << 5,   // the double truth agrees with ours; the reference differs
    kTerminator = 1u << 6,     // only one tracer cast a shadow ray (surface edge-on to light)
    kNotRechecked = 1u << 7,   // over the user's recheck cap: unverified, neither right nor wrong
    kInvalidHit = 1u << 8,     // ours is malformed (hit_check.h, HitClassifier::malformed): wrong
    kMissedHit = 1u << 9,      // wrong: the truth hits a primitive before ours, nothing touchy
    kFalseHit = 1u << 10,      // wrong: an occlusion where nothing near the segment is touchy
    kOutsideRange = 1u << 11,  // wrong: a hit whose t lies outside the ray's [tmin, tmax]
    kOffSurface = 1u << 12,    // wrong: the reported point is not on the primitive (on none)
};
constexpr int kReasonCount = 13;
const char* reasonName(int bit);            // "edge_or_vertex", "grazing", ...
std::string reasonNames(uint32_t reasons);  // comma-separated, "" for none

struct DoubleRay {
    DVec3 org, dir;
    double tmin, tmax;  // tmax may be +inf
};

DoubleRay toDoubleRay(const Ray& r);

// Absolute tolerances, in world units (the policy scales them by the scene's extent).
struct TouchTolerance {
    double distance = 0.0;    // |dt| and edge / silhouette distance
    double grazingCos = 0.0;  // |cos| at or below this is a grazing ray
};

class DoubleTracer {
public:
    DoubleTracer(const Scene& scene, TouchTolerance tol);

    // Closest hit over all primitives (ties: lower id), with t in [tmin, tmax].
    Hit closest(const DoubleRay& r) const;
    // The same with t in double: the primitive (-1 for none) and its t (+inf for none).
    int32_t closest(const DoubleRay& r, double& t) const;
    // Every primitive hit with t in [tmin, tmax], as (t, id), ascending t.
    std::vector<std::pair<double, uint32_t>> allHits(const DoubleRay& r) const;
    // The same hits in the same order (ascending t, then id), handed to f(t, id) one at a time
    // until f returns false, from one best-first traversal: a caller that stops at the first hit
    // it needs pays for the boxes before it only.
    // Whether some primitive hit with t in [tmin, tmax] satisfies pred(t, id): the hits in no
    // particular order, the search stopping at the first that does.
    template <class P>
    bool anyHitWhere(const DoubleRay& r, P&& pred) const {
        const double o[3] = {r.org.x, r.org.y, r.org.z}, d[3] = {r.dir.x, r.dir.y, r.dir.z};
        bool found = false;
        bvh_.segment(o, d, r.tmin, r.tmax, [&](uint32_t i) {
            double t;
            if (!found && hit(i, r, t) && pred(t, i)) found = true;
            return found ? -INFINITY : r.tmax;  // found: every box left is beyond the limit
        });
        return found;
    }

    template <class F>
    void hitsInOrder(const DoubleRay& r, F&& f) const {
        const double o[3] = {r.org.x, r.org.y, r.org.z}, d[3] = {r.dir.x, r.dir.y, r.dir.z};
        bvh_.ordered(
            o, d, r.tmin, r.tmax, [&](uint32_t i, double& t) { return hit(i, r, t); },
            [&](double t, uint32_t i) { return f(t, i); });
    }
    // The per-primitive queries below take ids from the tracer under test, which may be
    // corrupt: an id >= primitiveCount() is never indexed (no hit, no touchiness, +inf away).
    // Hit test of one primitive; t is the hit distance when it returns true.
    bool hit(uint32_t prim, const DoubleRay& r, double& t) const;
    // Why the answer for this primitive could flip under a perturbation of the ray by the
    // touch distance (AmbiguityReason bits; 0 = the configuration is clean). `distance`: a
    // larger one than the tolerance's for this query (0: the tolerance's).
    uint32_t touchiness(uint32_t prim, const DoubleRay& r, double distance = 0.0) const;
    // Distance from a point to the primitive's surface (the closed triangle; the sphere).
    double distanceTo(uint32_t prim, DVec3 p) const;
    // For a triangle: how far a single-precision watertight test's t may lie from the exact one
    // for this ray, in units of t: after Pharr, Jakob & Humphreys' analysis of Woop et al.'s test
    // (PBRT 3rd ed., sec. 3.9.6), with the edge functions' error weighted by the vertices' spread
    // along the ray around the hit (docs/VALIDATION.md, "The surface bound"), evaluated on the
    // exact sheared coordinates; +inf when the ray is parallel to the triangle's plane. 0 for
    // spheres.
    double floatTError(uint32_t prim, const DoubleRay& r) const;
    // For a triangle: the t at which the ray's line crosses its plane, inside the triangle or
    // not (what a float test's t estimates, floatTError off); NaN when the ray is parallel to
    // the plane, for a sphere and for an id out of range.
    double planeCrossing(uint32_t prim, const DoubleRay& r) const;
    // The longest side of a triangle, the diameter of a sphere; the largest over the scene.
    double diameter(uint32_t prim) const;
    double largestDiameter() const { return largestDiameter_; }
    // False only when no point of primitive i lies within max(base, its diameter) of p: its
    // bounding sphere (radius r, so the diameter is at most 2r) is farther than that, with a
    // margin of 1e-6 for a bound computed with a float |d|. A cheap filter before distanceTo
    // for a bound that grows with the primitive (surfacePrimitive).
    bool mayLieWithin(uint32_t i, DVec3 p, double base) const {
        const double r = boundRadius_[i];
        return length(p - boundCentre_[i]) - r <= std::max(base, 2.0 * r) * (1.0 + 1e-6);
    }
    // Calls f(prim) for every primitive whose box lies within `radius` of p (a superset of those
    // whose surface does).
    template <class F>
    void primitivesNear(DVec3 p, double radius, F&& f) const {
        const double q[3] = {p.x, p.y, p.z};
        double r = radius;
        bvh_.nearest(q, r, [&](uint32_t i) {
            f(i);
            return radius;  // keep the radius: every box within it is visited
        });
    }
    // The primitive whose surface is nearest to p (lowest id among equals); `dist` receives the
    // distance. -1 for a scene without primitives.
    int32_t nearestTo(DVec3 p, double& dist) const;
    // Union of touchiness over every primitive near the ray's segment.
    uint32_t touchinessNear(const DoubleRay& r, double distance = 0.0) const;

    // The same four queries over every primitive, without the BVH: the oracle the tests hold
    // the accelerated ones to (same answers, bit for bit).
    Hit closestBrute(const DoubleRay& r) const;
    std::vector<std::pair<double, uint32_t>> allHitsBrute(const DoubleRay& r) const;
    int32_t nearestToBrute(DVec3 p, double& dist) const;
    uint32_t touchinessNearBrute(const DoubleRay& r, double distance = 0.0) const;

    const TouchTolerance& tolerance() const { return tol_; }
    uint32_t primitiveCount() const { return count_; }

private:
    // tmax clipped to beyond the scene's bounds grown by tol.
    double clipFar(const DoubleRay& r, double tol) const;
    double touchDistance(double distance) const {
        return distance > tol_.distance ? distance : tol_.distance;
    }
    uint32_t triangleTouchiness(uint32_t prim, const DoubleRay& r, double tFar, double tol) const;
    uint32_t sphereTouchiness(uint32_t prim, const DoubleRay& r, double tFar, double tol) const;

    const Scene* scene_;
    uint32_t count_;
    TouchTolerance tol_;
    DVec3 sceneCentre_;
    double sceneRadius_;
    std::vector<DVec3> boundCentre_;  // per primitive: a bounding sphere for the near filter
    std::vector<double> boundRadius_;
    double largestDiameter_ = 0.0;
    double pad_;  // the BVH's growth of every box (at least the tolerance's touch distance)
    BoxBvh bvh_;  // over the primitives' boxes grown by pad_
};

}  // namespace oct
