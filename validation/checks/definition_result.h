// How the camera, shadow-ray and ray-scaling checks (one file each in this folder) describe a
// RayDefinitionReport (policy/ray_definitions.h) in validate's reports: one summary block, one
// JSON object, one failure clause.
#pragma once

#include "validation/policy/ray_definitions.h"
#include "validation/report/check_result.h"
#include "validation/report/report_util.h"

namespace oct {

// `field`: the JSON key; `label`: the summary's first word; `what`: what was held to what.
inline CheckResult definitionResult(const char* field, const char* label, const char* what,
                                    const RayDefinitionReport& d) {
    using report_detail::fmt;
    CheckResult r;
    r.pass = d.passes();
    r.json = {{field,
               {{"pass", d.passes()},
                {"scope", d.scope},
                {"compared", d.compared},
                {"unjudged", d.unjudged},
                {"failures", d.failures},
                {"worst_ratio", report_detail::num(d.worstRatio)},
                {"errors", d.errors},
                {"seconds", d.seconds}}}};
    r.summary =
        fmt("\n%-10s %s: %s, %s: %llu compared, %llu unjudged, %llu off it; worst error "
            "%.3g of its tolerance (%.1f ms)\n",
            label, d.passes() ? "PASS" : "FAIL", d.scope.c_str(), what,
            (unsigned long long)d.compared, (unsigned long long)d.unjudged,
            (unsigned long long)d.failures, d.worstRatio, 1e3 * d.seconds);
    for (const std::string& e : d.errors) r.summary += "  " + e + "\n";
    if (!r.pass)
        r.failureText = fmt(", %s: %llu off the definition", label, (unsigned long long)d.failures);
    return r;
}

}  // namespace oct
