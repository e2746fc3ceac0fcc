// The octrace command line: option parsing and printing only; the work lives in the library
// folders (core/, backends/, validation/, bench/). Every error reaches the user as one line on
// stderr and a non-zero exit status. The subcommands are registered in registerCommands.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "backends/backend_list.h"
#include "core/io/name_list.h"
#include "core/octree/layout_registry.h"
#include "core/render/frame.h"
#include "core/scene/scene.h"
#include "core/system/resources.h"

namespace oct {

// The exit statuses of every command, in this one place (runCli maps what a command throws):
//   0  success (a certification or validation: PASS);
//   1  a verdict: FAIL (certify, validate) or failed cases (bench), thrown as CommandVerdict;
//   2  the command could not do its work: a usage error, a bad option value, an input that is
//      missing, not a regular file or malformed, and any other error (out of memory, an output
//      that cannot be written), as grep and diff use 2 for trouble;
//   3  a verdict: INCOMPLETE (certify, when what it could check does not settle the verdict).
constexpr int kExitSuccess = 0;
constexpr int kExitFail = 1;
constexpr int kExitError = 2;
constexpr int kExitIncomplete = 3;

// A command's verdict other than success: runCli prints "octrace: " and what() as one line and
// exits with `status` (kExitFail or kExitIncomplete). Every other exception exits kExitError.
class CommandVerdict : public std::runtime_error {
public:
    CommandVerdict(int status, const std::string& what)
        : std::runtime_error(what), status_(status) {}
    int status() const { return status_; }

private:
    int status_;
};

// Runs the command line; returns the process exit status. Never throws.
int runCli(int argc, char** argv);
// Adds every subcommand to app (what runCli parses; the tests walk their options).
void registerCommands(CLI::App& app);
// The line runCli prints after std::bad_alloc in `command` (a subcommand, or the app when none
// ran): what to try, naming only options the command has.
std::string outOfMemoryAdvice(const CLI::App& command);

// The one validator of numeric options, on every option of every command that takes a number
// (tests/apps walks them all): NaN and +-inf, in any spelling strtod reads, are refused with
// one line naming the option (CLI11's Range lets NaN through), and so is a value outside
// [lo, hi], the bounds printed as %g (never 309 digits). Text that is no number is left to
// CLI11's conversion, which names it. Named kNumberValidator, so a test can find it.
constexpr const char* kNumberValidator = "NUMBER";
CLI::Validator finiteNumber();
// `why`, when given, is appended to the out-of-range message: why the bounds are what they are
// ("--threads: 4096 is not in [1, 16] (8 per core online ...)").
CLI::Validator numberIn(double lo, double hi, const std::string& why = "");
// --radius's own range, after finiteNumber(): a float > 0 (0 is the default rule, not a value).
CLI::Validator positiveRadius();

// --hash-slots, --linear-budget, --hash-budget, --node-budget: the layouts' shape and the
// memory limits of the octree and its layouts, the same for every command that builds layouts
// (SceneOptions below, and `octrace bench`).
struct LayoutLimitOptions {
    uint32_t hashSlots = HashParams{}.bucketSlots;
    uint64_t linearBudgetMiB = kDefaultLinearBudget >> 20;
    uint64_t hashBudgetMiB = kDefaultHashBudget >> 20;
    uint64_t nodeBudget = kDefaultNodeBudget;  // BuildParams::maxNodes

    uint64_t linearBudgetBytes() const { return linearBudgetMiB << 20; }
    HashParams hashParams() const { return {hashSlots, hashBudgetMiB << 20}; }
};
// Registers the four options; `overBudget` ends the layout budgets' help (what happens past one).
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
// --threads alone (certify, which has no --accel or --backend), bounded by maxThreads().
void addThreadsOption(CLI::App& cmd, int& threads);
// Applies --threads (0: leave OpenMP's default, i.e. OMP_NUM_THREADS or all cores).
void setCpuThreadsFromOption(int threads);
// --threads' bound: maxThreads() (core/system/resources.h).

// splitList (core/io/name_list.h) is the one list parser of the command line.
// Layouts named in a --accel list ("all": every layout), without repeats, in the order given.
// Throws naming the option and the value when one is unknown or the list is empty.
std::vector<const LayoutDesc*> parseLayoutList(const std::string& text);
// Backends named in a --backend list (auto resolved), without repeats; `notes` receives what
// auto chose. Throws for an unknown name or one that cannot run here.
// With `keepUnavailable`, a backend of the list that cannot run here is kept (the regression
// files report it as skipped) instead of refused.
std::vector<const BackendDesc*> parseBackendList(const std::string& text,
                                                 std::vector<std::string>& notes,
                                                 bool keepUnavailable = false);
// Exactly one layout or backend, for the commands that draw one (render, trace).
const LayoutDesc& parseOneLayout(const std::string& text, const char* command);
const BackendDesc& parseOneBackend(const std::string& text, const char* command, std::string& note);
// Across MPI ranks (dist/ranks.h): every rank resolved `--backend text` to the same `list`
// (`auto` resolves against each rank's own hardware), else throws std::runtime_error on every
// rank alike. Collective; nothing in one process.
void agreeOnBackends(const std::vector<const BackendDesc*>& list, const std::string& text);

// Before a ray file's rows are read (the reader's allocate step): `rows` times `bytesPerRow`
// (the rows and what the command keeps per row) against the machine's memory; throws
// ResourceError naming the file, its rows and the figure.
void checkRayFileMemory(const char* command, const std::string& path, uint64_t rows,
                        uint64_t bytesPerRow);

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
