// The regression files `octrace validate --golden DIR --cost-baseline FILE [--update]` runs,
// with or without a scene: either file, both or none (empty names), checked against this build
// or, with `update`, rewritten from it, from the repository root `root`.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "validation/regression/cost_baseline.h"
#include "validation/regression/golden.h"
#include "validation/report/check_result.h"

namespace oct {

// A backend asked for that cannot run here (no CUDA device): not run, and so not a pass.
struct SkippedBackend {
    std::string name, why;
};

struct RegressionReport {
    std::optional<GoldenReport> golden;
    std::optional<CostReport> cost;
    std::vector<SkippedBackend> skipped;

    bool ran() const { return golden || cost; }
    bool passes() const { return (!golden || golden->passes()) && (!cost || cost->passes()); }
    // What ran passed, but a backend asked for was skipped: the check is incomplete.
    bool incomplete() const { return passes() && !skipped.empty(); }
    // Golden's and the cost baselines' outcomes (report/check_result.h), in that order.
    std::vector<CheckResult> results() const;
    // ", 2 golden image comparisons off, 1 cost baselines exceeded or missing" ("" on a pass).
    std::string failureText() const;
};

// `backends`: the backends of our kernel to check (empty: the host's); those not available here
// are skipped (RegressionReport::skipped), the others render every file's scenes. --update
// rewrites from the host backend alone. Throws std::runtime_error for `update` without a file
// to rewrite, and for a backend that traces its own structure (Embree is the reference).
RegressionReport runRegressionFiles(const std::string& goldenDir, const std::string& costFile,
                                    bool update, const std::string& root,
                                    const std::vector<const BackendDesc*>& backends = {});
// Adds `golden` and `cost_baseline` (null when not run) to a report object and ands `pass`.
void addToJson(nlohmann::json& report, const RegressionReport& r);
std::string humanSummary(const RegressionReport& r);

}  // namespace oct
