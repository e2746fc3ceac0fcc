// octrace bench's options, and its performance baseline (`--baseline FILE`, `--update`): the
// options cmd_bench.cpp parses and the glue of apps/bench_baseline.cpp, which reads the file,
// takes from it the options the command line leaves out, and judges or rewrites it after the
// sweep (the rule and the file: bench/sweep/baseline.h).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "apps/cli.h"
#include "bench/sweep/baseline.h"
#include "bench/sweep/sweep.h"
#include "core/scene/grid_cloud.h"

namespace oct {

// The paper's clouds (1k .. 64k points), then two sizes beyond; with a GPU, two more. The four
// small ones place the crossover, where the octree starts to beat exhaustive tracing (below 1k
// points with this traversal).
inline constexpr const char* kDefaultClouds = "10,30,100,300,1k,2k,4k,8k,16k,32k,64k,256k,1M";

struct BenchOptions {
    bool quick = false;
    std::string out = "bench/results/latest";
    // accel empty: every layout; the device backend (cuda) is added when one answers.
    TraceChoice trace{"", std::string(hostBackend().name) + "," + referenceBackend().name};
    std::string clouds = kDefaultClouds;
    std::string meshes;  // empty: the defaults found under meshesDir
    std::string meshesDir;
    std::string size = "512x512";
    int repeats = 5;
    int warmup = 1;
    double maxSeconds = 300.0;
    uint64_t seed = kGridCloudDefaultSeed;
    int meshMaxDepth = BuildParams{}.maxDepth;
    uint32_t meshMaxPrims = BuildParams{}.maxPrims;
    uint32_t cloudMaxPrims = 1;
    LayoutLimitOptions limits;
    bool progress = true;
    bool pairedReference = false;
    std::string baseline;                      // --baseline FILE
    bool update = false;                       // --update: rewrite FILE from this run
    double maxSlowdown = kBaselineTimeFactor;  // --max-slowdown: BaselineRule::timeFactor
    std::string rays;                          // --rays R.npy: the ray bench instead of the sweep
    std::string scene;                         // --scene MESH: the scene of --rays
};

// The ray bench (apps/bench_rays.cpp, bench/sweep/ray_bench.h): o.rays traced on o.scene
// through every layout of --accel (default: those with an octree) on each backend of --backend
// (default: the host kernel, every backend with its own structure, an accelerator that
// answers), --warmup + --repeats interleaved rounds; prints the table and writes
// DIR/rays-bench.json and DIR/rays-bench.csv. Throws CommandVerdict kExitFail when a case that
// must agree exactly on hits does not (after writing the files).
void runRayBenchCommand(const BenchOptions& o, const CLI::App& cmd);

// What --baseline brings to a run: the stored file (none when --update makes a new one) and
// the cases of the file that cannot run here (a backend not available, a mesh not found).
struct BaselineRun {
    std::optional<BaselineFile> stored;
    NotRun notRun;
};

// Before the sweep: reads o.baseline (which must exist unless --update), sets every option of
// the file that the command line does not give (`cmd`), drops backends that cannot run here
// and meshes of the file that are not found (into notRun, with a note on stderr), and turns on
// the paired reference frames. Throws one line naming the file on a bad file.
BaselineRun prepareBaseline(BenchOptions& o, const CLI::App& cmd);

// The options of this run that the values depend on (the file's `options`), after parsing:
// `threads` is the number OpenMP uses.
nlohmann::ordered_json baselineRunOptions(const BenchOptions& o, const SweepOptions& s);

// Refuses (one line naming the option and the file) a run whose options differ from the
// stored file's; nothing for --update, which rewrites them.
void checkBaselineOptions(const BenchOptions& o, const BaselineRun& b,
                          const nlohmann::ordered_json& runOptions);

// After the sweep: judges the rows against the file and prints the report, or (--update)
// rewrites the file. Throws CommandVerdict: kExitFail when a case fails (or, updating, when a
// case failed and the file was left as it was), kExitIncomplete when cases were skipped.
void finishBaseline(const BenchOptions& o, const BaselineRun& b, const SweepResult& result,
                    const nlohmann::ordered_json& machine,
                    const nlohmann::ordered_json& runOptions);

}  // namespace oct
