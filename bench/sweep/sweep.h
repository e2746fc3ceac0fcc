// The paper's experiment (Barboza & Clua 2011, sec. 6) as a library: generated grid clouds of
// growing N and real meshes, each traced with every requested layout on every requested
// backend that runs our layouts, and with every backend that has its own structure (Embree) on
// the same rays as the reference for speed. Per case: build time, frame time (median, min, max
// of repeats after warm-up), rays per second, layout bytes, octree faces, traversal cost.
//
// Cases that cannot or should not run (a layout over its memory budget, exhaustive tracing
// estimated past maxSeconds) are rows with status "skipped" and the reason, never a crash.
// bench/make_results.py turns the files into plots and docs/RESULTS.md.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "backends/backend_list.h"
#include "bench/sweep/results.h"

namespace oct {

struct SceneSpec {
    bool cloud = true;
    uint32_t n = 0;    // grid cloud points
    std::string path;  // mesh file
    std::string label() const;
};

struct SweepOptions {
    std::vector<SceneSpec> scenes;
    std::vector<const LayoutDesc*> layouts;
    std::vector<const BackendDesc*> backends;  // in the order asked
    int width = 512, height = 512;
    int warmup = 1, repeats = 5;
    double maxSeconds = 300.0;   // per case, see planFrames in sweep.cpp
    uint64_t seed = 1;           // grid clouds
    BuildParams meshBuild;       // mesh octrees
    uint32_t cloudMaxPrims = 1;  // grid cloud octrees split down to the grid depth
    LayoutOptions limits;        // layouts' shape and budgets (its `build` is not used)
    bool progress = true;
    // Each timed frame of our layouts paired with a frame of the reference (Embree) traced next
    // to it, and ratio_to_embree the median of the pairs' ratios instead of median / Embree's
    // median: adjacent frames share the machine's load, so the ratio survives other work on a
    // shared machine (bench --baseline; bench/README.md, "Performance baselines", has the
    // spread with and without).
    bool pairedReference = false;
};

struct SweepResult {
    std::vector<Row> rows;  // as written to bench.json
    int failed = 0;         // cases with status "error" (skipped ones are not failures)
};

// Runs the sweep, printing a line per case on stdout and rewriting DIR/bench.json and
// DIR/bench.csv after every case (`machine` and `config` go into the JSON as given).
SweepResult runSweep(const SweepOptions& options, nlohmann::ordered_json machine,
                     const nlohmann::ordered_json& config, const std::filesystem::path& dir);

}  // namespace oct
