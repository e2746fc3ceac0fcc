#include "validation/policy/hit_check.h"

#include <algorithm>
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
        case HitClass::Unverified:
            return "unverified";
        case HitClass::Agree:
        default:
            return "agree";
    }
}

namespace {

double largestCoordinate(const Scene& scene) {
    const Aabb b = scene.bounds();
    double m = 0.0;
    for (int a = 0; a < 3; ++a)
        m = std::max({m, std::fabs(double(b.lo[a])), std::fabs(double(b.hi[a]))});
    return m;
}

}  // namespace

HitClassifier::HitClassifier(const Scene& scene, const ValidationPolicy& policy)
    : scene_(&scene),
      policy_(policy),
      extent_(sceneExtent(scene)),
      sceneMagnitude_(largestCoordinate(scene)),
      truth_(scene, {policy.edgeTolerance * sceneExtent(scene), policy.grazingCos}) {}

double HitClassifier::surfaceBound(const Ray& ray, int32_t prim) const {
    const double origin = std::max(
        {std::fabs(double(ray.org.x)), std::fabs(double(ray.org.y)), std::fabs(double(ray.org.z))});
    double bound = std::max(policy_.edgeTolerance * extent_,
                            kSurfaceUlps * 0x1p-24 * (origin + sceneMagnitude_));
    if (prim >= 0 && uint32_t(prim) < truth_.primitiveCount()) {
        const DoubleRay dr = toDoubleRay(ray);
        const double along =
            kSurfaceTErrors * truth_.floatTError(uint32_t(prim), dr) * length(dr.dir);
        bound = std::max(bound, std::min(along, truth_.diameter(uint32_t(prim))));
    }
    return bound;
}

DVec3 HitClassifier::hitPoint(const Ray& ray, float t) const {
    const DoubleRay dr = toDoubleRay(ray);
    return dr.org + dr.dir * double(t);
}

double HitClassifier::surfaceDistance(const Ray& ray, Hit h) const {
    if (h.prim < 0 || !std::isfinite(h.t)) return INFINITY;
    return truth_.distanceTo(uint32_t(h.prim), hitPoint(ray, h.t));
}

bool HitClassifier::onSurface(const Ray& ray, Hit h) const {
    if (h.prim < 0 || malformed(ray, h)) return false;
    return surfaceDistance(ray, h) <= surfaceBound(ray, h.prim);
}

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

int32_t HitClassifier::surfacePrimitive(const Ray& ray, float t, bool& on) const {
    const DVec3 p = hitPoint(ray, t);
    double nearestDist;
    const int32_t nearest = truth_.nearestTo(p, nearestDist);
    on = false;
    if (nearest < 0) return -1;
    if (nearestDist <= surfaceBound(ray, nearest)) {
        on = true;
        return nearest;
    }
    // Another primitive's bound may be larger (a sliver, a grazing ray): any primitive the
    // point is on lies within the largest bound a primitive can have of it.
    int32_t best = -1;
    double bestDist = INFINITY;
    const double radius = std::max(surfaceBound(ray), truth_.largestDiameter());
    truth_.primitivesNear(p, radius, [&](uint32_t i) {
        const double d = truth_.distanceTo(i, p);
        if (d <= surfaceBound(ray, int32_t(i)) &&
            (d < bestDist || (d == bestDist && int32_t(i) < best))) {
            bestDist = d;
            best = int32_t(i);
        }
    });
    on = best >= 0;
    return on ? best : nearest;
}

bool HitClassifier::tieHolds(const Ray& ray, Hit ours) const { return onSurface(ray, ours); }

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
    const double dirLength = length(dr.dir);
    const double tTol = policy_.tTolerance * extent_ / dirLength;  // in units of t
    const double touch = surfaceBound(ray);
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

    // 1. The rule: our point must lie on our primitive, whatever else is touchy about the ray.
    // On it but not where the truth meets q (within the t tolerance): an edge or vertex the
    // ray passes within the bound of, or a grazing ray, whose long along-ray error is small
    // across the surface.
    uint32_t reasons = 0;
    if (oursHit) {
        if (!onSurface(ray, ours)) {
            v.cls = HitClass::Wrong;
            v.reasons = kOffSurface;
            return v;
        }
        double tq;
        const bool confirmed = truth_.hit(q, dr, tq) && std::fabs(tq - tOurs) <= tTol;
        if (!confirmed) {
            const uint32_t r = truth_.touchiness(q, dr, touch);
            reasons |= r ? r : uint32_t(kGrazing);
        }
    }
    // 2. Every primitive the truth hits clearly before our answer: ours missed it, which only
    // a touchy configuration excuses. Our own primitive counts too when it is a sphere: a ray
    // meets a sphere twice, so a hit of ours on its surface beyond the truth's nearer hit on
    // it is the far root (step 1 confirmed the point is on the surface, not that it is the
    // first). A ray meets a triangle's plane once, so there our point and the truth's are the
    // same crossing, judged in step 1.
    const bool ownSecondCrossing = oursHit && scene_->kind == PrimKind::Spheres;
    bool clean = false;
    for (const auto& h : hits) {
        if (!(h.first < tOurs - tTol)) break;
        if (oursHit && h.second == q && !ownSecondCrossing) continue;  // judged in step 1
        const uint32_t r = truth_.touchiness(h.second, dr, touch);
        clean = clean || r == 0;
        reasons |= r;
    }
    if (clean) {
        v.cls = HitClass::Wrong;
        v.reasons = kMissedHit;
        return v;
    }
    const bool agreesWithTruth =
        (!oursHit && hits.empty()) ||
        (oursHit && !hits.empty() && std::fabs(hits[0].first - tOurs) <= tTol);
    if (agreesWithTruth) {
        // Ours is right; say too what made the reference stumble, when something did.
        reasons |= kReferenceOff;
        if (oursHit) reasons |= truth_.touchiness(q, dr, touch);
    }
    v.cls = reasons ? HitClass::Ambiguous : HitClass::Wrong;
    // Unexplained without a clean culprit: the truth's first hit is elsewhere than ours.
    v.reasons = reasons ? reasons : uint32_t(kMissedHit);
    return v;
}

HitClass HitClassifier::compareAnyHit(const Ray& ray, Hit ours, Hit reference) const {
    if (malformed(ray, ours) || malformed(ray, reference)) return HitClass::Wrong;
    const bool ho = ours.prim >= 0, hr = reference.prim >= 0;
    if (!ho && !hr) return HitClass::Agree;
    if (ho && hr && onSurface(ray, ours)) return HitClass::Agree;
    return HitClass::Wrong;
}

Verdict HitClassifier::recheckAnyHit(const Ray& ray, Hit ours) const {
    Verdict v;
    v.rechecked = true;
    const DoubleRay dr = toDoubleRay(ray);
    const double touch = surfaceBound(ray);
    const auto hits = truth_.allHits(dr);
    v.truthOccluded = !hits.empty();
    if (!hits.empty()) v.truth = {float(hits[0].first), int32_t(hits[0].second)};
    if (malformed(ray, ours)) {
        v.cls = HitClass::Wrong;
        v.reasons = malformed(ours) ? kInvalidHit : kOutsideRange;
        return v;
    }
    if (ours.prim >= 0) {
        if (!onSurface(ray, ours)) {
            v.cls = HitClass::Wrong;
            v.reasons = kOffSurface;
            return v;
        }
        // A point on a primitive inside the segment: right. Where the truth meets nothing,
        // the segment passes within the bound of that primitive's edge or ends on it.
        v.cls = HitClass::Ambiguous;
        if (!hits.empty()) {
            v.reasons = kReferenceOff;
        } else {
            const uint32_t r = truth_.touchiness(uint32_t(ours.prim), dr, touch);
            v.reasons = r ? r : uint32_t(kGrazing);
        }
        return v;
    }
    // Ours saw nothing: every primitive the truth meets on the segment must be touchy.
    uint32_t reasons = 0;
    bool clean = false;
    for (const auto& h : hits) {
        const uint32_t r = truth_.touchiness(h.second, dr, touch);
        clean = clean || r == 0;
        reasons |= r;
    }
    v.cls = clean ? HitClass::Wrong : HitClass::Ambiguous;
    v.reasons = clean ? uint32_t(kMissedHit) : (hits.empty() ? uint32_t(kReferenceOff) : reasons);
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
