// The regression set `octrace validate --regression FILE [--update | --regression-add SCENE]`
// runs, with or without a scene: every frame of the manifest (regression_manifest.h) rendered
// once per layout, view and backend, and each frame held to its golden image and its cost
// baseline; or, with --update / --regression-add, the manifest's derived fields rewritten from
// this build, from the repository root `root`.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "validation/regression/cost_baseline.h"
#include "validation/regression/golden.h"
#include "validation/regression/regression_manifest.h"
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

// What --regression-add records for the new scene: its name and the settings given on the
// command line (the others stay the manifest's defaults).
struct RegressionAddition {
    std::string scene;
    std::optional<std::string> name;  // --regression-name (default: the scene's file name)
    SceneSettings settings;
};

// Check: every frame of the manifest on each backend of `backends` (empty: the manifest's
// `backends`); those not available here are skipped (RegressionReport::skipped), the others
// render every frame. Update and Add render on the host backend alone, write the images and
// the manifest all or none, and refuse (nothing written) when two layouts render different
// images or when Embree's frame breaks its rule against the new image: a golden image that
// depends on the layout, or that the reference disagrees with, is not one. Add refuses a scene
// already listed. Throws std::runtime_error for a backend that traces its own structure (Embree
// is the reference) and IoError for a missing or malformed manifest or image.
RegressionReport runRegression(const std::string& manifest, RegressionMode mode,
                               const std::string& root,
                               const std::vector<const BackendDesc*>& backends = {},
                               const RegressionAddition* addition = nullptr);

// Adds `golden` and `cost_baseline` (null when not run) to a report object and ands `pass`.
void addToJson(nlohmann::json& report, const RegressionReport& r);
std::string humanSummary(const RegressionReport& r);

}  // namespace oct
