// The octrace command line: option parsing and printing only; the work lives in the library
// folders (core/, backends/, validation/, bench/). Every error reaches the user as one line on
// stderr and a non-zero exit status. The subcommands are registered in runCli (cli.cpp).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "backends/backend_list.h"
#include "core/octree/layout_registry.h"
#include "core/render/frame.h"
#include "core/scene/scene.h"

namespace oct {

// Runs the command line; returns the process exit status (docs/CERTIFY.md, "Exit status"): 0
// PASS or done, 1 FAIL, 2 bad input or usage, 3 INCOMPLETE. Never throws.
int runCli(int argc, char** argv);

constexpr int kExitFail = 1;
constexpr int kExitIncomplete = 3;

// A verdict that is not a PASS: validate and certify end with it, runCli prints the message
// and exits with the status.
class VerdictError : public std::runtime_error {
public:
    VerdictError(const std::string& message, int status)
        : std::runtime_error(message), status_(status) {}
    int status() const { return status_; }

private:
    int status_;
};

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

// --accel, --backend and --threads, the same spelling on every command that traces. Both take
// comma lists (spaces around items ignored); render and trace draw one layout on one backend
// and refuse a list of several with one line.
struct TraceChoice {
    std::string accel;
    std::string backend;
    int threads = 0;
};
// The defaults are o's values when called; `backendHelp` says what the command accepts.
void addTraceOptions(CLI::App& cmd, TraceChoice& o, const std::string& backendHelp);
// Applies --threads (0: leave OpenMP's default, i.e. OMP_NUM_THREADS or all cores).
void setCpuThreadsFromOption(int threads);

// Splits a comma list, trimming spaces and tabs around each item and dropping empty ones: the
// one list parser of the command line.
std::vector<std::string> splitList(const std::string& text);
// Layouts named in a --accel list ("all": every layout), without repeats, in the order given.
// Throws naming the option and the value when one is unknown or the list is empty.
std::vector<const LayoutDesc*> parseLayoutList(const std::string& text);
// Backends named in a --backend list (auto resolved), without repeats; `notes` receives what
// auto chose. Throws for an unknown name or one that cannot run here.
std::vector<const BackendDesc*> parseBackendList(const std::string& text,
                                                 std::vector<std::string>& notes);
// Exactly one layout or backend, for the commands that draw one (render, trace).
const LayoutDesc& parseOneLayout(const std::string& text, const char* command);
const BackendDesc& parseOneBackend(const std::string& text, const char* command, std::string& note);

// --json FILE, '-' for stdout; a bare --json (nothing after it) is stdout too.
void addJsonOption(CLI::App& cmd, std::string& path, const std::string& what);
// Writes text to `path`, or to stdout for '-'. Throws naming the file when it cannot.
void writeTextOutput(const std::string& path, const std::string& text);

// Parses --size "WxH" (1 <= W, H <= kMaxImageSide); throws FrameError naming the option.
void parseImageSize(const std::string& text, int& w, int& h);
// Parses "x,y,z" into a Vec3; throws CLI::ValidationError naming the option on bad input.
Vec3 parseVec3(const std::string& option, const std::string& text);

// --size, --eye, --target, --up, --fov, --light (apps/camera_options.cpp): the same camera for
// render and explain, so explain's --pixel names a pixel of render's image.
struct CameraChoice {
    std::string size = "512x512";
    std::string eye, target, up, light;
    float fov = 45.0f;
};
void addCameraOptions(CLI::App& cmd, CameraChoice& o);
// Parses and checks them (before anything is loaded); throws naming the option.
CameraOptions cameraOptions(const CameraChoice& o);

// Subcommand registration: each adds itself to the app and sets its callback.
void registerInfo(CLI::App& app);
void registerRender(CLI::App& app);
void registerTrace(CLI::App& app);
void registerValidate(CLI::App& app);
void registerBench(CLI::App& app);
void registerList(CLI::App& app);
void registerRays(CLI::App& app);
void registerCertify(CLI::App& app);
void registerExplain(CLI::App& app);

}  // namespace oct
