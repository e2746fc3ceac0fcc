// Pieces shared by the validation and certification reports (report.cpp): JSON of hits, reasons
// and findings, printf-style formatting, the counts line. Internal to validation/.
#pragma once

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "validation/policy/hit_validation.h"
#include "validation/policy/judged_scene.h"

namespace oct {
namespace report_detail {

using nlohmann::json;

// Non-finite numbers become null (JSON has no inf).
inline json num(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

inline json hitJson(Hit h) { return {{"t", num(h.t)}, {"prim", h.prim}}; }

inline json reasonsJson(uint32_t reasons) {
    json a = json::array();
    for (int b = 0; b < kReasonCount; ++b)
        if (reasons & (1u << b)) a.push_back(reasonName(b));
    return a;
}

inline json rayJson(const Ray& r) {
    return {r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z, num(r.tmin), num(r.tmax)};
}

inline json findingJson(const Finding& f, bool pixel) {
    json j;
    if (pixel) {
        j["x"] = f.x;
        j["y"] = f.y;
    } else {
        j["index"] = f.index;
        j["set"] = f.set;
        j["ray"] = rayJson(f.ray);
    }
    j["class"] = hitClassName(f.cls);
    j["reasons"] = reasonsJson(f.reasons);
    j["ours"] = hitJson(f.ours);
    j["reference"] = hitJson(f.reference);
    if (f.rechecked) j["truth"] = hitJson(f.truth);
    j["relative_dt"] = num(f.relativeDt);
    return j;
}

inline const char* shadowState(uint8_t s) {
    return s == kOccluded ? "occluded" : (s == kLit ? "lit" : "none");
}

inline json shadowJson(const ShadowFinding& f) {
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

// A report with its schema named (format, version 1), so that a reader can refuse a report it
// does not know (docs/VALIDATION.md, "Report fields").
inline json withSchema(json report, const char* format) {
    report["format"] = format;
    report["version"] = 1;
    return report;
}

inline std::string fmt(const char* f, ...) {
    char buf[1024];
    va_list ap;
    va_start(ap, f);
    std::vsnprintf(buf, sizeof buf, f, ap);
    va_end(ap);
    return buf;
}

// "miss" only for a well-formed miss; anything else shows what the tracer said.
inline std::string hitText(Hit h) {
    return h.prim == -1 && h.t == INFINITY ? std::string("miss")
                                           : fmt("t=%.9g #%d", double(h.t), h.prim);
}

inline std::string countsLine(const char* what, const ClassCounts& c) {
    return fmt("  %-8s %9llu %9llu %7llu %9llu %7llu %10.3g %12.3g\n", what,
               (unsigned long long)c.compared, (unsigned long long)c.agree,
               (unsigned long long)c.ties, (unsigned long long)c.ambiguous,
               (unsigned long long)c.wrong, c.ambiguousRate(), c.maxRelativeDt);
}

inline std::string reasonsText(const ClassCounts& c) {
    std::string s;
    for (int b = 0; b < kReasonCount; ++b)
        if (c.reasons[b]) s += fmt(" %s %llu", reasonName(b), (unsigned long long)c.reasons[b]);
    return s;
}

// The block validate's and certify's reports both begin with (policy/judged_scene.h). JSON:
// `scene` (name, kind, primitives, extent), `policy`, `reference`. Text: the head of the first
// line ("validate NAME: 992 triangles, extent 3.2") and the policy line, whose pass rule
// differs (it ends at "<= max ambiguous rate").
inline json sceneJson(const JudgedScene& r) {
    return {{"name", r.scene},
            {"kind", primKindName(r.kind)},
            {"primitives", r.primitives},
            {"extent", r.extent}};
}

inline json policyJson(const ValidationPolicy& p) {
    return {{"t_tolerance", p.tTolerance},
            {"edge_tolerance", p.edgeTolerance},
            {"grazing_cos", p.grazingCos},
            {"max_ambiguous_rate", p.maxAmbiguousRate},
            // null: no cap, every mismatch rechecked (the default)
            {"max_rechecks", p.maxRechecks == UINT64_MAX ? json(nullptr) : json(p.maxRechecks)}};
}

inline json referenceJson(double seconds) {
    return {{"tracer", "embree (RTC_SCENE_FLAG_ROBUST)"}, {"seconds", seconds}};
}

inline std::string sceneHead(const char* command, const JudgedScene& r) {
    return fmt("%s %s: %u %s, extent %.6g", command, r.scene.c_str(), r.primitives,
               primKindName(r.kind), r.extent);
}

inline std::string policyLine(const ValidationPolicy& p, const char* passRule) {
    return fmt(
        "policy   same hit: |dt| <= %.3g x extent; edge/tangent: %.3g x extent; grazing: "
        "|cos| <= %.3g; pass: %s <= %.3g\n",
        p.tTolerance, p.edgeTolerance, p.grazingCos, passRule, p.maxAmbiguousRate);
}

}  // namespace report_detail
}  // namespace oct
