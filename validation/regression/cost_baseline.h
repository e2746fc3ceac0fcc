// Cost baselines: regression of the traversal's work (boxes tested, primitives tested per frame,
// TraceCost) pinned per frame of the regression set and per layout in its manifest
// (regression_manifest.h, tests/data/regression/regression.json). Traversal is deterministic,
// so an unchanged build reproduces the totals exactly. The rule (same / within / increased /
// dropped / missing / stale): docs/VALIDATION.md, "Cost baselines". This file holds the rule
// and its report; regression_run.h runs the set.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/render/film.h"
#include "validation/regression/regression_render.h"

namespace oct {

struct CostTotals {
    uint64_t pixels = 0, nodes = 0, prims = 0;
    double nodesPerPixel() const { return pixels ? double(nodes) / double(pixels) : 0.0; }
    double primsPerPixel() const { return pixels ? double(prims) / double(pixels) : 0.0; }
};

// The per-layout outcome, worst of nodes and prims first: `same` (equal totals), `within`
// (changed by at most the tolerance), `dropped` (lower by more: reported, passes),
// `increased` (higher by more: fails), `missing` (a layout of the scene without a baseline:
// fails, the manifest needs --update), `stale` (a baseline for a layout this build does not
// have, or that the scene no longer lists: reported, passes).
enum class CostVerdict { Same, Within, Dropped, Increased, Missing, Stale };
const char* costVerdictName(CostVerdict v);

struct CostRow {
    std::string scene, view, layout;
    std::string entry;        // the regression set's entry (regressionEntryName)
    RegressionRender render;  // the frame's size and tree
    std::string backend;      // the backend that measured `now` (every backend of our kernel is
                              // held to the same baseline: the kernel's work does not depend on it)
    std::optional<CostTotals> baseline, now;
    double nodesChange = 0.0, primsChange = 0.0;  // now / baseline - 1 (inf from a zero baseline)
    CostVerdict verdict = CostVerdict::Same;
    bool passes() const {
        return verdict != CostVerdict::Increased && verdict != CostVerdict::Missing;
    }
};

struct CostReport {
    std::string manifest;
    std::string baselineVersion;  // the octrace version that wrote the baselines
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

// A frame's totals over its pixels (the Film's per-pixel nodes and primitives tested).
CostTotals frameCost(const Film& film);

nlohmann::json toJson(const CostReport& r);
std::string humanSummary(const CostReport& r);

}  // namespace oct
