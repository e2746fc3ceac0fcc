// The per-ray check's report (validate and certify share it) and `octrace certify`'s report, in
// the two forms with the same content: JSON (docs/CERTIFY.md lists the fields) and text.
#include "validation/ambiguity_bound.h"
#include "validation/report/report.h"
#include "validation/report/report_util.h"

namespace oct {

using nlohmann::json;
using namespace report_detail;

namespace {

// What the tracer should have answered: the double truth when rechecked, else the reference.
Hit expected(const Finding& f) { return f.rechecked ? f.truth : f.reference; }

json leakJson(const LeakFinding& f) {
    json j = {{"index", f.index},      {"set", f.set},          {"target_t", num(f.target.t)},
              {"got", hitJson(f.got)}, {"ray", rayJson(f.ray)}, {"rechecked", f.rechecked}};
    if (f.rechecked) j["truth"] = hitJson(f.truth);
    auto pos = [](Vec3 v) { return json::array({v.x, v.y, v.z}); };
    if (f.target.vertex()) {
        j["vertex"] = f.target.a;
        j["position"] = pos(f.target.pa);
    } else {
        j["edge"] = json::array({f.target.a, f.target.b});
        j["positions"] = json::array({pos(f.target.pa), pos(f.target.pb)});
    }
    return j;
}

std::string leakPlace(const RayTarget& t) {
    return t.vertex() ? fmt("vertex %u", t.a) : fmt("edge %u-%u", t.a, t.b);
}

const char* verdict(const SetCertification& s) {
    if (!s.clean()) return "FAIL";
    return s.counts.unverified || s.leakUnverified ? "incomplete" : "pass";
}

const char* queryName(QueryKind q) { return q == QueryKind::AnyHit ? "any_hit" : "closest"; }

std::string joined(const std::vector<std::string>& v) {
    std::string s;
    for (const std::string& x : v) s += (s.empty() ? "" : ", ") + x;
    return s;
}

// Each set's own bound on ambiguous answers, where it has one: "name counted <= limit", or
// "> limit FAIL".
std::string boundsLine(const RayCertification& r) {
    std::string list;
    bool fromBaseline = false;
    for (const SetCertification& k : r.sets) {
        if (!k.ambiguousLimit) continue;
        fromBaseline = fromBaseline || k.expectedAmbiguous.has_value();
        list += fmt("%s%s %llu %s %llu%s", list.empty() ? "" : ", ", k.range.name.c_str(),
                    (unsigned long long)k.ambiguousCounted, k.withinAmbiguousLimit() ? "<=" : ">",
                    (unsigned long long)*k.ambiguousLimit, k.withinAmbiguousLimit() ? "" : " FAIL");
    }
    if (list.empty()) return "";
    const std::string base =
        fromBaseline ? fmt("octrace's kernel on these rows + %g %% (grazing 100 %%) + the rate "
                           "of the rows",
                           100.0 * kAmbiguousSlack)
                     : fmt("no baseline%s: %g of an adversarial set's rows",
                           r.baselineIgnored ? " that applies (other tolerances)" : "",
                           kAdversarialAmbiguousShare);
    return "  ambiguous per set, leaks not counted (bound: " + base + "): " + list + "\n";
}

json findingWithExpected(const Finding& f) {
    json fj = findingJson(f, false);
    fj["expected"] = hitJson(expected(f));
    return fj;
}

}  // namespace

json toJson(const RayCertification& r, double maxRate) {
    json j = toJson(r.all);
    j["leak_checked"] = r.leakChecked;
    j["leaks"] = r.leaks;
    j["unsealed"] = r.unsealed;
    j["leak_unverified"] = r.leakUnverified;
    j["pass"] = r.passes(maxRate);
    j["correct"] = outcomeName(r.correct(maxRate));
    j["watertight"] = outcomeName(r.watertight());
    j["strict"] = toJson(r.strict);  // the pooled sets the ambiguous rate is judged on
    j["baseline_ignored"] = r.baselineIgnored;
    json bySet = json::object(), order = json::array();
    for (const SetCertification& s : r.sets) {
        json k = toJson(s.counts);
        k["begin"] = s.range.begin;
        k["rows"] = s.range.count;
        k["adversarial"] = s.adversarial;
        k["query"] = queryName(s.query);
        k["clean"] = s.clean();
        k["leak_checked"] = s.leakChecked;
        k["leaks"] = s.leaks;
        k["unsealed"] = s.unsealed;
        k["leak_unverified"] = s.leakUnverified;
        // The set's own bound (validation/ambiguity_bound.h); null: none of its own.
        k["ambiguous_counted"] = s.ambiguousCounted;
        k["expected_ambiguous"] = s.expectedAmbiguous ? json(*s.expectedAmbiguous) : json(nullptr);
        k["ambiguous_limit"] = s.ambiguousLimit ? json(*s.ambiguousLimit) : json(nullptr);
        json w = json::array(), l = json::array();
        for (const Finding& f : s.worst) w.push_back(findingWithExpected(f));
        for (const LeakFinding& f : s.leakList) l.push_back(leakJson(f));
        k["worst"] = w;
        k["leak_list"] = l;
        bySet[s.range.name] = k;
        order.push_back(s.range.name);
    }
    j["sets"] = order;
    j["by_set"] = bySet;
    json examples = json::array();
    for (const Finding& f : r.examples) examples.push_back(findingWithExpected(f));
    j["examples"] = examples;
    return j;
}

std::string humanRaySets(const RayCertification& r, double maxRate) {
    // An unverified column only when a recheck cap left something unverified.
    const bool capped = r.all.unverified || r.leakUnverified;
    std::string s =
        fmt("  set           rows     agree    ties ambiguous   wrong%s  leaks  amb. rate  "
            "max|dt|/ext  verdict\n",
            capped ? " unverif." : "");
    auto line = [&](const std::string& name, const ClassCounts& c, uint64_t leaks, uint64_t checked,
                    uint64_t leakUnverified, const char* v, bool adversarial, bool anyHit) {
        const std::string unverified =
            capped ? fmt(" %8llu", (unsigned long long)(c.unverified + leakUnverified)) : "";
        return fmt("  %-10s %8llu %9llu %7llu %9llu %7llu%s %6s %10.3g%s %12.3g  %s%s\n",
                   name.c_str(), (unsigned long long)c.compared, (unsigned long long)c.agree,
                   (unsigned long long)c.ties, (unsigned long long)c.ambiguous,
                   (unsigned long long)c.wrong, unverified.c_str(),
                   checked ? std::to_string(leaks).c_str() : "-", c.ambiguousRate(),
                   adversarial ? "*" : " ", c.maxRelativeDt, v, anyHit ? " (any hit)" : "");
    };
    bool anyAdversarial = false;
    for (const SetCertification& k : r.sets) {
        s += line(k.range.name, k.counts, k.leaks, k.leakChecked, k.leakUnverified, verdict(k),
                  k.adversarial, k.query == QueryKind::AnyHit);
        anyAdversarial = anyAdversarial || k.adversarial;
    }
    if (r.sets.size() > 1) {
        const Outcome o = worse(r.correct(maxRate), r.watertight());
        s += line("all", r.all, r.leaks, r.leakChecked, r.leakUnverified,
                  o == Outcome::Fail         ? "FAIL"
                  : o == Outcome::Incomplete ? "incomplete"
                                             : "pass",
                  false, false);
    }
    s += fmt("  ambiguous rate over the%s sets: %.3g (%llu of %llu; limit %.3g): %s\n",
             anyAdversarial ? " non-adversarial" : "", r.strict.ambiguousRate(),
             (unsigned long long)r.strict.ambiguous, (unsigned long long)r.strict.compared, maxRate,
             r.strict.ambiguousRate() <= maxRate ? "pass" : "FAIL");
    s += boundsLine(r);
    if (anyAdversarial)
        s += "  * adversarial set: built of touchy rays, ambiguous answers expected there, up to "
             "the set's bound\n";
    for (const SetCertification& k : r.sets) {
        std::string reasons = reasonsText(k.counts);
        if (!reasons.empty()) s += "  " + k.range.name + " by reason:" + reasons + "\n";
        if (k.unsealed)
            s +=
                fmt("  %s: %llu targets the truth does not meet at the target on the stored ray "
                    "(unsealed: not counted as checked)\n",
                    k.range.name.c_str(), (unsigned long long)k.unsealed);
    }
    auto row = [&](const Finding& f) {
        return fmt("    %8llu %-9s %-10s %-18s %s | %s | %s\n", (unsigned long long)f.index,
                   f.set.c_str(), hitClassName(f.cls), ("[" + reasonNames(f.reasons) + "]").c_str(),
                   hitText(f.ours).c_str(), hitText(expected(f)).c_str(),
                   hitText(f.reference).c_str());
    };
    int shown = 0;
    for (const Finding& f : r.worst) {
        if (f.cls == HitClass::Agree || f.cls == HitClass::Tie) continue;
        if (shown++ == 12) break;
        if (shown == 1)
            s += "  first wrong, unverified, then ambiguous rays (row set: class [reasons] got | "
                 "expected (truth when rechecked) | embree)\n";
        s += row(f);
    }
    if (!r.examples.empty()) {
        s += "  an example of every class and reason that occurred (the first row of each)\n";
        for (const Finding& f : r.examples) s += row(f);
    }
    shown = 0;
    for (const SetCertification& k : r.sets)
        for (const LeakFinding& f : k.leakList) {
            if (shown++ == 12) break;
            if (shown == 1) s += "  leaks (row set: edge or vertex: target t | got | truth)\n";
            s += fmt("    %8llu %-9s %-16s t=%.9g | %s | %s\n", (unsigned long long)f.index,
                     f.set.c_str(), leakPlace(f.target).c_str(), f.target.t, hitText(f.got).c_str(),
                     f.rechecked ? hitText(f.truth).c_str() : "not rechecked");
        }
    return s;
}

namespace {

// The two verdicts, each with what to do when it is not a PASS.
std::string verdictLines(const CertifyReport& r) {
    const Outcome correct = r.result.correct(r.policy.maxAmbiguousRate);
    const Outcome watertight = r.result.watertight();
    std::string s;
    s += fmt("correct     %-10s", outcomeName(correct));
    const std::string over = r.result.setsOverAmbiguousLimit();
    if (correct == Outcome::Fail)
        s +=
            fmt(" %llu closest-hit or any-hit answers wrong, ambiguous rate %.3g (limit %.3g)%s: "
                "the rows above say which and why",
                (unsigned long long)r.result.all.wrong, r.result.strict.ambiguousRate(),
                r.policy.maxAmbiguousRate,
                over.empty() ? ""
                             : (", more ambiguous answers than the set's bound in " + over +
                                " (right answers turned into excused ones: a range end, an "
                                "edge or a grazing hit decided otherwise than it should be)")
                                   .c_str());
    else if (correct == Outcome::Incomplete)
        s += fmt(" %llu answers unverified past --max-rechecks: raise it or drop it to judge them",
                 (unsigned long long)r.result.all.unverified);
    else if (correct == Outcome::Pass)
        s += " no wrong answer";
    s += requireName(r.require) == std::string("watertight") ? " (not required)\n" : "\n";
    s += fmt("watertight  %-10s", outcomeName(watertight));
    if (watertight == Outcome::Fail)
        s +=
            fmt(" %llu rays went through a sealed edge or vertex: the triangle test has cracks; a "
                "watertight test does not (Woop, Benthin & Wald, \"Watertight Ray/Triangle "
                "Intersection\", JCGT 2013)",
                (unsigned long long)r.result.leaks);
    else if (watertight == Outcome::Incomplete)
        s += fmt(" %llu leak candidates unverified past --max-rechecks",
                 (unsigned long long)r.result.leakUnverified);
    else if (watertight == Outcome::Pass)
        s += fmt(" no leak at %llu sealed targets", (unsigned long long)r.result.leakChecked);
    else
        s += " (no edges or vertices set: make the rays with octrace rays --set edges,vertices)";
    s += requireName(r.require) == std::string("correct") ? " (not required)\n" : "\n";
    return s;
}

}  // namespace

namespace {

json cameraRowsJson(const std::optional<RayDefinitionReport>& c) {
    if (!c) return nullptr;
    return {{"pass", c->passes()},
            {"scope", c->scope},
            {"compared", c->compared},
            {"failures", c->failures},
            {"worst_ratio", report_detail::num(c->worstRatio)},
            {"errors", c->errors}};
}

json certifyReportBody(const CertifyReport& r) {
    json topo = nullptr;
    if (r.topology)
        topo = {{"closed", r.topology->closed},
                {"vertices", r.topology->vertices},
                {"edges", r.topology->edges},
                {"boundary_edges", r.topology->boundaryEdges},
                {"non_manifold_edges", r.topology->nonManifoldEdges}};
    json scene = sceneJson(r);
    scene["topology"] = topo;
    return {{"pass", r.passes()},
            {"verdict", outcomeName(r.outcome())},
            {"require", requireName(r.require)},
            {"correct", outcomeName(r.result.correct(r.policy.maxAmbiguousRate))},
            {"watertight", outcomeName(r.result.watertight())},
            {"wrong", r.result.all.wrong},
            {"ambiguous", r.result.all.ambiguous},
            {"unverified", r.result.all.unverified + r.result.leakUnverified},
            {"leaks", r.result.leaks},
            {"missing_standard_sets", r.missingSets},
            {"camera_rows", cameraRowsJson(r.cameraRows)},
            {"scene", scene},
            {"rays", r.rays},
            {"hits", r.hits},
            {"prim_ids", r.primIds},
            {"manifest", r.manifest},
            {"notes", r.notes},
            {"policy", policyJson(r.policy)},
            {"reference", referenceJson(r.referenceSeconds)},
            {"result", toJson(r.result, r.policy.maxAmbiguousRate)},
            {"seconds", {{"check", r.checkSeconds}, {"total", r.seconds}}}};
}

}  // namespace

json toJson(const CertifyReport& r) {
    return report_detail::withSchema(certifyReportBody(r), "octrace-certify-report");
}

std::string humanSummary(const CertifyReport& r) {
    std::string s = sceneHead("certify", r);
    if (r.topology)
        s += fmt("; closed: %s (%llu boundary edges, %llu non-manifold edges)",
                 r.topology->closed ? "yes" : "no", (unsigned long long)r.topology->boundaryEdges,
                 (unsigned long long)r.topology->nonManifoldEdges);
    s += "\n";
    const uint64_t rows = r.result.all.compared;
    s += fmt("rays     %s: %llu rows in %zu set(s)%s; hits %s%s\n", r.rays.c_str(),
             (unsigned long long)rows, r.result.sets.size(),
             r.manifest ? " (manifest checked)" : " (no manifest: one set)", r.hits.c_str(),
             r.primIds ? "" : " (distances only: a hit's primitive is inferred)");
    s += policyLine(r.policy,
                    "no wrong ray and no leak in any set, ambiguous rate of the non-adversarial "
                    "sets");
    s +=
        fmt("reference embree (robust) %.2f s; check %.2f s\n", r.referenceSeconds, r.checkSeconds);
    if (r.topology && !r.topology->closed && r.result.leakChecked)
        s += "leaks    the mesh is open: checked at edges shared by two triangles and closed "
             "fans only, where the target is sealed whatever the rest of the mesh is\n";
    for (const std::string& n : r.notes) s += "note     " + n + "\n";
    s += humanRaySets(r.result, r.policy.maxAmbiguousRate);
    if (r.cameraRows) {
        const RayDefinitionReport& c = *r.cameraRows;
        s += fmt("camera   %s against the pinhole camera's definition (double): %s",
                 c.scope.c_str(), c.passes() ? "PASS" : "FAIL");
        if (!c.passes())
            s +=
                fmt(", %llu rows off (worst %.3g x the tolerance): the rays are not the camera "
                    "set they claim; the build that made them has a faulty camera\n",
                    (unsigned long long)c.failures, c.worstRatio);
        else
            s += "\n";
        for (const std::string& e : c.errors) s += "  " + e + "\n";
    }
    s += "\n" + verdictLines(r);
    const std::vector<std::string>& missing = r.missingSets;
    s +=
        fmt("%s: %llu wrong, %llu ambiguous, %llu unverified, %llu leaks (of %llu rays checked "
            "for leaks) over %llu rays%s (%.2f s)\n",
            outcomeName(r.outcome()), (unsigned long long)r.result.all.wrong,
            (unsigned long long)r.result.all.ambiguous,
            (unsigned long long)(r.result.all.unverified + r.result.leakUnverified),
            (unsigned long long)r.result.leaks, (unsigned long long)r.result.leakChecked,
            (unsigned long long)rows,
            missing.empty()
                ? ""
                : (", partial: the standard sets " + joined(missing) + " not given").c_str(),
            r.seconds);
    return s;
}

}  // namespace oct
