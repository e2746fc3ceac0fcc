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

// Whether `reference`, or one of the next few hits `more` gives (the reference's next ones along
// the ray, nearest first), is a witness.
template <class W>
bool witnessAmong(Hit reference, const std::function<Hit()>* more, W&& witness) {
    constexpr int kNextHits = 6;
    if (witness(reference)) return true;
    if (!more || reference.prim < 0) return false;
    for (int k = 0; k < kNextHits; ++k) {
        const Hit h = (*more)();
        if (h.prim < 0) return false;
        if (witness(h)) return true;
    }
    return false;
}

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
    return surfaceBoundFor(ray, hitTError(ray, prim));  // 0 for an id out of range
}

double HitClassifier::surfaceBoundFor(const Ray& ray, double tError) const {
    const double origin = std::max(
        {std::fabs(double(ray.org.x)), std::fabs(double(ray.org.y)), std::fabs(double(ray.org.z))});
    const double bound = std::max(policy_.edgeTolerance * extent_,
                                  kSurfaceUlps * 0x1p-24 * (origin + sceneMagnitude_));
    return std::max(bound, tError * double(length(ray.dir)));
}

double HitClassifier::hitTError(const Ray& ray, int32_t prim) const {
    if (prim < 0 || uint32_t(prim) >= truth_.primitiveCount()) return 0.0;
    const DoubleRay dr = toDoubleRay(ray);
    const double dirLength = length(dr.dir);
    const double e = truth_.floatTError(uint32_t(prim), dr);
    // A ray parallel to the plane crosses it nowhere: there is no t to be off, and a point on
    // such a ray is on the triangle only within the floors of the bound (the diameter's cap
    // would excuse any point within a triangle's size of it).
    if (!std::isfinite(e)) return 0.0;
    return std::min(kSurfaceTErrors * e, truth_.diameter(uint32_t(prim)) / dirLength);
}

double HitClassifier::tTolerance(const Ray& ray) const {
    return policy_.tTolerance * extent_ / double(length(ray.dir));
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
    return onPrimitive(ray, h.t, uint32_t(h.prim), surfaceDistance(ray, h));
}

bool HitClassifier::onPrimitive(const Ray& ray, float t, uint32_t prim, double distance) const {
    const double tError = hitTError(ray, int32_t(prim));
    if (!(distance <= surfaceBoundFor(ray, tError))) return false;
    // Along the ray as well as across the surface: a grazing ray stays within the bound of the
    // plane for a long way, so a t several per cent off is still "near" the triangle there.
    // A float test's t is the plane crossing's, off by at most its error bound (Woop et al.'s
    // test after PBRT 3.9.6, floatTError), wherever the ray meets the plane, inside or not.
    const double crossing = truth_.planeCrossing(prim, toDoubleRay(ray));
    return std::isnan(crossing) ||
           std::fabs(double(t) - crossing) <= std::max(tTolerance(ray), tError);
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
    if (onPrimitive(ray, t, uint32_t(nearest), nearestDist)) {
        on = true;
        return nearest;
    }
    // Another primitive's bound may be larger (a sliver, a grazing ray): any primitive the
    // point is on lies within the largest bound a primitive can have of it.
    int32_t best = -1;
    double bestDist = INFINITY;
    const double base = surfaceBound(ray);
    const double radius = std::max(base, truth_.largestDiameter());
    truth_.primitivesNear(p, radius, [&](uint32_t i) {
        // surfaceBound(ray, i) is at most max(base, the diameter of i) (hitTError's cap, times a
        // float |d|): most candidates within the largest diameter are ruled out by their
        // bounding sphere, unmeasured.
        if (!truth_.mayLieWithin(i, p, base)) return;
        const double d = truth_.distanceTo(i, p);
        if (onPrimitive(ray, t, i, d) && (d < bestDist || (d == bestDist && int32_t(i) < best))) {
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
    return recheckClosest(ray, ours, reference);
}

Hit HitClassifier::truthOf(const Ray& ray, const Verdict& v) const {
    return v.truthKnown || !v.rechecked ? v.truth : truth_.closest(toDoubleRay(ray));
}

Verdict HitClassifier::recheckClosest(const Ray& ray, Hit ours, Hit reference,
                                      const std::function<Hit()>* more) const {
    Verdict v;
    v.rechecked = true;
    if (malformed(ray, ours)) {  // nothing to recheck: not an answer to this ray
        v.cls = HitClass::Wrong;
        v.reasons = malformed(ours) ? kInvalidHit : kOutsideRange;
        return v;
    }
    const DoubleRay dr = toDoubleRay(ray);
    const double dirLength = length(dr.dir);
    const double tTol = policy_.tTolerance * extent_ / dirLength;  // in units of t
    const double touch = surfaceBound(ray);
    const bool oursHit = ours.prim >= 0;
    const double tOurs = oursHit ? double(ours.t) : INFINITY;
    const uint32_t q = oursHit ? uint32_t(ours.prim) : 0;

    // 1. The rule: our point must lie on our primitive, whatever else is touchy about the ray
    // (onSurface: across the surface and along the ray). On it but not where the truth meets q
    // within the t tolerance: an edge or vertex the ray passes within the bound of, or a
    // grazing ray, whose t a float test pins down only to its error bound.
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
    // same crossing, judged in step 1. The reference's primitive first: one clean primitive
    // hit clearly before ours is enough.
    const bool ownSecondCrossing = oursHit && scene_->kind == PrimKind::Spheres;
    auto counts = [&](uint32_t p) { return !oursHit || p != q || ownSecondCrossing; };
    // A witness: a clean primitive the truth hits clearly before ours.
    auto witness = [&](Hit c) {
        double tc;
        return c.prim >= 0 && uint32_t(c.prim) < truth_.primitiveCount() &&
               counts(uint32_t(c.prim)) && truth_.hit(uint32_t(c.prim), dr, tc) &&
               tc < tOurs - tTol && truth_.touchiness(uint32_t(c.prim), dr, touch) == 0;
    };
    if (witnessAmong(reference, more, witness)) {
        v.cls = HitClass::Wrong;
        v.reasons = kMissedHit;
        return v;
    }
    // Any clean primitive hit clearly before ours settles it (searched for in no order, the
    // search stopping there). Else every hit before ours was seen: their touchiness gives the
    // reasons, and the nearest (ties: lowest id) is the truth's answer, unless there was none,
    // when the truth's answer lies at or beyond ours.
    DoubleRay before = dr;
    before.tmax = std::min(dr.tmax, tOurs - tTol);
    double tFirst = INFINITY;
    int32_t first = -1;
    const bool clean =
        before.tmin <= before.tmax && truth_.anyHitWhere(before, [&](double t, uint32_t p) {
            if (!(t < tOurs - tTol)) return false;
            if (t < tFirst || (t == tFirst && int32_t(p) < first)) {
                tFirst = t;
                first = int32_t(p);
            }
            if (!counts(p)) return false;  // judged in step 1
            const uint32_t r = truth_.touchiness(p, dr, touch);
            reasons |= r;
            return r == 0;
        });
    if (clean) {
        v.cls = HitClass::Wrong;
        v.reasons = kMissedHit;
        return v;
    }
    if (first < 0 && oursHit) first = truth_.closest(dr, tFirst);
    v.truth = {first >= 0 ? float(tFirst) : INFINITY, first};
    v.truthKnown = true;
    const bool agreesWithTruth =
        (!oursHit && first < 0) || (oursHit && first >= 0 && std::fabs(tFirst - tOurs) <= tTol);
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

Verdict HitClassifier::recheckAnyHit(const Ray& ray, Hit ours, Hit reference,
                                     const std::function<Hit()>* more) const {
    Verdict v;
    v.rechecked = true;
    if (malformed(ray, ours)) {
        v.cls = HitClass::Wrong;
        v.reasons = malformed(ours) ? kInvalidHit : kOutsideRange;
        return v;
    }
    const DoubleRay dr = toDoubleRay(ray);
    const double touch = surfaceBound(ray);
    if (ours.prim >= 0) {
        if (!onSurface(ray, ours)) {
            v.cls = HitClass::Wrong;
            v.reasons = kOffSurface;
            return v;
        }
        // A point on a primitive inside the segment: right. Where the truth meets nothing,
        // the segment passes within the bound of that primitive's edge or ends on it.
        v.truth = truth_.closest(dr);
        v.truthKnown = true;
        v.truthOccluded = v.truth.prim >= 0;
        v.cls = HitClass::Ambiguous;
        if (v.truthOccluded) {
            v.reasons = kReferenceOff;
        } else {
            const uint32_t r = truth_.touchiness(uint32_t(ours.prim), dr, touch);
            v.reasons = r ? r : uint32_t(kGrazing);
        }
        return v;
    }
    // Ours saw nothing: every primitive the truth meets on the segment must be touchy; the
    // reference's first (a clean one settles it without a search).
    auto witness = [&](Hit c) {
        double tc;
        return c.prim >= 0 && uint32_t(c.prim) < truth_.primitiveCount() &&
               truth_.hit(uint32_t(c.prim), dr, tc) &&
               truth_.touchiness(uint32_t(c.prim), dr, touch) == 0;
    };
    if (witnessAmong(reference, more, witness)) {
        v.cls = HitClass::Wrong;
        v.reasons = kMissedHit;
        return v;
    }
    v.truth = truth_.closest(dr);
    v.truthKnown = true;
    v.truthOccluded = v.truth.prim >= 0;
    if (!v.truthOccluded) {
        v.cls = HitClass::Ambiguous;
        v.reasons = kReferenceOff;
        return v;
    }
    if (truth_.anyHitWhere(
            dr, [&](double, uint32_t p) { return truth_.touchiness(p, dr, touch) == 0; })) {
        v.cls = HitClass::Wrong;
        v.reasons = kMissedHit;
        return v;
    }
    uint32_t reasons = 0;
    truth_.hitsInOrder(dr, [&](double, uint32_t p) {
        reasons |= truth_.touchiness(p, dr, touch);
        return true;
    });
    v.cls = HitClass::Ambiguous;
    v.reasons = reasons;
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
