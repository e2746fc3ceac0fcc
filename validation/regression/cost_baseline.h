// Cost baselines: regression of the traversal's work (nodes visited, primitives tested per frame,
// TraceCost) pinned per scene and per layout of the registry in a committed JSON file
// (tests/data/cost_baselines.json). Traversal is deterministic, so an unchanged build
// reproduces the totals exactly. The file's fields and the rule (same / within / increased /
// dropped / missing / stale): docs/VALIDATION.md, "Cost baselines".
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "validation/regression/regression_render.h"

namespace oct {

struct CostTotals {
    uint64_t pixels = 0, nodes = 0, prims = 0;
    double nodesPerPixel() const { return pixels ? double(nodes) / double(pixels) : 0.0; }
    double primsPerPixel() const { return pixels ? double(prims) / double(pixels) : 0.0; }
};

// The per-layout outcome, worst of nodes and prims first: `same` (equal totals), `within`
// (changed by at most the tolerance), `dropped` (lower by more: reported, passes),
// `increased` (higher by more: fails), `missing` (a layout of the registry without a baseline:
// fails, the file needs --update), `stale` (a baseline for a layout this build does not have:
// reported, passes).
enum class CostVerdict { Same, Within, Dropped, Increased, Missing, Stale };
const char* costVerdictName(CostVerdict v);

struct CostRow {
    std::string scene, layout;
    std::string backend;  // the backend that measured `now` (every backend of our kernel is
                          // held to the same baseline: the kernel's work does not depend on it)
    std::optional<CostTotals> baseline, now;
    double nodesChange = 0.0, primsChange = 0.0;  // now / baseline - 1 (inf from a zero baseline)
    CostVerdict verdict = CostVerdict::Same;
    bool passes() const {
        return verdict != CostVerdict::Increased && verdict != CostVerdict::Missing;
    }
};

struct CostReport {
    std::string file;
    std::string baselineVersion;  // the octrace version that wrote the baselines
    RegressionRender render;
    double tolerance = 0.05;
    bool updated = false;  // rows compare the new totals with the old ones (update mode)
    std::vector<CostRow> rows;
    double seconds = 0.0;

    uint64_t failures() const;  // 0 in update mode
    bool passes() const { return failures() == 0; }
};

// The default rule: fail above +5 % (docs/VALIDATION.md has why).
constexpr double kCostTolerance = 0.05;

// Compares one layout's totals with its baseline (sets the changes and the verdict).
CostRow judgeCost(std::string scene, std::string layout, std::optional<CostTotals> baseline,
                  std::optional<CostTotals> now, double tolerance);

// Reads FILE, renders every scene with every layout of the registry on each of `backends`
// (empty: the host's) and judges each against the layout's baseline. Throws (one line, naming
// the file) on a missing or malformed file.
CostReport checkCostBaselines(const std::string& file, const std::string& root,
                              double tolerance = kCostTolerance,
                              const std::vector<const BackendDesc*>& backends = {});

// Re-measures every scene of FILE with every layout of the registry and rewrites FILE (with
// this build's version); rows compare the new totals with the old ones.
CostReport updateCostBaselines(const std::string& file, const std::string& root);

nlohmann::json toJson(const CostReport& r);
std::string humanSummary(const CostReport& r);

}  // namespace oct
