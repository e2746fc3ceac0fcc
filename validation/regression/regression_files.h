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

struct RegressionReport {
    std::optional<GoldenReport> golden;
    std::optional<CostReport> cost;

    bool ran() const { return golden || cost; }
    bool passes() const { return (!golden || golden->passes()) && (!cost || cost->passes()); }
    // Golden's and the cost baselines' outcomes (report/check_result.h), in that order.
    std::vector<CheckResult> results() const;
    // ", 2 golden image comparisons off, 1 cost baselines exceeded or missing" ("" on a pass).
    std::string failureText() const;
};

// Throws std::runtime_error for `update` without a file to rewrite.
RegressionReport runRegressionFiles(const std::string& goldenDir, const std::string& costFile,
                                    bool update, const std::string& root);
// Adds `golden` and `cost_baseline` (null when not run) to a report object and ands `pass`.
void addToJson(nlohmann::json& report, const RegressionReport& r);
std::string humanSummary(const RegressionReport& r);

}  // namespace oct
