#include "apps/cli.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <sstream>

#include "core/io/output_file.h"
#include "core/render/frame.h"
#include "core/scene/scene_formats.h"
#include "cpu_ref/render_cpu.h"

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
    o.hash = limits.hashParams();
    o.linearBudget = limits.linearBudgetBytes();
    return o;
}

void addSceneOptions(CLI::App& cmd, SceneOptions& o) {
    cmd.add_option("scene", o.path, sceneFormatsHelp())->required();
    cmd.add_option("--max-depth", o.maxDepth, "Deepest octree level (root = 0), 0..21")
        ->capture_default_str()
        ->check(CLI::Range(0, kMaxOctreeDepth));
    cmd.add_option("--max-prims", o.maxPrims, "Split a node holding more primitives than this")
        ->capture_default_str()
        ->check(CLI::Range(1u, 1u << 30));
    cmd.add_option("--radius", o.radius,
                   "Sphere radius for point clouds (default: half the median nearest-neighbour "
                   "distance)")
        ->check(CLI::Validator(
            [](std::string& text) -> std::string {
                // A float > 0 (as o.radius holds it: 1e-50 would become 0, the default rule,
                // and 1e39 infinity); the message is short, unlike CLI::PositiveNumber's.
                char* end = nullptr;
                const double value = std::strtod(text.c_str(), &end);
                if (!text.empty() && *end == '\0' && std::isfinite(float(value)) &&
                    float(value) > 0.0f)
                    return "";
                return text +
                       " is not a positive finite radius; give one, or leave --radius out "
                       "for the default rule";
            },
            "POSITIVE"));
    addLayoutLimitOptions(cmd, o.limits, "refused");
}

void addLayoutLimitOptions(CLI::App& cmd, LayoutLimitOptions& o, const std::string& overBudget) {
    cmd.add_option("--hash-slots", o.hashSlots, "Slots per hash bucket (B)")
        ->capture_default_str()
        ->check(CLI::Range(1u, 64u));
    cmd.add_option("--linear-budget", o.linearBudgetMiB,
                   "Largest linear octree to allocate, MiB (larger: " + overBudget + ")")
        ->capture_default_str()
        ->check(CLI::Range(uint64_t(1), uint64_t(1) << 24));
    cmd.add_option(
           "--hash-budget", o.hashBudgetMiB,
           "Largest hash octree (m * B slots) to allocate, MiB (larger: " + overBudget + ")")
        ->capture_default_str()
        ->check(CLI::Range(uint64_t(1), uint64_t(1) << 24));
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

void addTraceOptions(CLI::App& cmd, TraceChoice& o, const std::string& backendHelp) {
    // The plural spellings are bench's earlier ones, accepted everywhere.
    cmd.add_option("--accel,--accels", o.accel, "Acceleration layout: " + layoutNames())
        ->capture_default_str();
    cmd.add_option("--backend,--backends", o.backend, backendHelp)->capture_default_str();
    cmd.add_option("--threads", o.threads, "OpenMP threads (default: OMP_NUM_THREADS or all cores)")
        ->check(CLI::Range(1, 4096));
}

std::vector<std::string> splitList(const std::string& text) {
    std::vector<std::string> out;
    std::string item;
    std::istringstream in(text);
    while (std::getline(in, item, ',')) {
        item.erase(0, item.find_first_not_of(" \t"));
        item.erase(item.find_last_not_of(" \t") + 1);
        if (!item.empty()) out.push_back(item);
    }
    return out;
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
                                                 std::vector<std::string>& notes) {
    std::vector<const BackendDesc*> out;
    for (const std::string& name : splitList(text)) {
        std::string note;
        const BackendDesc* b = &resolveBackend(name, note);
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
    note = notes.empty() ? "" : notes[0];
    return *b[0];
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

// What to try after std::bad_alloc, in the options of the command that ran (layout builders
// and loading name their own sizes; this is whatever else ran out).
std::string outOfMemoryAdvice(const CLI::App& app) {
    const std::vector<CLI::App*> ran = app.get_subcommands();
    const std::string command = ran.empty() ? "" : ran[0]->get_name();
    std::string advice = "a smaller scene, a lower --max-depth or a higher --max-prims";
    if (command == "render") advice = "a smaller --size, " + advice;
    if (command == "trace") advice = "fewer rays, " + advice;
    if (command == "validate" || command == "bench")
        advice = "a smaller --size, fewer --rays, " + advice;
    return "out of memory (std::bad_alloc)" + (command.empty() ? "" : " in octrace " + command) +
           ": try " + advice;
}

// Standard output is an output too: a full disk or a closed pipe behind it must not end in
// exit status 0 with the results lost (as `--json -` into /dev/full did).
bool standardOutputFailed() {
    errno = 0;
    std::cout.flush();
    return std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout;
}

}  // namespace

int runCli(int argc, char** argv) {
    CLI::App app{
        "octrace: octree ray tracing after Barboza & Clua (SBGames 2011), with an "
        "OpenMP and a CUDA backend running one kernel, and Embree as ground truth"};
    app.require_subcommand(1);
    registerInfo(app);
    registerRender(app);
    registerTrace(app);
    registerValidate(app);
    registerBench(app);
    registerList(app);
    registerRays(app);
    registerCertify(app);
    registerExplain(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "octrace: error: " << e.what() << " (see --help)\n";
        return 2;
    } catch (const VerdictError& e) {
        std::cerr << "octrace: " << e.what() << "\n";
        return e.status();
    } catch (const std::bad_alloc&) {
        std::cerr << "octrace: error: " << outOfMemoryAdvice(app) << "\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "octrace: error: " << e.what() << "\n";
        return 1;
    }
    if (standardOutputFailed()) {
        const int err = errno;
        std::cerr << "octrace: error: cannot write standard output: "
                  << std::strerror(err ? err : EIO) << " (the results printed there are lost)\n";
        return 1;
    }
    return 0;
}

}  // namespace oct
