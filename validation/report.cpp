#include "validation/report.h"

#include <cmath>
#include <cstdarg>
#include <cstdio>

namespace oct {
namespace {

using nlohmann::json;

// Non-finite numbers become null (JSON has no inf).
json num(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json hitJson(Hit h) { return {{"t", num(h.t)}, {"prim", h.prim}}; }

json reasonsJson(uint32_t reasons) {
    json a = json::array();
    for (int b = 0; b < kReasonCount; ++b)
        if (reasons & (1u << b)) a.push_back(reasonName(b));
    return a;
}

json findingJson(const Finding& f, bool pixel) {
    json j;
    if (pixel) {
        j["x"] = f.x;
        j["y"] = f.y;
    } else {
        j["index"] = f.index;
        j["kind"] = rayKindName(f.kind);
        j["ray"] = {f.ray.org.x, f.ray.org.y, f.ray.org.z,     f.ray.dir.x,
                    f.ray.dir.y, f.ray.dir.z, num(f.ray.tmin), num(f.ray.tmax)};
    }
    j["class"] = hitClassName(f.cls);
    j["reasons"] = reasonsJson(f.reasons);
    j["ours"] = hitJson(f.ours);
    j["reference"] = hitJson(f.reference);
    if (f.rechecked) j["truth"] = hitJson(f.truth);
    j["relative_dt"] = num(f.relativeDt);
    return j;
}

const char* shadowState(uint8_t s) {
    return s == kOccluded ? "occluded" : (s == kLit ? "lit" : "none");
}

json shadowJson(const ShadowFinding& f) {
    json j = {{"x", f.x},
              {"y", f.y},
              {"class", hitClassName(f.cls)},
              {"reasons", reasonsJson(f.reasons)},
              {"ours", shadowState(f.ours)},
              {"reference", shadowState(f.reference)}};
    if (f.referenceOnOurRay >= 0)
        j["reference_on_our_ray"] = f.referenceOnOurRay ? "occluded" : "lit";
    if (f.truthOccluded >= 0) j["truth"] = f.truthOccluded ? "occluded" : "lit";
    return j;
}

std::string fmt(const char* f, ...) {
    char buf[1024];
    va_list ap;
    va_start(ap, f);
    std::vsnprintf(buf, sizeof buf, f, ap);
    va_end(ap);
    return buf;
}

std::string hitText(Hit h) {
    return h.prim < 0 ? std::string("miss") : fmt("t=%.9g #%d", double(h.t), h.prim);
}

std::string countsLine(const char* what, const ClassCounts& c) {
    return fmt("  %-8s %9llu %9llu %7llu %9llu %7llu %10.3g %12.3g\n", what,
               (unsigned long long)c.compared, (unsigned long long)c.agree,
               (unsigned long long)c.ties, (unsigned long long)c.ambiguous,
               (unsigned long long)c.wrong, c.ambiguousRate(), c.maxRelativeDt);
}

std::string reasonsText(const ClassCounts& c) {
    std::string s;
    for (int b = 0; b < kReasonCount; ++b)
        if (c.reasons[b]) s += fmt(" %s %llu", reasonName(b), (unsigned long long)c.reasons[b]);
    return s;
}

}  // namespace

json toJson(const ClassCounts& c) {
    json reasons = json::object();
    for (int b = 0; b < kReasonCount; ++b) reasons[reasonName(b)] = c.reasons[b];
    return {{"compared", c.compared},
            {"agree", c.agree},
            {"both_miss", c.bothMiss},
            {"ties", c.ties},
            {"ambiguous", c.ambiguous},
            {"wrong", c.wrong},
            {"mismatches", c.mismatches},
            {"rechecked", c.rechecked},
            {"ambiguous_rate", c.ambiguousRate()},
            {"wrong_rate", c.wrongRate()},
            {"max_relative_dt", num(c.maxRelativeDt)},
            {"reasons", reasons}};
}

json toJson(const ReplicationReport& r) {
    auto entries = [](const std::vector<ReplicationEntry>& v, bool gap) {
        json a = json::array();
        for (const ReplicationEntry& e : v) {
            json j = {
                {"prim", e.prim}, {"leaf_key", e.leafKey}, {"node", e.node}, {"depth", e.depth}};
            if (gap) j["gap"] = e.gap;
            a.push_back(j);
        }
        return a;
    };
    auto agreement = [](const ReferenceAgreement& a) {
        return json{{"overlaps", a.overlaps},
                    {"false_negatives", a.falseNegatives},
                    {"false_positives", a.falsePositives}};
    };
    json dist = json::object();
    for (const auto& [count, prims] : r.distribution) dist[std::to_string(count)] = prims;
    return {{"pass", r.passes()},
            {"primitives", r.primitives},
            {"leaves", r.leaves},
            {"octree_faces", r.octreeFaces},
            {"exact_overlaps", r.exactOverlaps},
            {"false_negatives", r.falseNegatives},
            {"false_positives", r.falsePositives},
            {"false_positive_gaps",
             {{"le_1e-12", r.falsePositiveGaps[0]},
              {"le_1e-9", r.falsePositiveGaps[1]},
              {"le_1e-6", r.falsePositiveGaps[2]},
              {"le_1e-3", r.falsePositiveGaps[3]},
              {"gt_1e-3", r.falsePositiveGaps[4]}}},
            {"max_false_positive_gap", r.maxFalsePositiveGap},
            {"double_precision", agreement(r.doublePrecision)},
            {"builder_vs_double", agreement(r.builderVsDouble)},
            {"index_out_of_range", r.indexOutOfRange},
            {"duplicate_entries", r.duplicateEntries},
            {"unlisted_primitives", r.unlistedPrimitives},
            {"range_errors", r.rangeErrors},
            {"structural_errors", r.structuralErrors},
            {"distribution", dist},
            {"max_replication", r.maxReplication},
            {"mean_replication", r.meanReplication},
            {"false_negative_list", entries(r.falseNegativeList, false)},
            {"false_positive_list", entries(r.falsePositiveList, true)},
            {"exact_tests", r.exactTests},
            {"seconds", r.seconds}};
}

json toJson(const ValidationReport& r) {
    json runs = json::array();
    for (const RunReport& run : r.runs) {
        json shadow = toJson(run.film.shadow);
        shadow["resolved_by_rerun"] = run.film.shadowResolvedByRerun;
        shadow["not_compared"] = run.film.shadowNotCompared;
        json rays = toJson(run.rays.all);
        json byKind = json::object();
        for (int k = 0; k < kRayKindCount; ++k)
            byKind[rayKindName(RayKind(k))] = toJson(run.rays.byKind[k]);
        rays["by_kind"] = byKind;
        json wp = json::array(), ws = json::array(), wr = json::array();
        for (const Finding& f : run.film.worstPixels) wp.push_back(findingJson(f, true));
        for (const ShadowFinding& f : run.film.worstShadows) ws.push_back(shadowJson(f));
        for (const Finding& f : run.rays.worst) wr.push_back(findingJson(f, false));
        runs.push_back({{"layout", run.layout},
                        {"backend", run.backend},
                        {"pass", run.passes(r.policy.maxAmbiguousRate)},
                        {"wrong", run.wrong()},
                        {"ambiguous", run.ambiguous()},
                        {"primary", toJson(run.film.primary)},
                        {"shadow", shadow},
                        {"rays", rays},
                        {"worst_pixels", wp},
                        {"worst_shadow_rays", ws},
                        {"worst_rays", wr},
                        {"seconds",
                         {{"render", run.renderSeconds},
                          {"trace", run.traceSeconds},
                          {"check", run.checkSeconds}}}});
    }
    json j = {{"scene",
               {{"name", r.scene},
                {"kind", r.kind == PrimKind::Triangles ? "triangles" : "spheres"},
                {"primitives", r.primitives},
                {"extent", r.extent}}},
              {"policy",
               {{"t_tolerance", r.policy.tTolerance},
                {"edge_tolerance", r.policy.edgeTolerance},
                {"grazing_cos", r.policy.grazingCos},
                {"max_ambiguous_rate", r.policy.maxAmbiguousRate},
                {"max_rechecks", r.policy.maxRechecks}}},
              {"frame", {{"width", r.width}, {"height", r.height}}},
              {"ray_set",
               {{"count", r.rayCount},
                {"seed", r.seed},
                {"around", r.raysByKind[0]},
                {"inside", r.raysByKind[1]},
                {"axis", r.raysByKind[2]}}},
              {"reference",
               {{"tracer", "embree (RTC_SCENE_FLAG_ROBUST)"}, {"seconds", r.referenceSeconds}}},
              {"runs", runs},
              {"wrong", r.wrong()},
              {"ambiguous", r.ambiguous()},
              {"pass", r.passes()},
              {"seconds", r.seconds}};
    j["replication"] = r.replication ? toJson(*r.replication) : json(nullptr);
    return j;
}

json toJson(const std::vector<Table1Row>& rows) {
    json a = json::array();
    for (const Table1Row& t : rows)
        a.push_back({{"name", t.name},
                     {"path", t.path},
                     {"vertices", t.vertices},
                     {"faces", t.faces},
                     {"octree_faces", t.octreeFaces},
                     {"depth", t.depth},
                     {"nodes", t.nodes},
                     {"build_seconds", t.buildSeconds}});
    return a;
}

std::string humanSummary(const ReplicationReport& r) {
    std::string s;
    s +=
        fmt("replication  %s: %llu primitives, %llu leaves, octree faces %llu (%.3f per "
            "primitive, max %u), %.2f s, %llu exact tests\n",
            r.passes() ? "PASS" : "FAIL", (unsigned long long)r.primitives,
            (unsigned long long)r.leaves, (unsigned long long)r.octreeFaces, r.meanReplication,
            r.maxReplication, r.seconds, (unsigned long long)r.exactTests);
    s +=
        fmt("  exact (CGAL) overlaps %llu; false negatives %llu; false positives %llu (gap / "
            "leaf edge <=1e-12: %llu, <=1e-9: %llu, <=1e-6: %llu, <=1e-3: %llu, larger: %llu; "
            "max %.3g)\n",
            (unsigned long long)r.exactOverlaps, (unsigned long long)r.falseNegatives,
            (unsigned long long)r.falsePositives, (unsigned long long)r.falsePositiveGaps[0],
            (unsigned long long)r.falsePositiveGaps[1], (unsigned long long)r.falsePositiveGaps[2],
            (unsigned long long)r.falsePositiveGaps[3], (unsigned long long)r.falsePositiveGaps[4],
            r.maxFalsePositiveGap);
    s +=
        fmt("  double Akenine-Moller (unpadded) vs exact: %llu overlaps, %llu false negatives, "
            "%llu false positives; builder vs it: %llu missing, %llu extra\n",
            (unsigned long long)r.doublePrecision.overlaps,
            (unsigned long long)r.doublePrecision.falseNegatives,
            (unsigned long long)r.doublePrecision.falsePositives,
            (unsigned long long)r.builderVsDouble.falseNegatives,
            (unsigned long long)r.builderVsDouble.falsePositives);
    if (r.indexOutOfRange || r.duplicateEntries || r.unlistedPrimitives)
        s +=
            fmt("  leaf lists: %llu indices out of range, %llu duplicates, %llu primitives in "
                "no leaf\n",
                (unsigned long long)r.indexOutOfRange, (unsigned long long)r.duplicateEntries,
                (unsigned long long)r.unlistedPrimitives);
    if (r.rangeErrors) {
        s += fmt("  broken node ranges: %llu\n", (unsigned long long)r.rangeErrors);
        for (const std::string& e : r.structuralErrors) s += "    " + e + "\n";
    }
    s += "  replication count: primitives";
    int shown = 0;
    for (const auto& [count, prims] : r.distribution) {
        if (shown++ == 12) {
            s += " ...";
            break;
        }
        s += fmt("  %u: %llu", count, (unsigned long long)prims);
    }
    s += "\n";
    for (const ReplicationEntry& e : r.falseNegativeList)
        s += fmt("  FALSE NEGATIVE primitive %u not listed in leaf key %llu (node %u, depth %d)\n",
                 e.prim, (unsigned long long)e.leafKey, e.node, e.depth);
    return s;
}

std::string humanSummary(const ValidationReport& r) {
    std::string s;
    s +=
        fmt("validate %s: %u %s, extent %.6g; %dx%d pixels, %llu rays (seed %llu: around %llu, "
            "inside %llu, axis %llu)\n",
            r.scene.c_str(), r.primitives, r.kind == PrimKind::Triangles ? "triangles" : "spheres",
            r.extent, r.width, r.height, (unsigned long long)r.rayCount, (unsigned long long)r.seed,
            (unsigned long long)r.raysByKind[0], (unsigned long long)r.raysByKind[1],
            (unsigned long long)r.raysByKind[2]);
    s +=
        fmt("policy   same hit: |dt| <= %.3g x extent; edge/tangent: %.3g x extent; grazing: "
            "|cos| <= %.3g; pass: no wrong, ambiguous rate <= %.3g\n",
            r.policy.tTolerance, r.policy.edgeTolerance, r.policy.grazingCos,
            r.policy.maxAmbiguousRate);
    s += fmt("reference embree (robust) %.2f s\n", r.referenceSeconds);
    for (const RunReport& run : r.runs) {
        s += fmt("\n%s on %s: %s  (render %.2f s, rays %.2f s, check %.2f s)\n", run.layout.c_str(),
                 run.backend.c_str(), run.passes(r.policy.maxAmbiguousRate) ? "PASS" : "FAIL",
                 run.renderSeconds, run.traceSeconds, run.checkSeconds);
        s += "  check     compared     agree    ties ambiguous   wrong  amb. rate  max|dt|/ext\n";
        s += countsLine("primary", run.film.primary);
        s += countsLine("shadow", run.film.shadow);
        s += countsLine("rays", run.rays.all);
        for (int k = 0; k < kRayKindCount; ++k)
            s += countsLine((std::string(" ") + rayKindName(RayKind(k))).c_str(),
                            run.rays.byKind[k]);
        std::string reasons = reasonsText(run.film.primary);
        if (!reasons.empty()) s += "  primary ambiguous by reason:" + reasons + "\n";
        reasons = reasonsText(run.film.shadow);
        if (!reasons.empty()) s += "  shadow ambiguous by reason:" + reasons + "\n";
        reasons = reasonsText(run.rays.all);
        if (!reasons.empty()) s += "  rays ambiguous by reason:" + reasons + "\n";
        if (run.film.shadowResolvedByRerun || run.film.shadowNotCompared)
            s +=
                fmt("  shadow: %llu differing states reproduced by Embree on our shadow ray "
                    "(agree); %llu pixels not compared (primary mismatch)\n",
                    (unsigned long long)run.film.shadowResolvedByRerun,
                    (unsigned long long)run.film.shadowNotCompared);
        // Pixels: the mismatches and ties, or else the largest |dt| that still agreed.
        int shown = 0;
        for (const Finding& f : run.film.worstPixels) {
            bool notable = f.cls != HitClass::Agree;
            if (shown == 8 || (!notable && shown > 0)) break;
            if (shown++ == 0)
                s += notable ? "  worst pixels (x,y: class [reasons] ours | embree | truth)\n"
                             : "  largest |dt| (x,y: class ours | embree)\n";
            s += fmt("    %4d,%-4d %-9s %-16s %s | %s", f.x, f.y, hitClassName(f.cls),
                     ("[" + reasonNames(f.reasons) + "]").c_str(), hitText(f.ours).c_str(),
                     hitText(f.reference).c_str());
            s += f.rechecked ? " | " + hitText(f.truth) + "\n" : std::string("\n");
        }
        shown = 0;
        for (const ShadowFinding& f : run.film.worstShadows) {
            if (f.cls == HitClass::Agree) continue;
            if (shown++ == 8) break;
            if (shown == 1)
                s += "  shadow rays (x,y: class [reasons] ours | embree | embree on our ray | "
                     "truth)\n";
            s += fmt("    %4d,%-4d %-9s %-16s %s | %s | %s | %s\n", f.x, f.y, hitClassName(f.cls),
                     ("[" + reasonNames(f.reasons) + "]").c_str(), shadowState(f.ours),
                     shadowState(f.reference),
                     f.referenceOnOurRay < 0 ? "-" : (f.referenceOnOurRay ? "occluded" : "lit"),
                     f.truthOccluded < 0 ? "-" : (f.truthOccluded ? "occluded" : "lit"));
        }
        shown = 0;
        for (const Finding& f : run.rays.worst) {
            if (f.cls != HitClass::Ambiguous && f.cls != HitClass::Wrong) continue;
            if (shown++ == 8) break;
            if (shown == 1)
                s += "  worst rays (index kind: class [reasons] ours | embree | truth)\n";
            s += fmt("    %6llu %-6s %-9s %-16s %s | %s", (unsigned long long)f.index,
                     rayKindName(f.kind), hitClassName(f.cls),
                     ("[" + reasonNames(f.reasons) + "]").c_str(), hitText(f.ours).c_str(),
                     hitText(f.reference).c_str());
            s += f.rechecked ? " | " + hitText(f.truth) + "\n" : std::string("\n");
        }
    }
    if (r.replication) s += "\n" + humanSummary(*r.replication);
    s += fmt("\n%s: %llu wrong, %llu ambiguous over %zu run(s)%s (%.2f s)\n",
             r.passes() ? "PASS" : "FAIL", (unsigned long long)r.wrong(),
             (unsigned long long)r.ambiguous(), r.runs.size(),
             r.replication ? (r.replication->passes() ? ", replication ok" : ", replication FAILED")
                           : "",
             r.seconds);
    return s;
}

std::string humanTable1(const std::vector<Table1Row>& rows) {
    std::string s = fmt("%-24s %10s %10s %13s %8s %6s %9s\n", "model", "vertices", "faces",
                        "octree faces", "ratio", "depth", "build s");
    for (const Table1Row& t : rows)
        s += fmt("%-24s %10llu %10llu %13llu %8.3f %6d %9.2f\n", t.name.c_str(),
                 (unsigned long long)t.vertices, (unsigned long long)t.faces,
                 (unsigned long long)t.octreeFaces,
                 t.faces ? double(t.octreeFaces) / double(t.faces) : 0.0, t.depth, t.buildSeconds);
    return s;
}

}  // namespace oct
