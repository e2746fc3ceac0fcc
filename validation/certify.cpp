#include "validation/certify.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "cpu_ref/embree_tracer.h"
#include "cpu_ref/render_cpu.h"

namespace oct {
namespace {

// No primitive ids (--no-prim) and the distances disagree: the primitive is inferred in the
// recheck, as the one nearest to the reported hit point.
constexpr int32_t kUnknownPrim = INT32_MIN;

template <class F>
void parallelFor(size_t n, F&& f) {
#pragma omp parallel for schedule(dynamic, 64)
    for (int64_t i = 0; i < int64_t(n); ++i) f(size_t(i));
}

// A running maximum that a NaN cannot hide (it counts as +inf).
void raiseMax(double& m, double v) {
    if (std::isnan(v)) v = INFINITY;
    if (v > m) m = v;
}

// The t tolerance in units of the ray's t.
double tTolerance(const HitClassifier& c, const Ray& ray) {
    return c.policy().tTolerance * c.extent() / double(length(ray.dir));
}

// Our answer as the policy judges it. With primitive ids it is the pair as given. Without, a
// +inf t is a miss; a t that is not a distance in [tmin, tmax] keeps primitive 0 so that
// malformed() names it; a t within the tolerance of the reference's hit takes its primitive;
// any other t is a hit on a primitive still unknown.
Hit judged(const HitClassifier& c, const HitArrays& ours, uint64_t i, const Ray& ray, Hit ref) {
    if (ours.primIds) return {ours.t[i], ours.prim[i]};
    const float t = ours.t[i];
    if (t == INFINITY) return {INFINITY, -1};
    if (c.malformed(ray, {t, 0})) return {t, 0};
    if (ref.prim >= 0 && !c.malformed(ray, ref) &&
        std::fabs(double(t) - double(ref.t)) <= tTolerance(c, ray))
        return {t, ref.prim};
    return {t, kUnknownPrim};
}

// Candidates for the findings: wrong and ambiguous first, by row; then ties and agreements by
// the largest |dt|.
struct Candidate {
    int severity;
    float dt;
    uint64_t index;
};

bool before(const Candidate& a, const Candidate& b) {
    if (a.severity != b.severity) return a.severity > b.severity;
    if (a.severity >= int(HitClass::Ambiguous)) return a.index < b.index;
    float da = std::isnan(a.dt) ? INFINITY : a.dt, db = std::isnan(b.dt) ? INFINITY : b.dt;
    if (da != db) return da > db;
    return a.index < b.index;
}

}  // namespace

bool RayCertification::passes(double maxAmbiguousRate) const {
    for (const SetCertification& s : sets)
        if (!s.clean()) return false;
    return strict.ambiguousRate() <= maxAmbiguousRate;
}

TopologySummary summarize(const MeshTopology& t) {
    return {t.closed(), t.vertices.size(), t.edges.size(), t.boundaryEdges, t.nonManifoldEdges};
}

RayCertification certifyRays(const HitClassifier& c, const RaySet& rays, const HitArrays& ours,
                             const HitArrays& ref) {
    const uint64_t n = rays.count();
    if (ours.t.size() != n || (ours.primIds && ours.prim.size() != n) || ref.t.size() != n ||
        !ref.primIds || ref.prim.size() != n)
        throw std::invalid_argument(
            "certifyRays: " + std::to_string(n) + " rays but answer arrays of " +
            std::to_string(ours.t.size()) + ", " + std::to_string(ours.prim.size()) + ", " +
            std::to_string(ref.t.size()) + ", " + std::to_string(ref.prim.size()));
    for (const RaySetRange& s : rays.sets)
        if (s.begin > n || s.count > n - s.begin)
            throw std::invalid_argument("certifyRays: set '" + s.name + "' rows " +
                                        std::to_string(s.begin) + "+" + std::to_string(s.count) +
                                        " outside the " + std::to_string(n) + " rays");
    const ValidationPolicy& pol = c.policy();

    // Pass 1, cheap and parallel: the policy's first step for every ray.
    std::vector<uint8_t> cls(n);
    std::vector<uint32_t> why(n, 0);
    std::vector<float> rel(n);
    parallelFor(n, [&](size_t i) {
        const Ray ray = rays.ray(i);
        const Hit r = ref.at(i);
        const Hit o = judged(c, ours, i, ray, r);
        const bool unknown = o.prim == kUnknownPrim;
        rel[i] = float(c.relativeDt(unknown ? Hit{o.t, 0} : o, r, length(ray.dir)));
        cls[i] = uint8_t(unknown ? HitClass::Wrong : c.compare(ray, o, r));
    });

    // Pass 2: rechecks in double, each set within its own budget.
    std::vector<uint64_t> recheck;
    std::vector<uint8_t> queued(n, 0);  // 1 rechecked, 2 over the budget
    for (const RaySetRange& s : rays.sets) {
        uint64_t inSet = 0;
        for (uint64_t i = s.begin; i < s.begin + s.count; ++i) {
            if (cls[i] != uint8_t(HitClass::Wrong)) continue;
            if (inSet++ < pol.maxRechecks) {
                recheck.push_back(i);
                queued[i] = 1;
            } else {
                queued[i] = 2;
                const Ray ray = rays.ray(i);
                Hit o = judged(c, ours, i, ray, ref.at(i));
                if (o.prim == kUnknownPrim) o.prim = 0;
                why[i] = kNotRechecked | (c.malformed(o)        ? uint32_t(kInvalidHit)
                                          : c.malformed(ray, o) ? uint32_t(kOutsideRange)
                                                                : 0u);
            }
        }
    }
    std::vector<Verdict> verdict(recheck.size());
    std::vector<int32_t> inferred(recheck.size(), -1);
    parallelFor(recheck.size(), [&](size_t k) {
        const uint64_t i = recheck[k];
        const Ray ray = rays.ray(i);
        Hit o = judged(c, ours, i, ray, ref.at(i));
        if (o.prim == kUnknownPrim) {
            const DoubleRay dr = toDoubleRay(ray);
            const double t = double(o.t);
            double dist;
            o.prim = c.truth().nearestTo(dr.org + dr.dir * t, dist);
        }
        inferred[k] = o.prim;
        verdict[k] = c.recheckClosest(ray, o);
    });
    std::unordered_map<uint64_t, size_t> slot;
    for (size_t k = 0; k < recheck.size(); ++k) {
        cls[recheck[k]] = uint8_t(verdict[k].cls);
        why[recheck[k]] = verdict[k].reasons;
        slot[recheck[k]] = k;
    }

    // Pass 3: the leak check of the targets, each set within its own budget.
    std::vector<LeakFinding> leaks(rays.targets.size());
    std::vector<uint8_t> leakState(rays.targets.size(), 0);  // 0 fine, 1 leak, 2 unsealed
    {
        std::vector<size_t> candidates;
        std::unordered_map<std::string, uint64_t> perSet;
        for (size_t k = 0; k < rays.targets.size(); ++k) {
            const RayTarget& tg = rays.targets[k];
            if (tg.row >= n) throw std::invalid_argument("certifyRays: target row beyond the rays");
            const Ray ray = rays.ray(tg.row);
            const float t = ours.t[tg.row];
            // A hit, well formed, at or before the target: t in [tmin, tmax] and a primitive id
            // (when given) in range.
            const Hit o = ours.primIds ? Hit{t, ours.prim[tg.row]} : Hit{t, t == INFINITY ? -1 : 0};
            const bool hitBefore =
                o.prim >= 0 && !c.malformed(ray, o) && double(t) <= tg.t + tTolerance(c, ray);
            if (hitBefore) continue;
            LeakFinding& f = leaks[k];
            f.index = tg.row;
            f.target = tg;
            f.got = o;
            f.ray = ray;
            for (const RaySetRange& s : rays.sets)
                if (tg.row >= s.begin && tg.row < s.begin + s.count) f.set = s.name;
            if (perSet[f.set]++ < pol.maxRechecks) {
                candidates.push_back(k);
            } else {
                f.rechecked = false;
                leakState[k] = 1;
            }
        }
        parallelFor(candidates.size(), [&](size_t m) {
            const size_t k = candidates[m];
            LeakFinding& f = leaks[k];
            f.truth = c.truth().closest(toDoubleRay(f.ray));
            const bool sealed =
                f.truth.prim >= 0 && double(f.truth.t) <= f.target.t + tTolerance(c, f.ray);
            leakState[k] = sealed ? 1 : 2;
        });
    }

    // Pass 4: counts and findings per set.
    RayCertification out;
    for (const RaySetRange& s : rays.sets) {
        SetCertification sc;
        sc.range = s;
        const RaySetDesc* kind = findRaySet(s.name);
        sc.adversarial = kind && kind->adversarial;
        std::vector<Candidate> cand;
        const bool camera = s.name == "camera";
        if (camera) {
            out.cameraClass.assign(s.count, 255);
            out.cameraRelativeDt.assign(s.count, 0.0f);
        }
        for (uint64_t i = s.begin; i < s.begin + s.count; ++i) {
            const HitClass k = HitClass(cls[i]);
            sc.counts.count(k, why[i]);
            const bool mismatch = queued[i] != 0;
            sc.counts.mismatches += mismatch;
            sc.counts.rechecked += queued[i] == 1;
            const bool oMiss = ours.t[i] == INFINITY && (!ours.primIds || ours.prim[i] == -1);
            const bool rMiss = ref.prim[i] < 0;
            const bool bothMiss = oMiss && rMiss;
            sc.counts.bothMiss += bothMiss;
            if (!oMiss && !rMiss) raiseMax(sc.counts.maxRelativeDt, rel[i]);
            if (mismatch || k == HitClass::Tie || rel[i] > 0.0f)
                cand.push_back({int(k), rel[i], i});
            if (camera) {
                out.cameraClass[i - s.begin] = bothMiss ? 255 : uint8_t(k);
                out.cameraRelativeDt[i - s.begin] = rel[i];
            }
        }
        const size_t keep = std::min(cand.size(), size_t(std::max(pol.worstCount, 0)));
        std::partial_sort(cand.begin(), cand.begin() + keep, cand.end(), before);
        for (size_t m = 0; m < keep; ++m) {
            const uint64_t i = cand[m].index;
            Finding f;
            f.index = i;
            f.set = s.name;
            f.cls = HitClass(cls[i]);
            f.reasons = why[i];
            f.ray = rays.ray(i);
            f.reference = ref.at(i);
            f.ours = judged(c, ours, i, f.ray, f.reference);
            auto it = slot.find(i);
            if (it != slot.end()) {
                f.rechecked = true;
                f.truth = verdict[it->second].truth;
                f.ours.prim = inferred[it->second];
            } else if (f.ours.prim == kUnknownPrim) {
                f.ours.prim = 0;  // over the budget: never inferred
            }
            f.relativeDt = rel[i];
            sc.worst.push_back(f);
        }
        for (size_t k = 0; k < rays.targets.size(); ++k) {
            const RayTarget& tg = rays.targets[k];
            if (tg.row < s.begin || tg.row >= s.begin + s.count) continue;
            ++sc.leakChecked;
            if (leakState[k] == 2) ++sc.unsealed;
            if (leakState[k] != 1) continue;
            ++sc.leaks;
            if (int(sc.leakList.size()) < pol.worstCount) sc.leakList.push_back(leaks[k]);
        }
        out.all.merge(sc.counts);
        if (!sc.adversarial) out.strict.merge(sc.counts);
        out.leakChecked += sc.leakChecked;
        out.leaks += sc.leaks;
        out.unsealed += sc.unsealed;
        out.sets.push_back(std::move(sc));
    }
    // Over all sets: the same order, the most severe first.
    std::vector<std::pair<Candidate, const Finding*>> all;
    for (const SetCertification& sc : out.sets)
        for (const Finding& f : sc.worst)
            all.push_back({{int(f.cls), float(f.relativeDt), f.index}, &f});
    std::stable_sort(all.begin(), all.end(),
                     [](const auto& a, const auto& b) { return before(a.first, b.first); });
    for (size_t m = 0; m < all.size() && int(m) < pol.worstCount; ++m)
        out.worst.push_back(*all[m].second);
    return out;
}

FilmValidation cameraDiff(const RayCertification& r, const RaySet& rays) {
    const RaySetRange* cam = rays.find("camera");
    if (!cam || !rays.frame || r.cameraClass.size() != cam->count ||
        cam->count != uint64_t(rays.frame->width) * uint64_t(rays.frame->height))
        throw std::invalid_argument(
            "a diff image needs the camera set of a ray file made by "
            "octrace rays (with its manifest)");
    FilmValidation v;
    v.width = rays.frame->width;
    v.height = rays.frame->height;
    v.primaryClass = r.cameraClass;
    v.shadowClass.assign(cam->count, 255);
    v.relativeDt = r.cameraRelativeDt;
    return v;
}

CertifyReport certifyTracer(const Scene& scene, const RaySet& rays, const HitArrays& ours,
                            const ValidationPolicy& policy) {
    const auto start = std::chrono::steady_clock::now();
    auto since = [](std::chrono::steady_clock::time_point t) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    };
    CertifyReport rep;
    rep.primIds = ours.primIds;
    if (scene.kind == PrimKind::Triangles) rep.topology = summarize(meshTopology(scene));
    HitClassifier classifier(scene, policy);
    static_cast<JudgedScene&>(rep) = judgedScene(scene, classifier);

    auto t0 = std::chrono::steady_clock::now();
    HitArrays ref;
    ref.t.resize(rays.count());
    ref.prim.resize(rays.count());
    {
        EmbreeTracer embree(scene);  // robust mode: the reference of docs/VALIDATION.md
        traceRaysCpu(embree.accel(),
                     RayBatchView{rays.rays.data(), ref.t.data(), ref.prim.data(), rays.count()});
    }
    rep.referenceSeconds = since(t0);
    t0 = std::chrono::steady_clock::now();
    rep.result = certifyRays(classifier, rays, ours, ref);
    rep.checkSeconds = since(t0);
    rep.seconds = since(start);
    return rep;
}

}  // namespace oct
