#include "apps/cli.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <optional>
#include <sstream>

#include "core/io/output_file.h"
#include "core/render/frame.h"
#include "core/scene/scene_formats.h"
#include "core/system/resources.h"
#include "cpu_ref/render_cpu.h"
#include "dist/ranks.h"

namespace oct {

LoadOptions SceneOptions::loadOptions() const {
    LoadOptions o;
    o.radius = radius;
    return o;
}

LayoutOptions SceneOptions::layoutOptions() const {
    LayoutOptions o;
    o.build.maxDepth = maxDepth;
    o.build.maxPrims = maxPrims;
    o.build.maxNodes = limits.nodeBudget;
    o.hash = limits.hashParams();
    o.linearBudget = limits.linearBudgetBytes();
    return o;
}

void addSceneOptions(CLI::App& cmd, SceneOptions& o) {
    cmd.add_option("scene", o.path, sceneFormatsHelp())->required();
    cmd.add_option("--max-depth", o.maxDepth, "Deepest octree level (root = 0), 0..21")
        ->capture_default_str()
        ->check(numberIn(0, kMaxOctreeDepth));
    cmd.add_option("--max-prims", o.maxPrims, "Split a node holding more primitives than this")
        ->capture_default_str()
        ->check(numberIn(1, 1u << 30));
    cmd.add_option("--radius", o.radius,
                   "Sphere radius for point clouds (default: half the median nearest-neighbour "
                   "distance)")
        ->check(finiteNumber())
        ->check(positiveRadius());
    addLayoutLimitOptions(cmd, o.limits, "refused");
}

void addLayoutLimitOptions(CLI::App& cmd, LayoutLimitOptions& o, const std::string& overBudget) {
    cmd.add_option("--hash-slots", o.hashSlots, "Slots per hash bucket (B)")
        ->capture_default_str()
        ->check(numberIn(1, 64));
    cmd.add_option("--linear-budget", o.linearBudgetMiB,
                   "Largest linear octree to allocate, MiB (larger: " + overBudget + ")")
        ->capture_default_str()
        ->check(numberIn(1, double(uint64_t(1) << 24)));
    cmd.add_option(
           "--hash-budget", o.hashBudgetMiB,
           "Largest hash octree (m * B slots) to allocate, MiB (larger: " + overBudget + ")")
        ->capture_default_str()
        ->check(numberIn(1, double(uint64_t(1) << 24)));
    cmd.add_option("--node-budget", o.nodeBudget,
                   "Most octree nodes to build (48 bytes each, some 220 while building); a tree "
                   "needing more is refused while it is built, and so is a level needing more "
                   "memory than is left")
        ->capture_default_str()
        ->check(numberIn(1, double(kMaxNodeBudget)));
}

namespace {

// The shortest decimal that reads back as v ("0.001", "1073741824", "1e+06").
std::string shortest(double v) {
    char buf[40];
    for (int precision = 1; precision <= 17; ++precision) {
        std::snprintf(buf, sizeof buf, "%.*g", precision, v);
        if (std::strtod(buf, nullptr) == v) break;
    }
    return buf;
}

// Why `text` is refused as a number in [lo, hi], or "" (also for text that is no number at
// all: CLI11's conversion refuses that, naming the type it wanted).
std::string numberProblem(const std::string& text, double lo, double hi) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end == text.c_str()) return "";
    if (std::isnan(v) || std::isinf(v)) {
        // "1e999" reads as inf too: out of any range, not a spelling of infinity.
        if (std::isinf(v) && text.find_first_of("iI") == std::string::npos) {
            const double bound = v > 0 ? hi : lo;
            return text + (v > 0 ? " is too large" : " is too small") +
                   (std::isfinite(bound)
                        ? std::string(v > 0 ? " (at most " : " (at least ") + shortest(bound) + ")"
                        : std::string());
        }
        return text + " is not a finite number" +
               (std::isfinite(lo) ? " (give one in [" + shortest(lo) + ", " + shortest(hi) + "])"
                                  : "");
    }
    if (*end != '\0' || (v >= lo && v <= hi)) return "";
    return text + " is not in [" + shortest(lo) + ", " + shortest(hi) + "]";
}

}  // namespace

CLI::Validator positiveRadius() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            // A float > 0 (as the option holds it: 1e-50 would become 0, the default rule, and
            // 1e39 infinity); the message is short, unlike CLI::PositiveNumber's.
            char* end = nullptr;
            const double value = std::strtod(text.c_str(), &end);
            if (!text.empty() && *end == '\0' && std::isfinite(float(value)) && float(value) > 0.0f)
                return "";
            return text +
                   " is not a positive finite radius; give one, or leave --radius out for the "
                   "default rule";
        },
        "POSITIVE");
}

CLI::Validator finiteNumber() {
    return CLI::Validator(
        [](std::string& text) { return numberProblem(text, -INFINITY, INFINITY); }, "",
        kNumberValidator);
}

CLI::Validator numberIn(double lo, double hi, const std::string& why) {
    return CLI::Validator(
        [lo, hi, why](std::string& text) {
            const std::string problem = numberProblem(text, lo, hi);
            return problem.empty() || why.empty() ? problem : problem + " (" + why + ")";
        },
        "[" + shortest(lo) + ", " + shortest(hi) + "]", kNumberValidator);
}

void parseImageSize(const std::string& text, int& w, int& h) {
    unsigned long long a = 0, b = 0;
    char x = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%llu%c%llu%c", &a, &x, &b, &extra) != 3 || x != 'x' || a < 1 ||
        b < 1 || a > uint64_t(kMaxImageSide) || b > uint64_t(kMaxImageSide) ||
        text.find('-') != std::string::npos)
        throw FrameError("--size '" + text + "' must be WxH with 1 <= W, H <= " +
                         std::to_string(kMaxImageSide) + " (e.g. 512x512)");
    w = int(a);
    h = int(b);
}

Vec3 parseVec3(const std::string& option, const std::string& text) {
    std::istringstream in(text);
    Vec3 v;
    char c1 = 0, c2 = 0;
    if (!(in >> v.x >> c1 >> v.y >> c2 >> v.z) || c1 != ',' || c2 != ',' || !in.eof() ||
        !isFinite(v))
        throw CLI::ValidationError(option, "'" + text + "' is not three finite numbers x,y,z");
    return v;
}

void setCpuThreadsFromOption(int threads) { setCpuThreads(threads); }

void addThreadsOption(CLI::App& cmd, int& threads) {
    const int most = maxThreads();
    cmd.add_option("--threads", threads,
                   "OpenMP threads, at most " + std::to_string(most) + " (" +
                       std::to_string(kThreadsPerCore) +
                       " per core online; default: OMP_NUM_THREADS or all cores)")
        ->check(numberIn(1, most,
                         std::to_string(kThreadsPerCore) +
                             " per core online: more only take "
                             "turns on the cores, each with a stack of its own"));
}

void addTraceOptions(CLI::App& cmd, TraceChoice& o, const std::string& backendHelp) {
    // The plural spellings are bench's earlier ones, accepted everywhere.
    cmd.add_option("--accel,--accels", o.accel, "Acceleration layout: " + layoutNames())
        ->capture_default_str();
    cmd.add_option("--backend,--backends", o.backend, backendHelp)->capture_default_str();
    addThreadsOption(cmd, o.threads);
}

std::vector<const LayoutDesc*> parseLayoutList(const std::string& text) {
    std::vector<const LayoutDesc*> out;
    auto add = [&](const LayoutDesc* l) {
        if (std::find(out.begin(), out.end(), l) == out.end()) out.push_back(l);
    };
    for (const std::string& name : splitList(text)) {
        if (name == "all")
            for (const LayoutDesc& l : layouts()) add(&l);
        else
            add(&findLayout(name));
    }
    if (out.empty())
        throw CLI::ValidationError("--accel",
                                   "'" + text + "' names no layout (" + layoutNames() + ", all)");
    return out;
}

std::vector<const BackendDesc*> parseBackendList(const std::string& text,
                                                 std::vector<std::string>& notes,
                                                 bool keepUnavailable) {
    std::vector<const BackendDesc*> out;
    for (const std::string& name : splitList(text)) {
        std::string note;
        const BackendDesc* known = name == "auto" ? nullptr : findBackend(name);
        const BackendDesc* b = keepUnavailable && known ? known : &resolveBackend(name, note);
        if (!note.empty()) notes.push_back(note);
        if (std::find(out.begin(), out.end(), b) == out.end()) out.push_back(b);
    }
    if (out.empty())
        throw CLI::ValidationError(
            "--backend", "'" + text + "' names no backend (" + backendNames() + ", auto)");
    return out;
}

const LayoutDesc& parseOneLayout(const std::string& text, const char* command) {
    std::vector<const LayoutDesc*> l = parseLayoutList(text);
    if (l.size() != 1)
        throw CLI::ValidationError("--accel", "'" + text + "': " + command +
                                                  " uses one layout (validate and bench "
                                                  "compare several)");
    return *l[0];
}

const BackendDesc& parseOneBackend(const std::string& text, const char* command,
                                   std::string& note) {
    std::vector<std::string> notes;
    std::vector<const BackendDesc*> b = parseBackendList(text, notes);
    if (b.size() != 1)
        throw CLI::ValidationError("--backend", "'" + text + "': " + command +
                                                    " uses one backend (validate and bench "
                                                    "compare several)");
    agreeOnBackends(b, text);
    note = notes.empty() ? "" : notes[0];
    return *b[0];
}

void agreeOnBackends(const std::vector<const BackendDesc*>& list, const std::string& text) {
    Ranks& ranks = Ranks::world();
    if (!ranks.distributed()) return;
    std::string names;
    for (const BackendDesc* b : list) names += (names.empty() ? "" : ",") + std::string(b->name);
    const uint64_t id = std::hash<std::string>{}(names);
    // Both calls on every rank, then every rank throws alike: rank 0 prints the line.
    const uint64_t low = ranks.minOver(id), high = ~ranks.minOver(~id);  // maxOver is double's
    if (low != high)
        throw std::runtime_error("--backend " + text +
                                 ": the ranks resolved it differently (rank 0: " +
                                 (ranks.root() ? names : std::string("?")) +
                                 "; a GPU on some nodes only?); name the backends every rank has, "
                                 "e.g. --backend cpu");
}

void checkRayFileMemory(const char* command, const std::string& path, uint64_t rows,
                        uint64_t bytesPerRow) {
    checkMemory(saturatingMul(rows, bytesPerRow),
                std::string("octrace ") + command + " on the " + std::to_string(rows) +
                    " rays of '" + path + "'",
                std::string(command) +
                    " the rays in parts (numpy.array_split the file) or on a machine with more "
                    "memory");
}

void addJsonOption(CLI::App& cmd, std::string& path, const std::string& what) {
    cmd.add_option("--json", path,
                   "Also write " + what +
                       " as JSON to FILE; a bare --json or '-' writes it to stdout (the text "
                       "summary then goes to stderr). None by default")
        ->expected(0, 1)
        ->default_str("-");
}

void writeTextOutput(const std::string& path, const std::string& text) {
    if (path == "-") {
        std::cout << text << std::flush;
        return;
    }
    OutputSet out;  // all or nothing, never half a file
    out.stage(path, text.data(), text.size());
    out.commit();
}

namespace {

// Standard output is an output too: a full disk or a closed pipe behind it must not end in
// exit status 0 with the results lost (as `--json -` into /dev/full did).
bool standardOutputFailed() {
    errno = 0;
    std::cout.flush();
    return std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout;
}

}  // namespace

std::string outOfMemoryAdvice(const CLI::App& command) {
    // What shrinks the work, in the order worth trying, each named only where the command has
    // the option (certify and rays have no --max-depth; info has no --size).
    auto has = [&](const char* name) { return command.get_option_no_throw(name) != nullptr; };
    auto isCount = [&](const char* name) {
        return has(name) &&
               command.get_option_no_throw(name)->get_type_name().rfind("TEXT", 0) != 0;
    };
    std::vector<std::string> items;
    if (has("--size")) items.push_back("a smaller --size");
    if (isCount("--rays")) items.push_back("fewer --rays");
    if (has("--rays") && !isCount("--rays")) items.push_back("fewer rays in the --rays file");
    if (isCount("--count")) items.push_back("a smaller --count");
    items.push_back("a smaller scene");
    if (has("--max-depth")) items.push_back("a lower --max-depth");
    if (has("--max-prims")) items.push_back("a higher --max-prims");
    std::string advice;
    for (size_t i = 0; i < items.size(); ++i)
        advice += (i == 0 ? "" : i + 1 == items.size() ? " or " : ", ") + items[i];
    const std::string name = command.get_name();
    return "out of memory (std::bad_alloc)" + (command.get_parent() ? " in octrace " + name : "") +
           ": try " + advice;
}

void registerCommands(CLI::App& app) {
    registerInfo(app);
    registerRender(app);
    registerTrace(app);
    registerValidate(app);
    registerBench(app);
    registerList(app);
    registerRays(app);
    registerCertify(app);
    registerExplain(app);
}

namespace {

// How a rank's run of the command ended.
enum class Ending {
    Done,     // the command returned, or ended on its verdict (CommandVerdict) as every rank does
    Failed,   // an error of this rank's (bad input, out of memory): the other ranks must learn it
    Learned,  // another rank's error, already agreed on (RankFailed)
};

// Across MPI ranks only the commands that split their rows run (docs/DISTRIBUTED.md); any other
// would run whole on every rank, each writing the same outputs. Throws std::runtime_error naming
// the command.
void checkSplitCommand(int argc, char** argv) {
    static const char* const kSplit[] = {"trace", "certify", "render", "validate"};
    for (int i = 1; i < argc; ++i) {
        const std::string word = argv[i];
        if (word.empty() || word[0] == '-') continue;  // --help and the like: as usual
        for (const char* c : kSplit)
            if (word == c) return;
        throw std::runtime_error("octrace " + word +
                                 " runs in one process; across MPI ranks run trace, certify, "
                                 "render or validate (docs/DISTRIBUTED.md)");
    }
}

// One run of the command line on this rank: its exit status, and the line it ends with on
// standard error ("" for none).
int runCommand(int argc, char** argv, std::string& line, Ending& ending) {
    CLI::App app{
        "octrace: octree ray tracing after Barboza & Clua (SBGames 2011), with an "
        "OpenMP and a CUDA backend running one kernel, and Embree as ground truth"};
    app.require_subcommand(1);
    registerCommands(app);
    ending = Ending::Failed;
    // Every exit status is chosen here (cli.h, kExitSuccess .. kExitIncomplete).
    try {
        if (Ranks::world().distributed()) checkSplitCommand(argc, argv);
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        ending = Ending::Done;
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        ending = Ending::Done;
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        line = std::string("octrace: error: ") + e.what() + " (see --help)";
        return kExitError;
    } catch (const CommandVerdict& e) {
        ending = Ending::Done;
        line = std::string("octrace: ") + e.what();
        return e.status();
    } catch (const RankFailed& e) {
        ending = Ending::Learned;  // rank 0 prints the failed rank's line
        line = e.line();
        return e.status();
    } catch (const std::bad_alloc&) {
        const std::vector<CLI::App*> ran = app.get_subcommands();
        line = "octrace: error: " + outOfMemoryAdvice(ran.empty() ? app : *ran[0]);
        return kExitError;
    } catch (const std::exception& e) {
        line = std::string("octrace: error: ") + e.what();
        return kExitError;
    }
    if (standardOutputFailed()) {
        const int err = errno;
        line = std::string("octrace: error: cannot write standard output: ") +
               std::strerror(err ? err : EIO) + " (the results printed there are lost)";
        return kExitError;
    }
    ending = Ending::Done;
    return kExitSuccess;
}

}  // namespace

int runCli(int argc, char** argv) {
    std::optional<RanksSession> session;
    try {
        session.emplace(argc, argv);  // MPI_Init under a launcher (dist/ranks.h)
    } catch (const std::exception& e) {
        std::cerr << "octrace: error: " << e.what() << "\n";
        return kExitError;
    }
    Ranks& ranks = Ranks::world();
    std::string line;
    Ending ending = Ending::Done;
    int status = runCommand(argc, argv, line, ending);
    // A rank's own error meets the other ranks' next collective call (Ranks::fail); a run that
    // ended on every rank agrees once more before it exits, so that no rank leaves while
    // another still fails (rank 0's writes come last).
    if (ending == Ending::Failed) return ranks.fail(line, status);
    if (ending == Ending::Done && ranks.distributed()) {
        try {
            ranks.checkpoint();
        } catch (const RankFailed& e) {
            line = e.line();
            status = e.status();
        }
    }
    if (!line.empty() && ranks.root()) std::cerr << line << "\n";
    return status;
}

}  // namespace oct
