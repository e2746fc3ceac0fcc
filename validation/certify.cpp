#include "validation/certify.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <type_traits>
#include <unordered_map>

#include "cpu_ref/embree_tracer.h"
#include "cpu_ref/render_cpu.h"
#include "validation/ambiguity_bound.h"

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
        std::fabs(double(t) - double(ref.t)) <= c.tTolerance(ray))
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
    if (a.severity >= hitSeverity(HitClass::Ambiguous)) return a.index < b.index;
    float da = std::isnan(a.dt) ? INFINITY : a.dt, db = std::isnan(b.dt) ? INFINITY : b.dt;
    if (da != db) return da > db;
    return a.index < b.index;
}

// The report's record of row i.
Finding finding(const HitClassifier& c, const RaySet& rays, const HitArrays& ours,
                const HitArrays& ref, const std::vector<uint8_t>& cls,
                const std::vector<uint32_t>& why, const std::vector<float>& rel,
                const std::unordered_map<uint64_t, size_t>& slot,
                const std::vector<Verdict>& verdict, const std::vector<int32_t>& inferred,
                uint64_t i, const std::string& set) {
    Finding f;
    f.index = i;
    f.set = set;
    f.cls = HitClass(cls[i]);
    f.reasons = why[i];
    f.ray = rays.ray(i);
    f.reference = ref.at(i);
    f.ours = judged(c, ours, i, f.ray, f.reference);
    auto it = slot.find(i);
    if (it != slot.end()) {
        f.rechecked = true;
        f.truth = c.truthOf(f.ray, verdict[it->second]);
        f.ours.prim = inferred[it->second];
    } else if (f.ours.prim == kUnknownPrim) {
        f.ours.prim = 0;  // past the cap: never inferred
    }
    f.relativeDt = rel[i];
    return f;
}
}  // namespace

const char* outcomeName(Outcome o) {
    switch (o) {
        case Outcome::Pass:
            return "PASS";
        case Outcome::Fail:
            return "FAIL";
        case Outcome::Incomplete:
            return "INCOMPLETE";
        case Outcome::NotTested:
            return "not tested";
    }
    return "?";
}

Outcome worse(Outcome a, Outcome b) {
    auto rank = [](Outcome o) { return o == Outcome::Fail ? 2 : o == Outcome::Incomplete ? 1 : 0; };
    return rank(a) >= rank(b) ? (rank(a) == 0 ? Outcome::Pass : a) : b;
}

Outcome RayCertification::correct(double maxAmbiguousRate) const {
    if (all.compared == 0) return Outcome::NotTested;
    if (all.wrong > 0 || strict.ambiguousRate() > maxAmbiguousRate) return Outcome::Fail;
    if (!setsOverAmbiguousLimit().empty()) return Outcome::Fail;
    return all.unverified > 0 ? Outcome::Incomplete : Outcome::Pass;
}

std::string RayCertification::setsOverAmbiguousLimit() const {
    std::string over;
    for (const SetCertification& s : sets)
        if (!s.withinAmbiguousLimit()) over += (over.empty() ? "" : ", ") + s.range.name;
    return over;
}

Outcome RayCertification::watertight() const {
    if (leaks > 0) return Outcome::Fail;
    if (leakUnverified > 0) return Outcome::Incomplete;
    return leakChecked > 0 ? Outcome::Pass : Outcome::NotTested;
}

TopologySummary summarize(const MeshTopology& t) {
    return {t.closed(), t.vertices.size(), t.edges.size(), t.boundaryEdges, t.nonManifoldEdges};
}

namespace {

// The query kind of a set: the table's for a standard set, the user's choice for their own.
QueryKind queryOf(const RaySetRange& s, const CertifyOptions& o) {
    const RaySetDesc* d = findRaySet(s.name);
    if (!d) return o.ownSets;
    return d->anyHit ? QueryKind::AnyHit : QueryKind::Closest;
}

// A query past the recheck cap: malformed answers are wrong without a recheck (O(1)), any
// other is unverified.
void overTheCap(const HitClassifier& c, const Ray& ray, Hit o, uint8_t& cls, uint32_t& why) {
    if (c.malformed(ray, o)) {
        cls = uint8_t(HitClass::Wrong);
        why = c.malformed(o) ? uint32_t(kInvalidHit) : uint32_t(kOutsideRange);
    } else {
        cls = uint8_t(HitClass::Unverified);
        why = kNotRechecked;
    }
}

}  // namespace

RayCertification certifyRays(const HitClassifier& c, const RaySet& rays, const HitArrays& ours,
                             const HitArrays& ref, const CertifyOptions& options,
                             const NextReferenceHit& next) {
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
    // This process's rows (RowShare), and the merge of an array filled for them only.
    const RowShare* share = options.share;
    if (share && (share->block == 0 || share->index >= share->count))
        throw std::invalid_argument("certifyRays: a share of blocks of " +
                                    std::to_string(share->block) + " rows, process " +
                                    std::to_string(share->index) + " of " +
                                    std::to_string(share->count));
    auto mine = [share](uint64_t row) { return !share || share->owns(row); };
    auto combine = [share](auto& v) {
        using T = typename std::decay_t<decltype(v)>::value_type;
        static_assert(std::is_trivially_copyable_v<T>);
        if (share) share->combine(v.data(), uint64_t(v.size()) * sizeof(T));
    };
    // Each row's query kind, from its set (rows outside every set are closest-hit queries).
    std::vector<uint8_t> anyHit(n, 0);
    for (const RaySetRange& s : rays.sets)
        if (queryOf(s, options) == QueryKind::AnyHit)
            std::fill(anyHit.begin() + s.begin, anyHit.begin() + s.begin + s.count, 1);

    // Pass 1, cheap and parallel: the policy's first step for every ray (of this process).
    std::vector<uint8_t> cls(n, 0);
    std::vector<uint32_t> why(n, 0);
    std::vector<float> rel(n, 0.0f);
    parallelFor(n, [&](size_t i) {
        if (!mine(i)) return;
        const Ray ray = rays.ray(i);
        const Hit r = ref.at(i);
        const Hit o = judged(c, ours, i, ray, r);
        const bool unknown = o.prim == kUnknownPrim;
        rel[i] = float(c.relativeDt(unknown ? Hit{o.t, 0} : o, r, length(ray.dir)));
        if (unknown)
            cls[i] = uint8_t(HitClass::Wrong);
        else
            cls[i] = uint8_t(anyHit[i] ? c.compareAnyHit(ray, o, r) : c.compare(ray, o, r));
    });
    combine(cls);
    combine(rel);

    // Pass 2: rechecks in double of every mismatch (each set up to the user's cap, if any).
    std::vector<uint64_t> recheck;
    std::vector<uint8_t> queued(n, 0);  // 1 rechecked, 2 past the cap
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
                overTheCap(c, ray, o, cls[i], why[i]);
            }
        }
    }
    // Zero bytes where another process rechecks (combine).
    std::vector<Verdict> verdict(recheck.size());
    static_assert(std::is_trivially_copyable_v<Verdict>);
    if (!verdict.empty())
        std::memset(static_cast<void*>(verdict.data()), 0, verdict.size() * sizeof(Verdict));
    std::vector<int32_t> inferred(recheck.size(), 0);
    parallelFor(recheck.size(), [&](size_t k) {
        const uint64_t i = recheck[k];
        if (!mine(i)) return;
        const Ray ray = rays.ray(i);
        Hit o = judged(c, ours, i, ray, ref.at(i));
        if (o.prim == kUnknownPrim) {  // --no-prim: the primitive the reported point is on
            bool on;
            o.prim = c.surfacePrimitive(ray, o.t, on);
        }
        inferred[k] = o.prim;
        const Hit r = ref.at(i);
        Hit last = r;  // each call: the reference's next hit beyond the last one given
        const std::function<Hit()> more = [&next, &last, i]() {
            last = next && last.prim >= 0 ? next(i, last) : Hit{INFINITY, -1};
            return last;
        };
        verdict[k] =
            anyHit[i] ? c.recheckAnyHit(ray, o, r, &more) : c.recheckClosest(ray, o, r, &more);
    });
    combine(verdict);
    combine(inferred);
    std::unordered_map<uint64_t, size_t> slot;
    for (size_t k = 0; k < recheck.size(); ++k) {
        cls[recheck[k]] = uint8_t(verdict[k].cls);
        why[recheck[k]] = verdict[k].reasons;
        slot[recheck[k]] = k;
    }

    // Pass 3: the leak check of the targets. A target the generator could not seal tests
    // nothing (unsealed). A sealed one passes when the ray stopped on the surface (on its
    // reported primitive or, where the id is wrong or absent, on any) at or before the target,
    // within the t tolerance or the float error bound of that primitive (a sliver's t may
    // legitimately run late: hitTError); any other answer is a candidate, a leak when the truth
    // meets the target's sealed surface on the stored ray.
    std::vector<uint8_t> leak(n, uint8_t(LeakState::NotTarget));
    std::vector<LeakFinding> leaks(rays.targets.size());
    {
        std::vector<size_t> candidates;
        std::unordered_map<std::string, uint64_t> perSet;
        std::vector<uint8_t> isCandidate(rays.targets.size(), 0);
        std::vector<Hit> got(rays.targets.size(), Hit{0.0f, 0});  // zero bytes: combine
        parallelFor(rays.targets.size(), [&](size_t k) {
            const RayTarget& tg = rays.targets[k];
            if (tg.row >= n || !tg.sealed || !mine(tg.row)) return;
            const Ray ray = rays.ray(tg.row);
            const float t = ours.t[tg.row];
            Hit o = ours.primIds ? Hit{t, ours.prim[tg.row]} : Hit{t, t == INFINITY ? -1 : 0};
            got[k] = o;
            // Watertightness asks whether the ray stopped on the surface, not which primitive
            // it names (the per-ray check judges that): a point on the surface but off its
            // reported primitive stopped there.
            if (o.prim >= 0 && !c.malformed(ray, o) && !(ours.primIds && c.onSurface(ray, o))) {
                bool on;
                const int32_t p = c.surfacePrimitive(ray, t, on);
                if (on || !ours.primIds) o.prim = p;
            }
            const bool sealedHere =
                o.prim >= 0 && c.onSurface(ray, o) &&
                double(t) <= tg.t + std::max(c.tTolerance(ray), c.hitTError(ray, o.prim));
            isCandidate[k] = !sealedHere;
        });
        combine(isCandidate);
        combine(got);
        for (size_t k = 0; k < rays.targets.size(); ++k) {
            const RayTarget& tg = rays.targets[k];
            if (tg.row >= n) throw std::invalid_argument("certifyRays: target row beyond the rays");
            if (tg.sealed) leaks[k].got = got[k];
            if (!tg.sealed) {
                leak[tg.row] = uint8_t(LeakState::Unsealed);
                continue;
            }
            if (!isCandidate[k]) {
                leak[tg.row] = uint8_t(LeakState::Sealed);
                continue;
            }
            LeakFinding& f = leaks[k];
            f.index = tg.row;
            f.target = tg;
            f.ray = rays.ray(tg.row);
            for (const RaySetRange& s : rays.sets)
                if (tg.row >= s.begin && tg.row < s.begin + s.count) f.set = s.name;
            if (!tg.triangles.empty()) {
                // Sealed by its generator in this run (the rows were rebuilt): the truth meets
                // one of the target's own triangles at the target; no search needed.
                leak[tg.row] = uint8_t(LeakState::Leak);
            } else if (perSet[f.set]++ < pol.maxRechecks) {
                candidates.push_back(k);
            } else {
                f.rechecked = false;
                leak[tg.row] = uint8_t(LeakState::Unverified);
            }
        }
        // Each candidate's truth and state, by the process owning its row (zero bytes elsewhere).
        std::vector<Hit> truth(candidates.size(), Hit{0.0f, 0});
        std::vector<uint8_t> state(candidates.size(), 0);
        parallelFor(candidates.size(), [&](size_t m) {
            const LeakFinding& f = leaks[candidates[m]];
            if (!mine(f.index)) return;
            truth[m] = c.truth().closest(toDoubleRay(f.ray));
            // The truth meets the target: one of its own triangles when the generator names
            // them (edges, vertices), else anything at or before it (the slivers square).
            const std::vector<uint32_t>& own = f.target.triangles;
            const bool onTarget =
                own.empty() || std::binary_search(own.begin(), own.end(), uint32_t(truth[m].prim));
            const bool sealed = truth[m].prim >= 0 && onTarget &&
                                double(truth[m].t) <= f.target.t + c.tTolerance(f.ray);
            state[m] = uint8_t(sealed ? LeakState::Leak : LeakState::Unsealed);
        });
        combine(truth);
        combine(state);
        for (size_t m = 0; m < candidates.size(); ++m) {
            LeakFinding& f = leaks[candidates[m]];
            f.truth = truth[m];
            leak[f.index] = state[m];
        }
    }

    // Pass 4: counts and findings per set.
    RayCertification out;
    const bool baseline = rays.baseline && baselineApplies(*rays.baseline, pol);
    out.baselineIgnored = rays.baseline && !baseline;
    for (size_t si = 0; si < rays.sets.size(); ++si) {
        const RaySetRange& s = rays.sets[si];
        SetCertification sc;
        sc.range = s;
        const RaySetDesc* desc = findRaySet(s.name);
        sc.adversarial = desc && desc->adversarial;
        sc.query = queryOf(s, options);
        std::vector<Candidate> cand;
        const bool camera = s.name == "camera";
        if (camera) {
            out.cameraClass.assign(s.count, 255);
            out.cameraRelativeDt.assign(s.count, 0.0f);
        }
        for (uint64_t i = s.begin; i < s.begin + s.count; ++i) {
            const HitClass k = HitClass(cls[i]);
            sc.counts.count(k, why[i]);
            sc.ambiguousCounted += k == HitClass::Ambiguous && leak[i] != uint8_t(LeakState::Leak);
            const bool mismatch = queued[i] != 0;
            sc.counts.mismatches += mismatch;
            sc.counts.rechecked += queued[i] == 1;
            const bool oMiss = ours.t[i] == INFINITY && (!ours.primIds || ours.prim[i] == -1);
            const bool rMiss = ref.prim[i] < 0;
            const bool bothMiss = oMiss && rMiss;
            sc.counts.bothMiss += bothMiss;
            if (!oMiss && !rMiss) raiseMax(sc.counts.maxRelativeDt, rel[i]);
            if (mismatch || k == HitClass::Tie || rel[i] > 0.0f)
                cand.push_back({hitSeverity(k), rel[i], i});
            if (camera) {
                out.cameraClass[i - s.begin] = bothMiss ? 255 : uint8_t(k);
                out.cameraRelativeDt[i - s.begin] = rel[i];
            }
            switch (LeakState(leak[i])) {
                case LeakState::Sealed:
                    ++sc.leakChecked;
                    break;
                case LeakState::Leak:
                    ++sc.leakChecked;
                    ++sc.leaks;
                    break;
                case LeakState::Unsealed:
                    ++sc.unsealed;
                    break;
                case LeakState::Unverified:
                    ++sc.leakUnverified;
                    break;
                case LeakState::NotTarget:
                    break;
            }
        }
        if (baseline && si < rays.baseline->ambiguous.size())
            sc.expectedAmbiguous = rays.baseline->ambiguous[si];
        sc.ambiguousLimit = ambiguousLimit(s.count, sc.expectedAmbiguous, sc.adversarial, pol,
                                           ambiguousSlack(s.name));
        const size_t keep = std::min(cand.size(), size_t(std::max(pol.worstCount, 0)));
        std::partial_sort(cand.begin(), cand.begin() + keep, cand.end(), before);
        for (size_t m = 0; m < keep; ++m)
            sc.worst.push_back(finding(c, rays, ours, ref, cls, why, rel, slot, verdict, inferred,
                                       cand[m].index, s.name));
        for (size_t k = 0; k < rays.targets.size(); ++k) {
            const RayTarget& tg = rays.targets[k];
            if (tg.row < s.begin || tg.row >= s.begin + s.count) continue;
            if (leak[tg.row] != uint8_t(LeakState::Leak)) continue;
            if (int(sc.leakList.size()) >= pol.worstCount) continue;
            LeakFinding f = leaks[k];
            if (!tg.triangles.empty()) f.truth = c.truth().closest(toDoubleRay(f.ray));
            sc.leakList.push_back(f);
        }
        out.all.merge(sc.counts);
        if (!sc.adversarial) out.strict.merge(sc.counts);
        out.leakChecked += sc.leakChecked;
        out.leaks += sc.leaks;
        out.unsealed += sc.unsealed;
        out.leakUnverified += sc.leakUnverified;
        out.sets.push_back(std::move(sc));
    }
    // Over all sets: the same order, the most severe first.
    std::vector<std::pair<Candidate, const Finding*>> all;
    for (const SetCertification& sc : out.sets)
        for (const Finding& f : sc.worst)
            all.push_back({{hitSeverity(f.cls), float(f.relativeDt), f.index}, &f});
    std::stable_sort(all.begin(), all.end(),
                     [](const auto& a, const auto& b) { return before(a.first, b.first); });
    for (size_t m = 0; m < all.size() && int(m) < pol.worstCount; ++m)
        out.worst.push_back(*all[m].second);
    // Examples: the first row of every (class, reason) that occurred, in row order, each row
    // once; a class without reasons (a tie) by its first row.
    {
        std::vector<uint64_t> first(size_t(kHitClassCount) * (kReasonCount + 1), UINT64_MAX);
        for (uint64_t i = 0; i < n; ++i) {
            const int k = cls[i];
            if (k == int(HitClass::Agree)) continue;
            const size_t base = size_t(k) * (kReasonCount + 1);
            if (first[base + kReasonCount] == UINT64_MAX) first[base + kReasonCount] = i;
            for (int b = 0; b < kReasonCount; ++b)
                if ((why[i] >> b & 1u) && first[base + size_t(b)] == UINT64_MAX)
                    first[base + size_t(b)] = i;
        }
        std::vector<uint64_t> rows;
        for (uint64_t r : first)
            if (r != UINT64_MAX) rows.push_back(r);
        std::sort(rows.begin(), rows.end());
        rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
        for (uint64_t i : rows) {
            std::string set;
            for (const RaySetRange& s : rays.sets)
                if (i >= s.begin && i < s.begin + s.count) set = s.name;
            out.examples.push_back(
                finding(c, rays, ours, ref, cls, why, rel, slot, verdict, inferred, i, set));
        }
    }
    out.rayClass = std::move(cls);
    out.rayReasons = std::move(why);
    out.rayLeak = std::move(leak);
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

const char* requireName(Require r) {
    return r == Require::Correct ? "correct" : r == Require::Watertight ? "watertight" : "all";
}

Outcome CertifyReport::outcome() const {
    if (cameraRowsOff()) return Outcome::Fail;
    const Outcome c = result.correct(policy.maxAmbiguousRate), w = result.watertight();
    switch (require) {
        case Require::Correct:
            return worse(c, Outcome::Pass);
        case Require::Watertight:
            return w == Outcome::NotTested ? Outcome::Incomplete : w;
        case Require::All:
            break;
    }
    return worse(c, w);
}

CertifyReport certifyTracer(const Scene& scene, const RaySet& rays, const HitArrays& ours,
                            const ValidationPolicy& policy, const CertifyOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    const HitClassifier classifier(scene, policy);
    CertifyReport rep = certifyTracer(classifier, rays, ours, options);
    rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return rep;
}

CertifyReport certifyTracer(const HitClassifier& classifier, const RaySet& rays,
                            const HitArrays& ours, const CertifyOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    auto since = [](std::chrono::steady_clock::time_point t) {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    };
    const Scene& scene = classifier.scene();
    CertifyReport rep;
    rep.primIds = ours.primIds;
    if (scene.kind == PrimKind::Triangles)
        rep.topology = summarize(rays.mesh ? rays.mesh->topology : meshTopology(scene));
    static_cast<JudgedScene&>(rep) = judgedScene(scene, classifier);
    for (const RaySetDesc& d : standardRaySets())
        if (!rays.find(d.name) && raySetMisfit(d, scene).empty()) rep.missingSets.push_back(d.name);

    auto t0 = std::chrono::steady_clock::now();
    HitArrays ref;
    ref.t.resize(rays.count());  // zeros: a RowShare merges the rows of every process
    ref.prim.resize(rays.count());
    EmbreeTracer embree(scene);  // robust mode: the reference of docs/VALIDATION.md
    const uint64_t n = rays.count();
    const RowShare* share = options.share;
    // This process's blocks (all rows without a share), each traced in place.
    const uint64_t block = share ? std::max<uint64_t>(share->block, 1) : std::max<uint64_t>(n, 1);
    const uint64_t step = share ? block * share->count : block;
    for (uint64_t b = share ? block * share->index : 0; b < n; b += step) {
        const uint64_t m = std::min(block, n - b);
        traceRaysCpu(embree.accel(), RayBatchView{rays.rays.data() + 8 * b, ref.t.data() + b,
                                                  ref.prim.data() + b, m});
    }
    if (options.share) {
        options.share->combine(ref.t.data(), ref.t.size() * sizeof(float));
        options.share->combine(ref.prim.data(), ref.prim.size() * sizeof(int32_t));
    }
    rep.referenceSeconds = since(t0);
    t0 = std::chrono::steady_clock::now();
    // The reference's next hit beyond its first, for the rechecks that need a witness (a miss
    // of ours where its first hit is touchy).
    const EmbreeAccel accel = embree.accel();
    const NextReferenceHit next = [&rays, accel](uint64_t i, Hit after) {
        float row[8];
        std::memcpy(row, &rays.rays[8 * i], sizeof row);
        row[6] = std::max(row[6], std::nextafter(after.t, INFINITY));
        Hit h{INFINITY, -1};
        if (!(row[6] <= row[7])) return h;
        traceRayAt(0, accel, RayBatchView{row, &h.t, &h.prim, 1});
        return h;
    };
    rep.result = certifyRays(classifier, rays, ours, ref, options, next);
    rep.cameraRows = rays.cameraRows;
    rep.checkSeconds = since(t0);
    rep.seconds = since(start);
    return rep;
}

}  // namespace oct
