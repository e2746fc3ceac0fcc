// The octrace command line: subcommands info, render, trace (and more as they land). Every
// error reaches the user as one line on stderr and a non-zero exit status.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/octree/accel.h"
#include "core/scene/scene.h"

namespace oct {

// Runs the command line; returns the process exit status. Never throws.
int runCli(int argc, char** argv);

// --hash-slots, --linear-budget, --hash-budget: the layouts' shape and memory limits, the same
// for every command that builds layouts (SceneOptions below, and `octrace bench`).
struct LayoutLimitOptions {
    uint32_t hashSlots = HashParams{}.bucketSlots;
    uint64_t linearBudgetMiB = kDefaultLinearBudget >> 20;
    uint64_t hashBudgetMiB = kDefaultHashBudget >> 20;

    uint64_t linearBudgetBytes() const { return linearBudgetMiB << 20; }
    HashParams hashParams() const { return {hashSlots, hashBudgetMiB << 20}; }
};
// Registers the three options; `overBudget` ends the budgets' help (what happens past one).
void addLayoutLimitOptions(CLI::App& cmd, LayoutLimitOptions& o, const std::string& overBudget);

// Options every subcommand that builds an octree shares (`octrace info` documents them).
struct SceneOptions {
    std::string path;
    int maxDepth = BuildParams{}.maxDepth;
    uint32_t maxPrims = BuildParams{}.maxPrims;
    float radius = 0.0f;
    LayoutLimitOptions limits;

    LoadOptions loadOptions() const;
    LayoutOptions layoutOptions() const;
};

void addSceneOptions(CLI::App& cmd, SceneOptions& o);
// --accel, --backend, --threads for the commands that trace.
void addBackendOptions(CLI::App& cmd, std::string& accel, std::string& backend, int& threads);
// Applies --threads (0: leave OpenMP's default, i.e. OMP_NUM_THREADS or all cores).
void setCpuThreadsFromOption(int threads);

// Parses --size "WxH" (1 <= W, H <= kMaxImageSide); throws FrameError naming the option.
void parseImageSize(const std::string& text, int& w, int& h);
// Parses "x,y,z" into a Vec3; throws CLI::ValidationError naming the option on bad input.
Vec3 parseVec3(const std::string& option, const std::string& text);

// Subcommand registration: each adds itself to the app and sets its callback.
void registerInfo(CLI::App& app);
void registerRender(CLI::App& app);
void registerTrace(CLI::App& app);
void registerValidate(CLI::App& app);
void registerBench(CLI::App& app);

}  // namespace oct
