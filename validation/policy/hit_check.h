// The per-ray policy of docs/VALIDATION.md ("The rule" and "The per-pixel policy") for
// closest-hit and any-hit (occlusion) queries: ours against a reference tracer (Embree), a
// mismatch rechecked against the double-precision truth (double_tracer.h). The rule above the
// others: a reported hit must lie on its primitive (with --no-prim: on some primitive) within
// the surface bound, inside [tmin, tmax]; touchiness may excuse which primitive, or a hit
// against a miss, never a point off every surface (reason off_surface).
#pragma once

#include <cstdint>
#include <functional>

#include "core/geometry/ray.h"
#include "core/scene/scene.h"
#include "validation/policy/double_tracer.h"
#include "validation/policy/film_compare.h"

namespace oct {

struct ValidationPolicy {
    // |dt| <= tTolerance * extent is the same hit (extent: the scene's bounding-box diagonal).
    double tTolerance = kDefaultRelativeTolerance;
    // A ray within edgeTolerance * extent of a triangle's boundary or a sphere's silhouette
    // (or ending that close to a primitive) is an edge / tangent / range-end configuration.
    double edgeTolerance = 2e-6;
    // |cos(ray, triangle normal)| at or below this is a grazing ray.
    double grazingCos = 1e-3;
    // Fail when ambiguous / compared exceeds this, separately for primary pixels, shadow rays
    // and the ray sets.
    double maxAmbiguousRate = 1e-3;
    // A cap on the mismatches rechecked in double, per check (primary pixels, shadow rays, each
    // ray set, each set's leak candidates); beyond it a query is unverified (neither right nor
    // wrong) and the verdict INCOMPLETE. No cap by default: every flagged query is rechecked.
    uint64_t maxRechecks = UINT64_MAX;
    // Findings kept for the report: the worst pixels, shadow rays and rays.
    int worstCount = 16;
};

// The values are those of certify's per-ray class file (docs/CERTIFY.md): never renumber.
enum class HitClass : uint8_t { Agree = 0, Tie = 1, Ambiguous = 2, Wrong = 3, Unverified = 4 };
constexpr int kHitClassCount = 5;
const char* hitClassName(HitClass c);  // "agree", "tie", "ambiguous", "wrong", "unverified"
// The order reports list findings in: wrong, unverified, ambiguous, tie, agree.
inline int hitSeverity(HitClass c) {
    return c == HitClass::Wrong ? 4 : c == HitClass::Unverified ? 3 : int(c);
}

// The surface bound's floor far from the origin, in unit roundoffs (2^-24) of the magnitudes
// involved, |o| + M: one. Correct float tracers (Moller-Trumbore, Embree, octrace) on the far
// scenes of tests/far_meshes.h came within 0.016 of it; 64 once let a hit 12 ulps off its
// triangle pass (docs/VALIDATION.md, "The surface bound").
constexpr double kSurfaceUlps = 1.0;
// Margin over the float test's own t error bound (PBRT's, for the watertight test).
constexpr double kSurfaceTErrors = 2.0;

struct Verdict {
    HitClass cls = HitClass::Agree;
    uint32_t reasons = 0;  // AmbiguityReason bits (ambiguous; kNotRechecked, kInvalidHit)
    bool rechecked = false;
    Hit truth = {INFINITY, -1};  // double-precision closest hit (closest queries, rechecked)
    bool truthKnown = false;     // false: not needed for the verdict (HitClassifier::truthOf)
    bool truthOccluded = false;  // occlusion queries, rechecked
};

class HitClassifier {
public:
    HitClassifier(const Scene& scene, const ValidationPolicy& policy);

    const ValidationPolicy& policy() const { return policy_; }
    const Scene& scene() const { return *scene_; }
    double extent() const { return extent_; }
    const DoubleTracer& truth() const { return truth_; }

    // The first step: Agree, Tie, or Wrong standing for "mismatch, recheck it". Needs the ray
    // only to confirm a tie (tieHolds); everything else is |dt| and the primitive ids.
    HitClass compare(const Ray& ray, Hit ours, Hit reference) const;
    // An answer no correct tracer gives (docs/TRACE_FORMAT.md): a hit (prim >= 0) with a t that
    // is not finite or a primitive id >= the scene's count; a primitive id below -1; a miss
    // (prim -1) whose t is not +inf.
    bool malformed(Hit h) const;
    // The same, and a hit's t outside the ray's [tmin, tmax].
    bool malformed(const Ray& ray, Hit h) const;
    // How far from a primitive a correct float tracer's hit point on this ray may lie (docs/
    // VALIDATION.md, "The surface bound"): the largest of edgeTolerance x extent, kSurfaceUlps x
    // 2^-24 x (|origin| + the scene's largest coordinate) (the magnitudes its arithmetic rounds,
    // infinity norms) and, for primitive `prim`, kSurfaceTErrors x the float test's t error
    // bound x |d| (DoubleTracer::floatTError, large for slivers and grazing rays) capped at the
    // primitive's diameter. Without `prim`, the first two.
    double surfaceBound(const Ray& ray, int32_t prim = -1) const;
    // The point o + t d of a hit (in double from the float ray), and its distance to primitive
    // `prim` (+inf for an id out of range).
    DVec3 hitPoint(const Ray& ray, float t) const;
    double surfaceDistance(const Ray& ray, Hit h) const;
    // How far a correct float tracer's t for a hit on `prim` may lie from the exact one, in units
    // of t: kSurfaceTErrors x the watertight test's bound (DoubleTracer::floatTError), capped at
    // the primitive's diameter over |d|. 0 for spheres and for a ray parallel to the plane.
    double hitTError(const Ray& ray, int32_t prim) const;
    // |dt| within policy().tTolerance x extent, in units of this ray's t.
    double tTolerance(const Ray& ray) const;
    // The rule: a well-formed hit inside [tmin, tmax] whose point lies within surfaceBound of
    // its primitive, and whose t lies within max(tTolerance, hitTError) of where the ray
    // crosses a triangle's plane (onPrimitive). O(1).
    bool onSurface(const Ray& ray, Hit h) const;
    // The same for a point at t on the ray `distance` from primitive `prim` (distanceTo).
    bool onPrimitive(const Ray& ray, float t, uint32_t prim, double distance) const;
    // Without a primitive id (certify --no-prim): the primitive a hit at t is on, the nearest
    // to its point among those it lies within the bound of (lowest id among equals); when it
    // is on none, the nearest primitive, and `on` is false. -1 for a scene without primitives.
    int32_t surfacePrimitive(const Ray& ray, float t, bool& on) const;
    // A different primitive at the same t is a tie only when our hit is on our primitive: a
    // shared edge or vertex, or surfaces crossing there.
    bool tieHolds(const Ray& ray, Hit ours) const;
    // |dt| / extent for two hits, +inf when exactly one hits or either hit's t is not finite
    // (never NaN, so a maximum over it cannot hide a broken hit), 0 when both miss.
    double relativeDt(Hit a, Hit b, float dirLength = 1.0f) const;

    // Full verdict for one closest-hit query (rechecks a mismatch).
    Verdict closest(const Ray& ray, Hit ours, Hit reference) const;
    // Recheck of a closest-hit mismatch against the double truth. `reference` (when it hits) is
    // tried first as the primitive ours missed: a clean one settles the verdict without a
    // search, so a tracer that answers every ray wrongly costs no more than a right one.
    // `more` (may be null) gives another candidate when the reference's is not decisive: the
    // reference's next hit on the ray.
    Verdict recheckClosest(const Ray& ray, Hit ours, Hit reference = {INFINITY, -1},
                           const std::function<Hit()>* more = nullptr) const;
    // The truth's closest hit a verdict names: its own when it had to find it, else found now.
    Hit truthOf(const Ray& ray, const Verdict& v) const;
    // The first step of an any-hit query with a reported hit (certify's shadow set): both miss
    // -> agree; ours on a primitive in [tmin, tmax] and the reference hits -> agree (any hit is
    // right); anything else is a mismatch (Wrong, to recheck).
    HitClass compareAnyHit(const Ray& ray, Hit ours, Hit reference) const;
    // Recheck of an any-hit mismatch: ours off every surface -> wrong (off_surface); ours on a
    // surface -> ambiguous (the truth decides which side was off); ours a miss -> every
    // primitive the truth meets on the segment must be touchy, else wrong (missed_hit).
    Verdict recheckAnyHit(const Ray& ray, Hit ours, Hit reference = {INFINITY, -1},
                          const std::function<Hit()>* more = nullptr) const;
    // Recheck of an occlusion mismatch (ours != reference) on one ray, when only the yes/no
    // answer is known (the Film's shadow flags).
    Verdict recheckOcclusion(const Ray& ray, bool oursOccluded) const;

private:
    // surfaceBound for a primitive whose hitTError is `tError` (0: the floors alone), so that
    // onPrimitive runs the primitive's error bound once for both of its tests.
    double surfaceBoundFor(const Ray& ray, double tError) const;

    const Scene* scene_;
    ValidationPolicy policy_;
    double extent_;
    double sceneMagnitude_;  // the largest |coordinate| of the scene's bounds
    DoubleTracer truth_;
};

}  // namespace oct
