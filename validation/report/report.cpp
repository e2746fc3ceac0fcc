#include "validation/report/report.h"

#include <cmath>

#include "validation/checks/check.h"
#include "validation/report/report_util.h"

namespace oct {
using nlohmann::json;
using namespace report_detail;

json toJson(const ClassCounts& c) {
    json reasons = json::object();
    for (int b = 0; b < kReasonCount; ++b) reasons[reasonName(b)] = c.reasons[b];
    return {{"compared", c.compared},      {"agree", c.agree},
            {"both_miss", c.bothMiss},     {"ties", c.ties},
            {"ambiguous", c.ambiguous},    {"wrong", c.wrong},
            {"unverified", c.unverified},  {"mismatches", c.mismatches},
            {"rechecked", c.rechecked},    {"ambiguous_rate", c.ambiguousRate()},
            {"wrong_rate", c.wrongRate()}, {"max_relative_dt", num(c.maxRelativeDt)},
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
            {"tiling_errors", r.tilingErrors},
            {"wide_false_positives", r.wideFalsePositives},
            {"max_allowed_false_positive_gap", kMaxFalsePositiveGap},
            {"structural_errors", r.structuralErrors},
            {"distribution", dist},
            {"max_replication", r.maxReplication},
            {"mean_replication", r.meanReplication},
            {"false_negative_list", entries(r.falseNegativeList, false)},
            {"false_positive_list", entries(r.falsePositiveList, true)},
            {"exact_tests", r.exactTests},
            {"seconds", r.seconds}};
}

namespace {

json raySetJson(const ValidationReport& r) {
    json j = {{"count", r.rayCount}, {"seed", r.seed}};
    for (const RaySetRange& s : r.raySets) j[s.name] = s.count;
    return j;
}

std::string raySetText(const ValidationReport& r) {
    std::string s;
    for (const RaySetRange& k : r.raySets)
        s += fmt("%s%s %llu", s.empty() ? "" : ", ", k.name.c_str(), (unsigned long long)k.count);
    return s;
}

}  // namespace

namespace {

json validationReportBody(const ValidationReport& r) {
    const double rate = r.policy.maxAmbiguousRate;
    json runs = json::array();
    for (const RunReport& run : r.runs) {
        json one = {{"layout", run.layout},
                    {"backend", run.backend},
                    {"pass", run.passes(rate)},
                    {"wrong", run.wrong()},
                    {"ambiguous", run.ambiguous()},
                    {"seconds",
                     {{"render", run.renderSeconds},
                      {"trace", run.traceSeconds},
                      {"check", run.checkSeconds}}}};
        for (const RunCheck* c : runChecks()) one.update(c->result(run, rate).json);
        runs.push_back(one);
    }
    json j = {{"scene", sceneJson(r)},
              {"policy", policyJson(r.policy)},
              {"frame", {{"width", r.width}, {"height", r.height}}},
              {"ray_set", raySetJson(r)},
              {"reference", referenceJson(r.referenceSeconds)},
              {"runs", runs},
              {"wrong", r.wrong()},
              {"ambiguous", r.ambiguous()},
              {"pass", r.passes()},
              {"verdict", !r.passes()    ? "FAIL"
                          : r.complete() ? "PASS"
                                         : "INCOMPLETE"},
              {"seconds", r.seconds}};
    for (const SceneCheck* c : sceneChecks()) j.update(c->result(r).json);
    return j;
}

}  // namespace

json toJson(const ValidationReport& r) {
    return report_detail::withSchema(validationReportBody(r), "octrace-validate-report");
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
    if (r.wideFalsePositives)
        s +=
            fmt("  false positives wider than %.3g of the leaf's edge (not rounding: the "
                "builder's test is wrong): %llu\n",
                kMaxFalsePositiveGap, (unsigned long long)r.wideFalsePositives);
    if (r.rangeErrors || r.tilingErrors) {
        s += fmt("  broken node ranges: %llu; boxes, keys or depths not the subdivision's: %llu\n",
                 (unsigned long long)r.rangeErrors, (unsigned long long)r.tilingErrors);
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
    const double rate = r.policy.maxAmbiguousRate;
    std::string s;
    s += sceneHead("validate", r) + fmt("; %dx%d pixels, %llu rays (seed %llu: %s)\n", r.width,
                                        r.height, (unsigned long long)r.rayCount,
                                        (unsigned long long)r.seed, raySetText(r).c_str());
    s += policyLine(r.policy, "no wrong, ambiguous rate");
    s += fmt("reference embree (robust) %.2f s\n", r.referenceSeconds);
    for (const RunReport& run : r.runs) {
        s += fmt("\n%s on %s: %s  (render %.2f s, rays %.2f s, check %.2f s)\n", run.layout.c_str(),
                 run.backend.c_str(),
                 !run.passes(rate)    ? "FAIL"
                 : run.complete(rate) ? "PASS"
                                      : "INCOMPLETE",
                 run.renderSeconds, run.traceSeconds, run.checkSeconds);
        for (const RunCheck* c : runChecks()) s += c->result(run, rate).summary;
    }
    std::string verdicts;
    for (const SceneCheck* c : sceneChecks()) {
        const CheckResult x = c->result(r);
        s += x.summary;
        verdicts += x.verdict;
    }
    s += fmt("\n%s: %llu wrong, %llu ambiguous over %zu run(s)%s (%.2f s)\n",
             !r.passes()    ? "FAIL"
             : r.complete() ? "PASS"
                            : "INCOMPLETE",
             (unsigned long long)r.wrong(), (unsigned long long)r.ambiguous(), r.runs.size(),
             verdicts.c_str(), r.seconds);
    return s;
}

std::string failureText(const ValidationReport& r) {
    std::string s =
        std::to_string(r.wrong()) + " wrong, " + std::to_string(r.ambiguous()) + " ambiguous";
    const double rate = r.policy.maxAmbiguousRate;
    for (const RunReport& run : r.runs)
        for (const RunCheck* c : runChecks()) s += c->result(run, rate).failureText;
    for (const SceneCheck* c : sceneChecks()) s += c->result(r).failureText;
    return s;
}

}  // namespace oct
