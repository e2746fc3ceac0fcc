#include "validation/policy/hit_check.h"

#include <cmath>

namespace oct {

const char* hitClassName(HitClass c) {
    switch (c) {
        case HitClass::Tie:
            return "tie";
        case HitClass::Ambiguous:
            return "ambiguous";
        case HitClass::Wrong:
            return "wrong";
        case HitClass::Agree:
        default:
            return "agree";
    }
}

HitClassifier::HitClassifier(const Scene& scene, const ValidationPolicy& policy)
    : scene_(&scene),
      policy_(policy),
      extent_(sceneExtent(scene)),
      truth_(scene, {policy.edgeTolerance * sceneExtent(scene), policy.grazingCos}) {}

bool HitClassifier::malformed(Hit h) const {
    if (h.prim == -1) return !(h.t == INFINITY);
    if (h.prim < -1) return true;
    return !std::isfinite(h.t) || uint32_t(h.prim) >= truth_.primitiveCount();
}

bool HitClassifier::malformed(const Ray& ray, Hit h) const {
    if (malformed(h)) return true;
    // Written as !(in range) so that a NaN bound (never in a checked ray file) fails too.
    return h.prim >= 0 && !(h.t >= ray.tmin && h.t <= ray.tmax);
}

double HitClassifier::relativeDt(Hit a, Hit b, float dirLength) const {
    bool ha = a.prim >= 0, hb = b.prim >= 0;
    if (!ha && !hb) return 0.0;
    if (ha != hb) return INFINITY;
    if (!std::isfinite(a.t) || !std::isfinite(b.t)) return INFINITY;
    return std::fabs(double(a.t) - double(b.t)) * double(dirLength) / extent_;
}

bool HitClassifier::tieHolds(const Ray& ray, Hit ours) const {
    if (ours.prim < 0 || malformed(ours)) return false;
    const DoubleRay dr = toDoubleRay(ray);
    const double t = double(ours.t);
    const DVec3 p = dr.org + dr.dir * t;
    return truth_.distanceTo(uint32_t(ours.prim), p) <= truth_.tolerance().distance;
}

HitClass HitClassifier::compare(const Ray& ray, Hit ours, Hit reference) const {
    // A malformed answer on either side goes to the recheck: ours is wrong there (invalid_hit),
    // and a broken reference must not make a tie or an agreement out of nothing.
    if (malformed(ray, ours) || malformed(ray, reference)) return HitClass::Wrong;
    bool ho = ours.prim >= 0, hr = reference.prim >= 0;
    if (!ho && !hr) return HitClass::Agree;
    if (ho != hr) return HitClass::Wrong;
    // Written as !(<=) so that a NaN difference is a mismatch, never an agreement.
    if (!(relativeDt(ours, reference, length(ray.dir)) <= policy_.tTolerance))
        return HitClass::Wrong;
    if (ours.prim == reference.prim) return HitClass::Agree;
    // Another primitive at the same t: right only where ours really is at that point; a wrong
    // primitive far from any shared edge shades with the wrong normal, so it is rechecked.
    return tieHolds(ray, ours) ? HitClass::Tie : HitClass::Wrong;
}

Verdict HitClassifier::closest(const Ray& ray, Hit ours, Hit reference) const {
    Verdict v;
    v.cls = compare(ray, ours, reference);
    if (v.cls != HitClass::Wrong) return v;
    return recheckClosest(ray, ours);
}

Verdict HitClassifier::recheckClosest(const Ray& ray, Hit ours) const {
    Verdict v;
    v.rechecked = true;
    const DoubleRay dr = toDoubleRay(ray);
    const double dirLength =
        std::sqrt(dr.dir.x * dr.dir.x + dr.dir.y * dr.dir.y + dr.dir.z * dr.dir.z);
    const double tolAbs = policy_.tTolerance * extent_;  // world units
    const double tTol = tolAbs / dirLength;              // in units of t
    auto hits = truth_.allHits(dr);
    if (!hits.empty()) v.truth = {float(hits[0].first), int32_t(hits[0].second)};
    if (malformed(ray, ours)) {  // nothing to recheck: not an answer to this ray
        v.cls = HitClass::Wrong;
        v.reasons = malformed(ours) ? kInvalidHit : kOutsideRange;
        return v;
    }
    const bool oursHit = ours.prim >= 0;
    const double tOurs = oursHit ? double(ours.t) : INFINITY;
    const uint32_t q = oursHit ? uint32_t(ours.prim) : 0;

    bool clean = false;  // an error nothing excuses
    uint32_t reasons = 0, wrongWhy = 0;
    // 1. Our own answer: a hit on q at tOurs, confirmed when the double test hits q within the
    // tolerance of tOurs, or when our hit point lies within the edge tolerance of q itself (a
    // grazing ray: the same small distance off the surface is a long way along the ray). The
    // edge tolerance, not the t tolerance: a point off the surface is off sideways, and the
    // t tolerance (5x larger) would excuse a perpendicular ray that clearly misses q's edge.
    if (oursHit) {
        double tq;
        bool confirmed = truth_.hit(q, dr, tq) && std::fabs(tq - tOurs) <= tTol;
        if (!confirmed) {
            uint32_t r = truth_.touchiness(q, dr);
            DVec3 p = dr.org + dr.dir * tOurs;
            if (r == 0 && truth_.distanceTo(q, p) <= truth_.tolerance().distance) r = kGrazing;
            if (r == 0) {
                clean = true;
                wrongWhy |= kFalseHit;
            }
            reasons |= r;
        }
    }
    // 2. Every primitive the truth hits clearly before our answer: ours missed it, which only
    // a touchy configuration excuses. Our own primitive counts too when it is a sphere: a ray
    // meets a sphere twice, so a hit of ours on its surface beyond the truth's nearer hit on
    // it is the far root (step 1 confirmed the point is on the surface, not that it is the
    // first). A ray meets a triangle's plane once, so there our point and the truth's are the
    // same crossing, judged in step 1.
    const bool ownSecondCrossing = oursHit && scene_->kind == PrimKind::Spheres;
    for (const auto& h : hits) {
        if (!(h.first < tOurs - tTol)) break;
        if (oursHit && h.second == q && !ownSecondCrossing) continue;  // judged in step 1
        uint32_t r = truth_.touchiness(h.second, dr);
        if (r == 0) {
            clean = true;
            wrongWhy |= kMissedHit;
        }
        reasons |= r;
    }
    if (clean) {
        v.cls = HitClass::Wrong;
        v.reasons = wrongWhy;
        return v;
    }
    bool agreesWithTruth = (!oursHit && hits.empty()) ||
                           (oursHit && !hits.empty() && std::fabs(hits[0].first - tOurs) <= tTol);
    if (agreesWithTruth) {
        // Ours is right; say too what made the reference stumble, when something did.
        reasons |= kReferenceOff;
        if (oursHit) reasons |= truth_.touchiness(q, dr);
    }
    v.cls = reasons ? HitClass::Ambiguous : HitClass::Wrong;
    // Unexplained without a clean culprit: the truth's first hit is elsewhere than ours.
    v.reasons = reasons ? reasons
                        : (!hits.empty() && hits[0].first < tOurs ? uint32_t(kMissedHit)
                                                                  : uint32_t(kFalseHit));
    return v;
}

Verdict HitClassifier::recheckOcclusion(const Ray& ray, bool oursOccluded) const {
    Verdict v;
    v.rechecked = true;
    DoubleRay dr = toDoubleRay(ray);
    auto hits = truth_.allHits(dr);
    v.truthOccluded = !hits.empty();
    if (hits.size() > 0) v.truth = {float(hits[0].first), int32_t(hits[0].second)};
    if (oursOccluded == v.truthOccluded) {
        v.cls = HitClass::Ambiguous;
        v.reasons = kReferenceOff;
        return v;
    }
    uint32_t reasons = 0;
    bool clean = false;
    if (v.truthOccluded) {  // ours saw through every occluder: each must be touchy
        for (const auto& h : hits) {
            uint32_t r = truth_.touchiness(h.second, dr);
            if (r == 0) clean = true;
            reasons |= r;
        }
    } else {  // ours found an occluder the truth does not: something near must be touchy
        reasons = truth_.touchinessNear(dr);
    }
    v.cls = clean || reasons == 0 ? HitClass::Wrong : HitClass::Ambiguous;
    v.reasons =
        v.cls == HitClass::Ambiguous ? reasons : uint32_t(v.truthOccluded ? kMissedHit : kFalseHit);
    return v;
}

}  // namespace oct
