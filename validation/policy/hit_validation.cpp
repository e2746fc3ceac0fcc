#include "validation/policy/hit_validation.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/octree/built_scene.h"
#include "core/render/kernel.h"

namespace oct {
namespace {

// A running maximum of |dt| / extent that a NaN cannot hide (std::max(m, NaN) keeps m): a NaN
// counts as +inf, the value of a hit that is not there.
void raiseMax(double& m, double v) {
    if (std::isnan(v)) v = INFINITY;
    if (v > m) m = v;
}

}  // namespace

void ClassCounts::count(HitClass c, uint32_t why) {
    ++compared;
    switch (c) {
        case HitClass::Agree:
            ++agree;
            break;
        case HitClass::Tie:
            ++ties;
            break;
        case HitClass::Ambiguous:
            ++ambiguous;
            break;
        case HitClass::Wrong:
            ++wrong;
            break;
        case HitClass::Unverified:
            ++unverified;
            break;
    }
    for (int b = 0; b < kReasonCount; ++b)
        if (why & (1u << b)) ++reasons[b];
}

void ClassCounts::merge(const ClassCounts& o) {
    compared += o.compared;
    bothMiss += o.bothMiss;
    agree += o.agree;
    ties += o.ties;
    ambiguous += o.ambiguous;
    wrong += o.wrong;
    unverified += o.unverified;
    mismatches += o.mismatches;
    rechecked += o.rechecked;
    for (int b = 0; b < kReasonCount; ++b) reasons[b] += o.reasons[b];
    raiseMax(maxRelativeDt, o.maxRelativeDt);
}

namespace {

int severity(HitClass c) { return hitSeverity(c); }

template <class F>
void keepWorst(std::vector<F>& v, int count, double (*dt)(const F&)) {
    auto key = [&](const F& f) {
        double d = dt(f);
        return std::isnan(d) ? INFINITY : d;
    };
    std::stable_sort(v.begin(), v.end(), [&](const F& a, const F& b) {
        if (severity(a.cls) != severity(b.cls)) return severity(a.cls) > severity(b.cls);
        return key(a) > key(b);
    });
    if (v.size() > size_t(std::max(count, 0))) v.resize(size_t(std::max(count, 0)));
}

// A query worth reporting, before its Finding is built: only the worst few are built.
struct Candidate {
    int severity;
    double dt;  // +inf for hit against miss
    uint64_t index;
};

// Indices of the `count` most severe candidates, then the largest |dt|, then the lowest index.
std::vector<uint64_t> worstIndices(std::vector<Candidate>& c, int count) {
    auto key = [](const Candidate& a) { return std::isnan(a.dt) ? INFINITY : a.dt; };
    auto before = [&](const Candidate& a, const Candidate& b) {
        if (a.severity != b.severity) return a.severity > b.severity;
        if (key(a) != key(b)) return key(a) > key(b);
        return a.index < b.index;
    };
    size_t k = std::min(c.size(), size_t(std::max(count, 0)));
    std::partial_sort(c.begin(), c.begin() + k, c.end(), before);
    std::vector<uint64_t> out;
    for (size_t i = 0; i < k; ++i) out.push_back(c[i].index);
    return out;
}
double shadowDt(const ShadowFinding&) { return 0.0; }

// A mismatch past the recheck cap: a malformed hit is wrong without a recheck (O(1)); any other
// is unverified.
Verdict overTheCap(const HitClassifier& c, const Ray& ray, Hit ours) {
    Verdict v;
    if (c.malformed(ray, ours)) {
        v.cls = HitClass::Wrong;
        v.reasons = c.malformed(ours) ? kInvalidHit : kOutsideRange;
    } else {
        v.cls = HitClass::Unverified;
        v.reasons = kNotRechecked;
    }
    return v;
}

// Runs f(i) for i in [0, n) on the OpenMP threads; each call writes only its own slot.
template <class F>
void parallelFor(size_t n, F&& f) {
#pragma omp parallel for schedule(dynamic, 1)
    for (int64_t i = 0; i < int64_t(n); ++i) f(size_t(i));
}

// Our shadow ray, rebuilt exactly as the kernel builds it from our hit (kernel.h). Only
// well-formed hits get here (compare() sends the others to the recheck), but a corrupt id must
// never index the primitive arrays: for one, facing is NaN (never edge-on) and the ray empty.
Ray ourShadowRay(const FrameParams& p, const PrimitivesView& prims, const Ray& primary, Hit h,
                 float& facing) {
    if (h.prim < 0 || uint32_t(h.prim) >= prims.count || !std::isfinite(h.t)) {
        facing = NAN;
        return Ray{};
    }
    const ShadowQuery q = shadowQuery(p.shading, prims, primary, h);
    facing = q.facing;
    return q.ray;
}

}  // namespace

FilmValidation validateFilm(const HitClassifier& c, const FrameParams& p, const Film& ours,
                            const Film& reference, const OcclusionQuery& referenceOccluded) {
    if (ours.width != p.width || ours.height != p.height || reference.width != p.width ||
        reference.height != p.height)
        throw std::invalid_argument("validateFilm: films of " + std::to_string(ours.width) + "x" +
                                    std::to_string(ours.height) + " and " +
                                    std::to_string(reference.width) + "x" +
                                    std::to_string(reference.height) + " for a frame of " +
                                    std::to_string(p.width) + "x" + std::to_string(p.height));
    const ValidationPolicy& pol = c.policy();
    const PrimitivesView prims = primitivesView(c.scene());
    const size_t n = ours.pixelCount();
    FilmValidation v;
    v.width = p.width;
    v.height = p.height;
    v.primaryClass.assign(n, 255);
    v.shadowClass.assign(n, 255);
    v.relativeDt.assign(n, 0.0f);

    // Pass 1, cheap: the policy's first step for every pixel; mismatches are queued.
    std::vector<uint32_t> primaryQueue, shadowQueue;
    std::vector<Verdict> primaryVerdict(n);
    for (size_t i = 0; i < n; ++i) {
        Hit o = {ours.t[i], ours.prim[i]}, r = {reference.t[i], reference.prim[i]};
        double rel = c.relativeDt(o, r);
        v.relativeDt[i] = float(rel);
        if (o.prim >= 0 && r.prim >= 0) raiseMax(v.primary.maxRelativeDt, rel);
        int x = int(i % size_t(p.width)), y = int(i / size_t(p.width));
        HitClass k = c.compare(primaryRay(p.camera, x, y, p.width, p.height), o, r);
        primaryVerdict[i].cls = k;
        if (k == HitClass::Wrong) {
            ++v.primary.mismatches;
            primaryQueue.push_back(uint32_t(i));
            continue;
        }
        if (o.prim < 0 && r.prim < 0) ++v.primary.bothMiss;
        // Shadow rays are compared where the primary hits agree; both must have cast one, or
        // the one that did not must be explained (a terminator).
        uint8_t so = ours.shadow[i], sr = reference.shadow[i];
        if (so == kNoShadowRay && sr == kNoShadowRay) continue;
        if (so != sr) {
            ++v.shadow.mismatches;
            shadowQueue.push_back(uint32_t(i));
        }
    }

    // Pass 2: rechecks in double, in parallel, each check within its own budget, so that a
    // flood of primary mismatches cannot leave the shadow rays unchecked.
    size_t nPrimary = std::min<size_t>(primaryQueue.size(), pol.maxRechecks);
    size_t nShadow = std::min<size_t>(shadowQueue.size(), pol.maxRechecks);
    parallelFor(nPrimary, [&](size_t k) {
        size_t i = primaryQueue[k];
        int x = int(i % size_t(p.width)), y = int(i / size_t(p.width));
        Ray ray = primaryRay(p.camera, x, y, p.width, p.height);
        primaryVerdict[i] =
            c.recheckClosest(ray, {ours.t[i], ours.prim[i]}, {reference.t[i], reference.prim[i]});
    });
    for (size_t k = nPrimary; k < primaryQueue.size(); ++k) {
        size_t i = primaryQueue[k];
        int x = int(i % size_t(p.width)), y = int(i / size_t(p.width));
        primaryVerdict[i] =
            overTheCap(c, primaryRay(p.camera, x, y, p.width, p.height), {ours.t[i], ours.prim[i]});
    }

    std::vector<ShadowFinding> shadowFindings(shadowQueue.size());
    parallelFor(shadowQueue.size(), [&](size_t k) {
        size_t i = shadowQueue[k];
        ShadowFinding& f = shadowFindings[k];
        f.x = int(i % size_t(p.width));
        f.y = int(i / size_t(p.width));
        f.ours = ours.shadow[i];
        f.reference = reference.shadow[i];
        Ray primary = primaryRay(p.camera, f.x, f.y, p.width, p.height);
        Hit o = {ours.t[i], ours.prim[i]}, r = {reference.t[i], reference.prim[i]};
        if (f.ours == kNoShadowRay || f.reference == kNoShadowRay) {
            // One surface faces the light and the other does not: legitimate for two primitives
            // meeting at an edge (a genuine tie: compare() checked that our primitive is at our
            // hit point), or for one primitive edge-on to the light. A different primitive that
            // is not a tie never gets here: it was a primary mismatch.
            float facingO = 0.0f, facingR = 0.0f;
            f.ray = ourShadowRay(p, prims, primary, o, facingO);
            ourShadowRay(p, prims, primary, r, facingR);
            bool edgeOn =
                std::fabs(facingO) <= pol.grazingCos || std::fabs(facingR) <= pol.grazingCos;
            bool tie = primaryVerdict[i].cls == HitClass::Tie;
            f.cls = tie || edgeOn ? HitClass::Ambiguous : HitClass::Wrong;
            f.reasons = f.cls == HitClass::Ambiguous ? uint32_t(kTerminator) : 0u;
            return;
        }
        float facing;
        f.ray = ourShadowRay(p, prims, primary, o, facing);
        bool oursOccluded = f.ours == kOccluded;
        if (referenceOccluded) {
            f.referenceOnOurRay = referenceOccluded(f.ray) ? 1 : 0;
            if ((f.referenceOnOurRay == 1) == oursOccluded) {
                f.cls = HitClass::Agree;  // the shadow rays differed, not the answers
                return;
            }
        }
        if (k >= nShadow) {
            f.cls = HitClass::Unverified;
            f.reasons = kNotRechecked;
            return;
        }
        Verdict vd = c.recheckOcclusion(f.ray, oursOccluded);
        f.cls = vd.cls;
        f.reasons = vd.reasons;
        f.truthOccluded = vd.truthOccluded ? 1 : 0;
    });

    // Pass 3: counts, maps and findings.
    std::vector<Candidate> candidates;
    std::vector<uint8_t> shadowFlag(n, 0);  // 1 queued, decided in shadowFindings
    for (size_t k = 0; k < shadowQueue.size(); ++k) shadowFlag[shadowQueue[k]] = 1;
    std::vector<uint8_t> primaryMismatch(n, 0);  // 1: queued for the recheck (or past the cap)
    for (uint32_t i : primaryQueue) primaryMismatch[i] = 1;
    for (size_t i = 0; i < n; ++i) {
        const Verdict& vd = primaryVerdict[i];
        Hit o = {ours.t[i], ours.prim[i]}, r = {reference.t[i], reference.prim[i]};
        const bool queued = primaryMismatch[i] != 0;
        HitClass k = vd.cls;
        v.primary.count(k, vd.reasons);
        v.primary.rechecked += vd.rechecked;
        bool bothMiss = o.prim < 0 && r.prim < 0;
        v.primaryClass[i] = bothMiss ? 255 : uint8_t(k);
        if (queued || k == HitClass::Tie || v.relativeDt[i] > 0.0f)
            candidates.push_back({severity(k), double(v.relativeDt[i]), i});
        if (queued) {
            if (ours.shadow[i] != kNoShadowRay || reference.shadow[i] != kNoShadowRay)
                ++v.shadowNotCompared;
            continue;
        }
        uint8_t so = ours.shadow[i], sr = reference.shadow[i];
        if (so == kNoShadowRay && sr == kNoShadowRay) continue;
        if (!shadowFlag[i]) {
            v.shadow.count(HitClass::Agree, 0);
            v.shadowClass[i] = uint8_t(HitClass::Agree);
        }
    }
    for (const ShadowFinding& f : shadowFindings) {
        v.shadow.count(f.cls, f.reasons);
        v.shadow.rechecked += f.truthOccluded >= 0;
        v.shadowResolvedByRerun += f.cls == HitClass::Agree;
        v.shadowClass[size_t(f.y) * size_t(p.width) + size_t(f.x)] = uint8_t(f.cls);
    }
    for (uint64_t i : worstIndices(candidates, pol.worstCount)) {
        const Verdict& vd = primaryVerdict[i];
        Finding f;
        f.x = int(i % size_t(p.width));
        f.y = int(i / size_t(p.width));
        f.index = i;
        f.cls = vd.cls;
        f.reasons = vd.reasons;
        f.ours = {ours.t[i], ours.prim[i]};
        f.reference = {reference.t[i], reference.prim[i]};
        f.rechecked = vd.rechecked;
        f.relativeDt = v.relativeDt[i];
        f.ray = primaryRay(p.camera, f.x, f.y, p.width, p.height);
        f.truth = c.truthOf(f.ray, vd);
        v.worstPixels.push_back(f);
    }
    keepWorst(shadowFindings, pol.worstCount, shadowDt);
    v.worstShadows = std::move(shadowFindings);
    return v;
}

}  // namespace oct
