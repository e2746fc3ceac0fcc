// The per-ray policy of docs/VALIDATION.md ("The per-pixel policy"), for closest hits and for
// occlusion (shadow) queries: ours against a reference tracer (Embree), and on a mismatch a
// recheck against the double-precision, brute-force truth of double_tracer.h.
//
// Closest hits, first step: a hit of ours with a non-finite t or a primitive id out of range
// is malformed, wrong whatever the reference says (reason invalid_hit); both miss -> agree;
// both hit with |dt| <= tTolerance * extent -> agree, or a tie when the primitives differ and
// our primitive passes within edgeTolerance * extent of our hit point (a shared edge or vertex:
// both answers are right); anything else, a NaN included, is a mismatch, rechecked:
//  1. our own hit (primitive q at t): confirmed when the truth hits q within the tolerance of
//     t, or when our hit point lies within edgeTolerance * extent of q's surface (the error of
//     a grazing ray is small across the surface and long along the ray: reason grazing);
//     otherwise q must be touchy for this ray (edge or vertex, grazing, degenerate, tangent,
//     range end) or the mismatch is wrong;
//  2. every primitive the truth hits clearly before our t: ours missed it, which only a touchy
//     configuration excuses, else wrong;
//  3. nothing unexcused: ambiguous, with the reasons found; if ours also agrees with the
//     truth by the first-step rule, the reference was the one off (reason reference_off).
// A wrong verdict says why: invalid_hit (malformed), t_outside_range (a hit beyond the ray's
// [tmin, tmax]), false_hit (step 1: our primitive is not there), missed_hit (step 2: we missed
// a primitive before our t), or not_rechecked.
// Occlusion (one ray, ours != reference): ours equals the truth -> ambiguous, reference_off;
// ours lit but occluded in truth -> every occluder must be touchy; ours occluded but lit in
// truth -> some primitive near the segment must be touchy; else wrong.
#pragma once

#include <cstdint>

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
    // Mismatches rechecked in double (each costs one brute-force pass over the primitives),
    // per check: primary pixels, shadow rays and the ray set each have this many; beyond it
    // they count as wrong with reason not_rechecked.
    uint64_t maxRechecks = 20000;
    // Findings kept for the report: the worst pixels, shadow rays and rays.
    int worstCount = 16;
};

enum class HitClass : uint8_t { Agree = 0, Tie = 1, Ambiguous = 2, Wrong = 3 };
const char* hitClassName(HitClass c);  // "agree", "tie", "ambiguous", "wrong"

struct Verdict {
    HitClass cls = HitClass::Agree;
    uint32_t reasons = 0;  // AmbiguityReason bits (ambiguous; kNotRechecked, kInvalidHit)
    bool rechecked = false;
    Hit truth = {INFINITY, -1};  // double-precision closest hit (closest queries, rechecked)
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
    // A different primitive at the same t is a tie only when our primitive passes within the
    // edge tolerance of our hit point: a shared edge or vertex, or surfaces crossing there.
    // O(1): one point-to-primitive distance.
    bool tieHolds(const Ray& ray, Hit ours) const;
    // |dt| / extent for two hits, +inf when exactly one hits or either hit's t is not finite
    // (never NaN, so a maximum over it cannot hide a broken hit), 0 when both miss.
    double relativeDt(Hit a, Hit b, float dirLength = 1.0f) const;

    // Full verdict for one closest-hit query (rechecks a mismatch).
    Verdict closest(const Ray& ray, Hit ours, Hit reference) const;
    // Recheck of a closest-hit mismatch against the double truth.
    Verdict recheckClosest(const Ray& ray, Hit ours) const;
    // Recheck of an occlusion mismatch (ours != reference) on one ray.
    Verdict recheckOcclusion(const Ray& ray, bool oursOccluded) const;

private:
    const Scene* scene_;
    ValidationPolicy policy_;
    double extent_;
    DoubleTracer truth_;
};

}  // namespace oct
