#include "teach/explain.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "core/io/ray_file.h"
#include "core/octree/skip_reasons.h"
#include "core/render/kernel.h"
#include "teach/teach_error.h"

namespace oct {

// --- the recorder ----------------------------------------------------------------------------

void StepRecorder::boxTested(uint64_t key, int depth, const Aabb& box, bool hit, float t0,
                             float t1) {
    ExplainStep s;
    s.event = StepEvent::Box;
    s.key = key;
    s.depth = depth;
    s.box = box;
    s.hit = hit;
    if (hit) {
        s.t0 = t0;
        s.t1 = t1;
    }
    steps.push_back(s);
}

void StepRecorder::childSkipped(uint64_t key, SkipReason why) {
    ExplainStep s;
    s.event = StepEvent::Skip;
    s.key = key;
    s.why = why;
    steps.push_back(s);
}

void StepRecorder::nodePopped(uint64_t key, float tEnter, bool visited) {
    ExplainStep s;
    s.event = StepEvent::Pop;
    s.key = key;
    s.t0 = tEnter;
    s.hit = visited;
    if (!visited) s.why = SkipReason::BeyondHit;
    steps.push_back(s);
}

void StepRecorder::primTested(uint32_t prim, bool hit, float t) {
    ExplainStep s;
    s.event = StepEvent::Prim;
    s.prim = prim;
    s.hit = hit;
    if (hit) s.t0 = t;  // undefined on a miss
    steps.push_back(s);
}

void StepRecorder::hashProbe(uint64_t key, uint64_t bucket, uint32_t slot, uint64_t slotKey) {
    ExplainStep s;
    s.event = StepEvent::Probe;
    s.key = key;
    s.bucket = bucket;
    s.slot = slot;
    s.slotKey = slotKey;
    s.hit = slotKey == key;
    steps.push_back(s);
}

void StepRecorder::finish(const Ray& ray) {
    const RaySlabs slabs = makeRaySlabs(ray.org, ray.dir);
    // Every layout searches [tmin, best] with best starting at tmax (initialHit) and shrinking
    // to each nearer primitive hit (considerPrimitive); a box is tested against that interval.
    float best = ray.tmax;
    for (ExplainStep& s : steps) {
        s.bestT = best;
        if (s.event == StepEvent::Prim && s.hit) best = std::min(best, s.t0);
        if (s.event == StepEvent::Box && !s.hit) {
            float t0, t1;
            if (intersectBox(slabs, s.box, ray.tmin, ray.tmax, t0, t1)) {
                s.why = SkipReason::BeyondHit;
                s.t0 = t0;
                s.t1 = t1;
            }
        }
    }
}

std::map<uint64_t, int> visitOrder(const std::vector<ExplainStep>& steps) {
    std::map<uint64_t, int> order;
    for (const ExplainStep& s : steps)
        if (s.event == StepEvent::Pop && s.hit && !order.count(s.key))
            order.emplace(s.key, int(order.size()) + 1);
    return order;
}

StepTotals countSteps(const std::vector<ExplainStep>& steps) {
    StepTotals t;
    for (size_t i = 0; i < steps.size(); ++i) {
        const ExplainStep& s = steps[i];
        switch (s.event) {
            case StepEvent::Box:
                ++t.boxTests;
                t.boxesHit += s.hit;
                break;
            case StepEvent::Skip:
                ++t.skipped;
                break;
            case StepEvent::Pop:
                t.entered += s.hit;
                t.dropped += !s.hit;
                break;
            case StepEvent::Prim:
                ++t.primTests;
                t.primHits += s.hit;
                break;
            case StepEvent::Probe:
                ++t.probes;
                // A lookup is a run of probes for one key that ends where the key is found.
                t.lookups += i == 0 || steps[i - 1].event != StepEvent::Probe ||
                             steps[i - 1].key != s.key || steps[i - 1].hit;
                break;
        }
    }
    return t;
}

// --- why a ray misses a box ------------------------------------------------------------------

namespace {

const char* kAxis[3] = {"x", "y", "z"};

double comp(Vec3 v, int a) { return a == 0 ? v.x : a == 1 ? v.y : v.z; }

std::string fmt(const char* f, double a) {
    char b[64];
    std::snprintf(b, sizeof b, f, a);
    return b;
}
std::string num(double v) { return std::isinf(v) ? (v > 0 ? "inf" : "-inf") : fmt("%.6g", v); }
std::string vec(Vec3 v) { return "(" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + ")"; }
std::string slab(const Aabb& b, int a) {
    return std::string(kAxis[a]) + " slab [" + num(comp(b.lo, a)) + ", " + num(comp(b.hi, a)) + "]";
}

double boxDistance(const Aabb& b, double p[3]) {
    double d2 = 0;
    for (int a = 0; a < 3; ++a) {
        const double lo = comp(b.lo, a), hi = comp(b.hi, a);
        const double e = p[a] < lo ? lo - p[a] : p[a] > hi ? p[a] - hi : 0.0;
        d2 += e * e;
    }
    return std::sqrt(d2);
}

}  // namespace

BoxMiss analyseBoxMiss(const Ray& ray, const Aabb& box) {
    BoxMiss m;
    double nearT[3], farT[3];
    int parallelOutside = -1;
    for (int a = 0; a < 3; ++a) {
        const double o = comp(ray.org, a), d = comp(ray.dir, a);
        const double lo = comp(box.lo, a), hi = comp(box.hi, a);
        if (d == 0.0) {
            nearT[a] = -INFINITY;
            farT[a] = INFINITY;
            if ((o < lo || o > hi) && parallelOutside < 0) parallelOutside = a;
        } else {
            const double ta = (lo - o) / d, tb = (hi - o) / d;
            nearT[a] = std::min(ta, tb);
            farT[a] = std::max(ta, tb);
        }
    }
    const int enterLast = int(std::max_element(nearT, nearT + 3) - nearT);
    const int leaveFirst = int(std::min_element(farT, farT + 3) - farT);
    if (parallelOutside >= 0) {
        const int a = parallelOutside;
        m.reason = "the ray runs parallel to the " + slab(box, a) + " at " + kAxis[a] + " = " +
                   num(comp(ray.org, a)) + ", outside it";
    } else if (farT[leaveFirst] < ray.tmin) {
        m.reason = "the box is behind the ray: it leaves the " + slab(box, leaveFirst) +
                   " at t = " + num(farT[leaveFirst]) + ", before its start t = " + num(ray.tmin);
    } else if (nearT[enterLast] > ray.tmax) {
        m.reason = "the box lies beyond the segment's end: the ray enters the " +
                   slab(box, enterLast) + " at t = " + num(nearT[enterLast]) +
                   " > tmax = " + num(ray.tmax);
    } else if (nearT[enterLast] > farT[leaveFirst]) {
        m.reason = "the ray leaves the " + slab(box, leaveFirst) +
                   " at t = " + num(farT[leaveFirst]) + " before it enters the " +
                   slab(box, enterLast) + " at t = " + num(nearT[enterLast]);
    } else {
        m.reason = "the slabs overlap on [" + num(nearT[enterLast]) + ", " + num(farT[leaveFirst]) +
                   "] only by rounding: the single-precision test "
                   "rejects it";
    }
    // Closest approach: the distance to a convex set along a line is convex in t, so a golden-
    // section search over the segment (cut to a few box sizes past the box) finds its minimum.
    double span = 0;
    for (int a = 0; a < 3; ++a) {
        const double c = 0.5 * (comp(box.lo, a) + comp(box.hi, a)) - comp(ray.org, a);
        span += c * c + (comp(box.hi, a) - comp(box.lo, a)) * (comp(box.hi, a) - comp(box.lo, a));
    }
    const double dirLen = std::sqrt(double(dot(ray.dir, ray.dir)));
    double lo = ray.tmin,
           hi = std::min(double(ray.tmax), ray.tmin + 4.0 * std::sqrt(span) / dirLen);
    auto f = [&](double t) {
        double p[3] = {ray.org.x + t * ray.dir.x, ray.org.y + t * ray.dir.y,
                       ray.org.z + t * ray.dir.z};
        return boxDistance(box, p);
    };
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    for (int i = 0; i < 200 && hi - lo > 1e-12 * (1.0 + std::fabs(hi)); ++i) {
        const double a = hi - g * (hi - lo), b = lo + g * (hi - lo);
        if (f(a) <= f(b))
            hi = b;
        else
            lo = a;
    }
    m.t = 0.5 * (lo + hi);
    m.distance = f(m.t);
    m.point = ray.org + ray.dir * float(m.t);
    return m;
}

// --- tracing with recorders ------------------------------------------------------------------

namespace {

Aabb rootOf(const BuiltScene& bs) { return bs.tree ? bs.tree->root : rootCube(*bs.scene); }

Explanation start(const BuiltScene& bs) {
    Explanation e;
    e.scene = bs.scene->name;
    e.layout = bs.layout->name;
    e.primitives = bs.scene->primitiveCount();
    e.kind = bs.scene->kind;
    e.root = rootOf(bs);
    return e;
}

RayTrace makeTrace(const char* role, const Ray& ray, bool anyHit, StepRecorder& rec) {
    RayTrace r;
    r.role = role;
    r.ray = ray;
    r.anyHit = anyHit;
    rec.finish(ray);
    r.steps = std::move(rec.steps);
    r.totals = countSteps(r.steps);
    return r;
}

// The hit the steps report: closest (the lowest t, ties to the lower id as considerPrimitive
// rules) or, for an any-hit query, the first.
Hit hitOfSteps(const RayTrace& r) {
    Hit h = {INFINITY, -1};
    for (const ExplainStep& s : r.steps) {
        if (s.event != StepEvent::Prim || !s.hit) continue;
        if (r.anyHit) return {s.t0, int32_t(s.prim)};
        if (h.prim < 0 || s.t0 < h.t || (s.t0 == h.t && int32_t(s.prim) < h.prim))
            h = {s.t0, int32_t(s.prim)};
    }
    return h;
}

void finishExplanation(Explanation& e) {
    e.primary.hit = hitOfSteps(e.primary);
    if (e.shadow) e.shadow->hit = hitOfSteps(*e.shadow);
    float t0, t1;
    if (!intersectBox(makeRaySlabs(e.primary.ray.org, e.primary.ray.dir), e.root,
                      e.primary.ray.tmin, e.primary.ray.tmax, t0, t1))
        e.primary.miss = analyseBoxMiss(e.primary.ray, e.root);
    verifyExplanation(e);
}

}  // namespace

void verifyExplanation(const Explanation& e) {
    // The recorded steps must add up to what the kernel counted, or the explanation would
    // describe a different traversal from the one the Film reports.
    const StepTotals p = countSteps(e.primary.steps);
    const StepTotals s = e.shadow ? countSteps(e.shadow->steps) : StepTotals{};
    const uint64_t nodes = p.boxTests + s.boxTests;
    const uint64_t prims = p.primTests + s.primTests;
    if (nodes != e.cost.nodesVisited || prims != e.cost.primsTested)
        throw TeachError("explain: layout '" + e.layout + "' reported " + std::to_string(nodes) +
                         " box tests and " + std::to_string(prims) +
                         " primitive tests to the observer, but its traversal counted " +
                         std::to_string(e.cost.nodesVisited) + " and " +
                         std::to_string(e.cost.primsTested) +
                         ": it does not report every step (see "
                         "core/octree/traversal_observer.h)");
}

void checkPixelInImage(int x, int y, int width, int height) {
    if (x < 0 || y < 0 || x >= width || y >= height)
        throw TeachError("--pixel " + std::to_string(x) + "," + std::to_string(y) +
                         " is outside the " + std::to_string(width) + "x" + std::to_string(height) +
                         " image (x in 0.." + std::to_string(width - 1) + ", y in 0.." +
                         std::to_string(height - 1) + ", row 0 at the top)");
}

Explanation explainPixel(const BuiltScene& bs, const FrameParams& frame, int x, int y) {
    checkPixelInImage(x, y, frame.width, frame.height);
    Explanation e = start(bs);
    e.pixelMode = true;
    e.x = x;
    e.y = y;
    e.width = frame.width;
    e.height = frame.height;
    e.light = frame.shading.light;
    StepRecorder primaryRec, shadowRec;
    PixelSample s{};
    const PrimitivesView prims = bs.prims();
    bs.visit(
        [&](const auto& view) { s = tracePixel(x, y, frame, view, prims, primaryRec, shadowRec); });
    e.cost = s.cost;
    e.primary = makeTrace("primary", s.primary, false, primaryRec);
    e.shadowState = s.shadow;
    if (s.hit.prim >= 0) e.normal = s.shadowQuery.normal;
    if (s.hit.prim >= 0 && s.shadowQuery.cast)
        e.shadow = makeTrace("shadow", s.shadowQuery.ray, true, shadowRec);
    e.rgb[0] = toByte(s.colour.x);
    e.rgb[1] = toByte(s.colour.y);
    e.rgb[2] = toByte(s.colour.z);
    finishExplanation(e);
    if (e.primary.hit.prim != s.hit.prim)
        throw TeachError("explain: the recorded steps end at primitive " +
                         std::to_string(e.primary.hit.prim) + " but the kernel hit " +
                         std::to_string(s.hit.prim));
    return e;
}

Ray explainedRay(const float* row) {
    // Trace's ray first: its direction's largest component in [0.5, 1) (scaledRay), so its
    // length lies in [0.5, sqrt 3) and normalising cannot overflow or underflow, as it did in
    // float on the direction as given (|d| > 1.84e19 squared is +inf: a miss with NaN points).
    int e = 0;
    const Ray scaled = scaledRay(row, e);
    const DVec3 d = toDouble(scaled.dir);
    const double len = length(d);
    Ray ray;
    ray.org = scaled.org;
    ray.dir = {float(d.x / len), float(d.y / len), float(d.z / len)};
    // t on the scaled ray times its length is a distance; past float range it is +inf, where
    // trace's scaled tmin and tmax are too large for any hit as well.
    auto distance = [len](float t) {
        const double d = double(t) * len;
        return d > double(FLT_MAX) ? INFINITY : float(d);
    };
    ray.tmin = distance(scaled.tmin);
    ray.tmax = distance(scaled.tmax);
    return ray;
}

Explanation explainRay(const BuiltScene& bs, const FrameParams& frame, Vec3 origin, Vec3 dir) {
    const float row[8] = {origin.x, origin.y, origin.z, dir.x, dir.y, dir.z, 0.0f, INFINITY};
    return explainRay(bs, frame, row);
}

Explanation explainRay(const BuiltScene& bs, const FrameParams& frame, const float* row) {
    const std::string problem = rayRowProblem(row);
    if (!problem.empty()) throw TeachError("--ray: " + problem);
    Explanation e = start(bs);
    e.pixelMode = false;
    e.light = frame.shading.light;
    const Ray ray = explainedRay(row);
    StepRecorder primaryRec, shadowRec;
    TraceCost cost = {0, 0};
    Hit hit = missHit();
    ShadowQuery sq{};
    bool occluded = false;
    const PrimitivesView prims = bs.prims();
    // The kernel's steps after the camera ray (tracePixel): closest hit, shadow query, any hit.
    bs.visit([&](const auto& view) {
        hit = closestHit(view, ray, cost, primaryRec);
        if (hit.prim < 0) return;
        sq = shadowQuery(frame.shading, prims, ray, hit);
        if (sq.cast) occluded = anyHit(view, sq.ray, cost, shadowRec);
    });
    e.cost = cost;
    e.primary = makeTrace("primary", ray, false, primaryRec);
    e.shadowState = hit.prim < 0 ? kNoShadowRay
                    : !sq.cast   ? kNoShadowRay
                    : occluded   ? kOccluded
                                 : kLit;
    if (hit.prim >= 0) e.normal = sq.normal;
    if (hit.prim >= 0 && sq.cast) e.shadow = makeTrace("shadow", sq.ray, true, shadowRec);
    finishExplanation(e);
    return e;
}

std::string keyOctal(uint64_t key) {
    char b[32];
    std::snprintf(b, sizeof b, "%llo", (unsigned long long)key);
    return b;
}

// --- readable lines --------------------------------------------------------------------------

namespace {

std::string boxText(const Aabb& b) { return vec(b.lo) + ".." + vec(b.hi); }

std::string idList(const std::vector<uint32_t>& ids) {
    // Consecutive ids (exhaustive tracing) as a range, otherwise the first few.
    bool contiguous = true;
    for (size_t i = 1; i < ids.size(); ++i) contiguous = contiguous && ids[i] == ids[i - 1] + 1;
    if (contiguous && ids.size() > 2)
        return std::to_string(ids.front()) + ".." + std::to_string(ids.back());
    std::string s;
    const size_t shown = std::min<size_t>(ids.size(), 10);
    for (size_t i = 0; i < shown; ++i) s += (i ? " " : "") + std::to_string(ids[i]);
    if (ids.size() > shown) s += " ... (" + std::to_string(ids.size() - shown) + " more)";
    return s;
}

std::string stepNo(size_t i) { return fmt("%6.0f", double(i + 1)); }

std::string keyCol(uint64_t key) {
    std::string k = keyOctal(key);
    if (k.size() < 8) k.resize(8, ' ');
    return k;
}

}  // namespace

std::vector<ExplainLine> explainLines(const Explanation& e, int rayIndex) {
    const RayTrace& r = rayIndex == 0 ? e.primary : *e.shadow;
    std::vector<ExplainLine> out;
    auto add = [&](size_t step, uint64_t key, int64_t prim, std::string text) {
        out.push_back({step, rayIndex, key, prim, std::move(text)});
    };
    const std::vector<ExplainStep>& st = r.steps;
    Hit running = {r.ray.tmax, -1};  // the closest hit so far
    for (size_t i = 0; i < st.size();) {
        const ExplainStep& s = st[i];
        switch (s.event) {
            case StepEvent::Box: {
                std::string t = stepNo(i) + "  box    " + keyCol(s.key) + " depth " +
                                std::to_string(s.depth) + "  box " + boxText(s.box) + "  ";
                if (s.hit)
                    t += "hit, t " + num(s.t0) + " .. " + num(s.t1);
                else if (s.why == SkipReason::BeyondHit)
                    t += "culled: met from t " + num(s.t0) + ", beyond the closest hit t " +
                         num(s.bestT);
                else
                    t += "missed";
                add(i + 1, s.key, -1, t);
                ++i;
                break;
            }
            case StepEvent::Skip:
                add(i + 1, s.key, -1,
                    stepNo(i) + "  skip   " + keyCol(s.key) + " " + skipReasonText(s.why));
                ++i;
                break;
            case StepEvent::Pop:
                add(i + 1, s.key, -1,
                    stepNo(i) + (s.hit ? "  enter  " : "  drop   ") + keyCol(s.key) +
                        (s.hit ? " at t " + num(s.t0)
                               : " not entered: its box starts at t " + num(s.t0) +
                                     ", beyond the closest hit t " + num(s.bestT)));
                ++i;
                break;
            case StepEvent::Probe: {
                // One lookup: consecutive probes for the same key.
                size_t j = i;
                std::string t = stepNo(i) + "  probe  " + keyCol(s.key) + " bucket " +
                                std::to_string(s.bucket) + ":";
                bool found = false;
                do {
                    const ExplainStep& p = st[j];
                    t += std::string(j > i ? "," : "") + " slot " + std::to_string(p.slot) + " " +
                         (p.slotKey == 0 ? std::string("empty")
                          : p.hit        ? std::string("found")
                                         : "holds " + keyOctal(p.slotKey));
                    found = p.hit;
                    ++j;
                } while (!found && j < st.size() && st[j].event == StepEvent::Probe &&
                         st[j].key == s.key);
                t += found ? "" : " -> not stored";
                add(i + 1, s.key, -1, t);
                i = j;
                break;
            }
            case StepEvent::Prim: {
                if (s.hit) {
                    std::string t =
                        stepNo(i) + "  prim   " + std::to_string(s.prim) + " hit at t " + num(s.t0);
                    // considerPrimitive's rule: nearer, or as near with a lower id.
                    const bool better = running.prim < 0 || s.t0 < running.t ||
                                        (s.t0 == running.t && int32_t(s.prim) < running.prim);
                    if (r.anyHit)
                        t += ": occluded, the search ends";
                    else if (better)
                        t += " (closest so far)";
                    else
                        t += " (not nearer than t " + num(running.t) + ", primitive " +
                             std::to_string(running.prim) + ")";
                    if (better) running = {s.t0, int32_t(s.prim)};
                    add(i + 1, 0, s.prim, t);
                    ++i;
                    break;
                }
                // A run of misses on one line.
                std::vector<uint32_t> ids;
                size_t j = i;
                while (j < st.size() && st[j].event == StepEvent::Prim && !st[j].hit)
                    ids.push_back(st[j++].prim);
                if (ids.size() == 1)
                    add(i + 1, 0, s.prim,
                        stepNo(i) + "  prim   " + std::to_string(s.prim) + " missed");
                else
                    add(i + 1, 0, -1,
                        stepNo(i) + "  prims  " + idList(ids) + " missed (" +
                            std::to_string(ids.size()) + " tests)");
                i = j;
                break;
            }
        }
    }
    return out;
}

namespace {

std::string totalsText(const StepTotals& t) {
    // The words of docs/TEACHING.md ("Words"): boxes tested, nodes entered, primitives tested.
    std::string s = std::to_string(t.boxTests) + " boxes tested (" + std::to_string(t.boxesHit) +
                    " met), " + std::to_string(t.primTests) + " primitives tested (" +
                    std::to_string(t.primHits) + " hit); " + std::to_string(t.entered) +
                    " nodes entered, " + std::to_string(t.dropped) + " dropped, " +
                    std::to_string(t.skipped) + " children skipped";
    if (t.probes)
        s += "; " + std::to_string(t.probes) + " hash probes in " + std::to_string(t.lookups) +
             " lookups (" + fmt("%.2f", double(t.probes) / double(t.lookups)) + " a lookup)";
    return s;
}

void appendRay(std::string& out, const Explanation& e, int index) {
    const RayTrace& r = index == 0 ? e.primary : *e.shadow;
    if (index == 0)
        out += "primary ray  origin " + vec(r.ray.org) + "  direction " + vec(r.ray.dir) +
               "  t from " + num(r.ray.tmin) + "\n";
    else
        out += "shadow ray   origin " + vec(r.ray.org) + "  towards the light " + vec(e.light) +
               ", t up to " + num(r.ray.tmax) + "; any hit ends the search\n";
    out += "  step  event  key      what happened\n";
    for (const ExplainLine& l : explainLines(e, index)) out += l.text + "\n";
    if (r.steps.empty()) out += "       (no steps)\n";
    if (index == 0) {
        if (r.hit.prim >= 0) {
            out += "  hit   primitive " + std::to_string(r.hit.prim) + " at t " + num(r.hit.t) +
                   ", point " + vec(r.ray.org + r.ray.dir * r.hit.t) + "\n";
        } else if (r.miss) {
            out += "  miss  the ray misses the root box " + boxText(e.root) + ": " +
                   r.miss->reason + ". Closest approach " + num(r.miss->distance) + " at t " +
                   num(r.miss->t) + ", point " + vec(r.miss->point) + "\n";
        } else {
            out += "  miss  the ray crosses the root box but hits no primitive\n";
        }
    } else {
        out += e.shadowState == kOccluded
                   ? "  occluded by primitive " + std::to_string(r.hit.prim) + " at t " +
                         num(r.hit.t) + ": the point is in shadow\n"
                   : std::string("  lit: nothing between the point and the light\n");
    }
    out += "  cost  " + totalsText(r.totals) + "\n";
}

}  // namespace

std::string explainText(const Explanation& e) {
    std::string out = "octrace explain  " + e.scene + " (" + std::to_string(e.primitives) + " " +
                      primKindName(e.kind) + "), layout " + e.layout + "\n";
    if (e.pixelMode)
        out += "pixel (" + std::to_string(e.x) + ", " + std::to_string(e.y) + ") of " +
               std::to_string(e.width) + "x" + std::to_string(e.height) +
               ": the camera ray through its centre, then its shadow ray\n";
    else
        out +=
            "the ray given by --ray (direction normalised, tmin and tmax scaled with it, so t is "
            "a distance), then its shadow ray\n";
    out +=
        "keys: Morton keys in octal; 1 is the root, each further digit an octant (x + 2y + "
        "4z)\n\n";
    appendRay(out, e, 0);
    out += "\n";
    if (e.shadow) {
        appendRay(out, e, 1);
        out += "\n";
    } else if (e.primary.hit.prim >= 0) {
        out += "no shadow ray: the surface faces away from the light " + vec(e.light) + "\n\n";
    }
    out += std::string(e.pixelMode ? "pixel" : "ray") + " cost  " +
           std::to_string(e.cost.nodesVisited) + " boxes tested, " +
           std::to_string(e.cost.primsTested) +
           " primitives tested (primary + shadow): the kernel's count, " +
           (e.pixelMode ? "the heat map's value for this pixel" : "as octrace trace") + "\n";
    return out;
}

std::string explainJson(const Explanation& e) {
    using json = nlohmann::ordered_json;
    auto v3 = [](Vec3 v) { return json::array({v.x, v.y, v.z}); };
    auto tnum = [](float t) { return std::isfinite(t) ? json(t) : json(nullptr); };
    json j;
    j["format"] = "octrace-explain";  // the schema, so a reader can refuse one it does not know
    // Version 2: the words of docs/TEACHING.md ("Words"); version 1 had the events "pop" (with
    // "visited") and the keys "nodes", "visited", "prims" for boxes tested, nodes entered and
    // primitives tested.
    j["version"] = 2;
    j["scene"] = e.scene;
    j["primitives"] = e.primitives;
    j["kind"] = primKindName(e.kind);
    j["layout"] = e.layout;
    if (e.pixelMode)
        j["query"] = {{"pixel", {e.x, e.y}}, {"image", {e.width, e.height}}};
    else
        j["query"] = {{"ray",
                       {e.primary.ray.org.x, e.primary.ray.org.y, e.primary.ray.org.z,
                        e.primary.ray.dir.x, e.primary.ray.dir.y, e.primary.ray.dir.z}}};
    j["root_box"] = {v3(e.root.lo), v3(e.root.hi)};
    j["light"] = v3(e.light);
    json rays = json::array();
    for (int index = 0; index < (e.shadow ? 2 : 1); ++index) {
        const RayTrace& r = index == 0 ? e.primary : *e.shadow;
        json jr;
        jr["role"] = r.role;
        jr["origin"] = v3(r.ray.org);
        jr["direction"] = v3(r.ray.dir);
        jr["tmin"] = tnum(r.ray.tmin);
        jr["tmax"] = tnum(r.ray.tmax);  // null: unbounded
        jr["any_hit"] = r.anyHit;
        json steps = json::array();
        for (size_t i = 0; i < r.steps.size(); ++i) {
            const ExplainStep& s = r.steps[i];
            json js;
            js["step"] = i + 1;
            switch (s.event) {
                case StepEvent::Box:
                    js["event"] = "box";
                    js["key"] = keyOctal(s.key);
                    js["depth"] = s.depth;
                    js["box"] = {v3(s.box.lo), v3(s.box.hi)};
                    js["hit"] = s.hit;
                    if (s.hit || s.why == SkipReason::BeyondHit) {
                        js["t_enter"] = tnum(s.t0);
                        js["t_exit"] = tnum(s.t1);
                    }
                    if (!s.hit) js["why"] = skipReasonKey(s.why);
                    if (!s.hit && s.why == SkipReason::BeyondHit) js["closest_t"] = tnum(s.bestT);
                    break;
                case StepEvent::Skip:
                    js["event"] = "skip";
                    js["key"] = keyOctal(s.key);
                    js["why"] = skipReasonKey(s.why);
                    break;
                case StepEvent::Pop:
                    js["event"] = s.hit ? "enter" : "drop";  // the text's words
                    js["key"] = keyOctal(s.key);
                    js["t_enter"] = tnum(s.t0);
                    if (!s.hit) {
                        js["why"] = "beyond_hit";
                        js["closest_t"] = tnum(s.bestT);
                    }
                    break;
                case StepEvent::Prim:
                    js["event"] = "prim";
                    js["prim"] = s.prim;
                    js["hit"] = s.hit;
                    if (s.hit) js["t"] = s.t0;
                    break;
                case StepEvent::Probe:
                    js["event"] = "probe";
                    js["key"] = keyOctal(s.key);
                    js["bucket"] = s.bucket;
                    js["slot"] = s.slot;
                    js["slot_key"] = s.slotKey ? json(keyOctal(s.slotKey)) : json(nullptr);
                    js["found"] = s.hit;
                    break;
            }
            steps.push_back(std::move(js));
        }
        jr["steps"] = std::move(steps);
        if (r.hit.prim >= 0)
            jr["hit"] = {{"prim", r.hit.prim},
                         {"t", r.hit.t},
                         {"point", v3(r.ray.org + r.ray.dir * r.hit.t)}};
        else
            jr["hit"] = nullptr;
        if (r.miss)
            jr["root_miss"] = {{"reason", r.miss->reason},
                               {"closest_distance", r.miss->distance},
                               {"closest_t", r.miss->t},
                               {"closest_point", v3(r.miss->point)}};
        const StepTotals& t = r.totals;
        jr["totals"] = {{"boxes_tested", t.boxTests},    {"boxes_met", t.boxesHit},
                        {"prims_tested", t.primTests},   {"prim_hits", t.primHits},
                        {"nodes_entered", t.entered},    {"nodes_dropped", t.dropped},
                        {"children_skipped", t.skipped}, {"hash_probes", t.probes},
                        {"hash_lookups", t.lookups}};
        rays.push_back(std::move(jr));
    }
    j["rays"] = std::move(rays);
    j["shadow"] = e.shadowState == kOccluded ? "occluded" : e.shadowState == kLit ? "lit" : "none";
    if (e.pixelMode) j["rgb"] = {e.rgb[0], e.rgb[1], e.rgb[2]};
    j["cost"] = {{"boxes_tested", e.cost.nodesVisited}, {"prims_tested", e.cost.primsTested}};
    return j.dump(1) + "\n";
}

}  // namespace oct
