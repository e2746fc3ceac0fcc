// The policy's tolerance options, the same spelling for validate and certify
// (docs/VALIDATION.md, "Tolerances, and why").
#pragma once

#include <CLI/CLI.hpp>

#include "apps/cli.h"
#include "validation/policy/hit_check.h"

namespace oct {

// `rateOver` says what the ambiguous rate is taken over, `recheckUnit` what one cap applies to.
inline void addPolicyOptions(CLI::App& cmd, ValidationPolicy& p, const std::string& rateOver,
                             const std::string& recheckUnit) {
    cmd.add_option("--max-ambiguous-rate", p.maxAmbiguousRate,
                   "Fail when ambiguous / compared exceeds this (" + rateOver + ")")
        ->capture_default_str()
        ->check(numberIn(0.0, 1.0));
    cmd.add_option("--t-tolerance", p.tTolerance,
                   "Same hit when |dt| <= this x scene extent (bounding-box diagonal)")
        ->capture_default_str()
        ->check(numberIn(0.0, 1.0));
    cmd.add_option("--edge-tolerance", p.edgeTolerance,
                   "Edge, vertex, tangent or range-end configuration within this x extent")
        ->capture_default_str()
        ->check(numberIn(0.0, 1.0));
    cmd.add_option("--grazing-cos", p.grazingCos, "Grazing ray when |cos(ray, normal)| <= this")
        ->capture_default_str()
        ->check(numberIn(0.0, 1.0));
    cmd.add_option("--max-rechecks", p.maxRechecks,
                   "Recheck at most this many mismatches in double " + recheckUnit +
                       "; the rest are unverified and the verdict INCOMPLETE (exit 3). "
                       "Default: every one")
        ->check(numberIn(1.0, 1.8e19));
}

}  // namespace oct
