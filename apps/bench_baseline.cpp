// octrace bench --baseline FILE [--update]: the glue between bench's options and the baseline
// file (bench/sweep/baseline.h has the file and the rule; bench/README.md, "Performance
// baselines", the measurements behind them).
#include <omp.h>

#include <cstdio>
#include <filesystem>

#include "apps/bench.h"
#include "core/io/output_file.h"
#include "validation/rays/ray_manifest.h"

namespace oct {
namespace {

using BaselineJson = nlohmann::ordered_json;

std::string commaList(const std::vector<std::string>& items) {
    std::string s;
    for (const std::string& i : items) s += (s.empty() ? "" : ",") + i;
    return s;
}

// An option of the file: present, of type T, and (numbers) within [lo, hi], else one line
// naming the file and the option.
template <class T>
T fileOption(const BaselineFile& f, const char* key, const std::string& file) {
    try {
        return f.options.at(key).get<T>();
    } catch (const nlohmann::json::exception&) {
        throw IoError(file + ": option '" + key +
                      "' is missing or has the wrong type; make the file with octrace bench "
                      "--baseline FILE --update");
    }
}

int fileCount(const BaselineFile& f, const char* key, int lo, int hi, const std::string& file) {
    const int v = fileOption<int>(f, key, file);
    if (v < lo || v > hi)
        throw IoError(file + ": option '" + key + "' is " + std::to_string(v) + ", not in [" +
                      std::to_string(lo) + ", " + std::to_string(hi) +
                      "]; make the file with octrace bench --baseline FILE --update");
    return v;
}

// The file's layouts that this build has; the others' cases come out stale.
std::string knownLayouts(const std::vector<std::string>& names, const std::string& file) {
    std::vector<std::string> known;
    for (const std::string& n : names)
        for (const LayoutDesc& l : layouts())
            if (n == l.name) known.push_back(n);
    if (known.empty())
        throw IoError(file + ": names no layout of this build (" + layoutNames() +
                      "); make the file with octrace bench --baseline FILE --update");
    return commaList(known);
}

// Every option of the file that the command line does not give.
void takeFileOptions(BenchOptions& o, const CLI::App& cmd, const BaselineFile& f) {
    const std::string& file = o.baseline;
    auto take = [&](const char* flag) { return cmd.count(flag) == 0; };
    if (take("--size")) o.size = fileOption<std::string>(f, "size", file);
    if (take("--warmup")) o.warmup = fileCount(f, "warmup", 0, 1000, file);
    if (take("--repeats")) o.repeats = fileCount(f, "repeats", 1, 1000, file);
    if (take("--threads")) o.trace.threads = fileCount(f, "threads", 1, maxThreads(), file);
    if (take("--seed")) o.seed = fileOption<uint64_t>(f, "seed", file);
    if (take("--max-depth")) o.meshMaxDepth = fileCount(f, "max_depth", 0, kMaxOctreeDepth, file);
    if (take("--max-prims")) o.meshMaxPrims = uint32_t(fileCount(f, "max_prims", 1, 1 << 30, file));
    if (take("--cloud-max-prims"))
        o.cloudMaxPrims = uint32_t(fileCount(f, "cloud_max_prims", 1, 1 << 30, file));
    if (take("--hash-slots"))
        o.limits.hashSlots = uint32_t(fileCount(f, "hash_slots", 1, 64, file));
    if (take("--clouds")) {
        std::vector<std::string> clouds;
        for (uint64_t n : fileOption<std::vector<uint64_t>>(f, "clouds", file))
            clouds.push_back(std::to_string(n));
        o.clouds = clouds.empty() ? "none" : commaList(clouds);
    }
    if (take("--meshes")) {
        const auto meshes = fileOption<std::vector<std::string>>(f, "meshes", file);
        o.meshes = meshes.empty() ? "none" : commaList(meshes);
    }
    if (take("--accel"))
        o.trace.accel =
            knownLayouts(fileOption<std::vector<std::string>>(f, "layouts", file), file);
    if (take("--backend"))
        o.trace.backend = commaList(fileOption<std::vector<std::string>>(f, "backends", file));
}

// Backends that cannot run here leave the list; their cases are skipped (never passed).
void dropUnavailableBackends(BenchOptions& o, NotRun& notRun) {
    std::vector<std::string> kept;
    bool reference = false;
    for (const std::string& name : splitList(o.trace.backend)) {
        const BackendDesc* b = findBackend(name);
        std::string why;
        if (b && !b->available(why)) {
            notRun.backends[name] = "backend not available here: " + why;
            std::fprintf(stderr,
                         "bench: baseline: %s is not available here (%s): its cases are "
                         "skipped\n",
                         name.c_str(), why.c_str());
            continue;
        }
        reference = reference || (b && b->reference);
        kept.push_back(name);  // unknown names are refused by parseBackendList, as without a file
    }
    if (!reference)
        throw CLI::ValidationError(
            "--backend", "'" + o.trace.backend + "' lacks " + referenceBackend().name +
                             ": --baseline takes every time as a ratio to its frames; add it");
    o.trace.backend = commaList(kept);
}

// The file's meshes that are not here (a fetched mesh, git-ignored): their cases are skipped.
void dropAbsentMeshes(BenchOptions& o, NotRun& notRun) {
    if (o.meshes == "none") return;
    std::vector<std::string> kept;
    for (const std::string& m : splitList(o.meshes)) {
        if (std::filesystem::is_regular_file(m)) {
            kept.push_back(m);
            continue;
        }
        const std::string scene = std::filesystem::path(m).filename().string();
        notRun.scenes[scene] = "mesh not found: " + m +
                               " (a relative path starts at the working folder: the committed "
                               "files' at the repository root; a fetched mesh: meshes/fetch)";
        std::fprintf(stderr, "bench: baseline: %s not found: its cases are skipped\n", m.c_str());
    }
    o.meshes = kept.empty() ? "none" : commaList(kept);
}

BaselineFile readForUpdate(const std::string& file) {
    try {
        return readBaseline(file);
    } catch (const IoError& e) {
        throw IoError(std::string(e.what()) +
                      " (--update rewrites only a baseline it can read: move this one away)");
    }
}

}  // namespace

BaselineRun prepareBaseline(BenchOptions& o, const CLI::App& cmd) {
    BaselineRun b;
    if (!o.update || std::filesystem::exists(o.baseline))
        b.stored = o.update ? readForUpdate(o.baseline) : readBaseline(o.baseline);
    if (b.stored) takeFileOptions(o, cmd, *b.stored);
    // One thread unless asked: the paired frames' CPU clock counts one thread's work exactly;
    // two threads also count the time one spins at the frame's end waiting for the other
    // (largest change between runs x3.4, against x1.14 with one; bench/README.md).
    if (cmd.count("--threads") == 0 && !b.stored) o.trace.threads = 1;
    const bool meshesFromFile = b.stored && cmd.count("--meshes") == 0;
    if (meshesFromFile) dropAbsentMeshes(o, b.notRun);
    dropUnavailableBackends(o, b.notRun);
    o.pairedReference = true;
    return b;
}

BaselineJson baselineRunOptions(const BenchOptions& o, const SweepOptions& s) {
    std::vector<uint64_t> clouds;
    std::vector<std::string> meshes, layoutList, backendList;
    for (const SceneSpec& sc : s.scenes) {
        if (sc.cloud)
            clouds.push_back(sc.n);
        else
            meshes.push_back(sc.path);
    }
    for (const LayoutDesc* l : s.layouts) layoutList.push_back(l->name);
    for (const BackendDesc* b : s.backends) backendList.push_back(b->name);
    return {{"size", std::to_string(s.width) + "x" + std::to_string(s.height)},
            {"warmup", o.warmup},
            {"repeats", o.repeats},
            {"threads", omp_get_max_threads()},
            {"seed", o.seed},
            {"max_depth", o.meshMaxDepth},
            {"max_prims", o.meshMaxPrims},
            {"cloud_max_prims", o.cloudMaxPrims},
            {"hash_slots", o.limits.hashSlots},
            {"clouds", clouds},
            {"meshes", meshes},
            {"layouts", layoutList},
            {"backends", backendList}};
}

void checkBaselineOptions(const BenchOptions& o, const BaselineRun& b,
                          const BaselineJson& runOptions) {
    if (o.update || !b.stored) return;
    const std::string mismatch = optionMismatch(b.stored->options, runOptions, o.baseline);
    if (!mismatch.empty())
        throw std::runtime_error(mismatch +
                                 ": ratios and counts measured with other options do not "
                                 "compare; leave the option out (the file's value is the "
                                 "default) or rewrite the file with --update");
}

void finishBaseline(const BenchOptions& o, const BaselineRun& b, const SweepResult& result,
                    const BaselineJson& machine, const BaselineJson& runOptions) {
    const std::string& file = o.baseline;
    if (o.update) {
        const std::vector<BaselineCase> cases = baselineCases(result.rows);
        if (result.failed > 0 || cases.empty())
            throw CommandVerdict(kExitFail, "bench baseline: " + std::to_string(result.failed) +
                                                " cases failed and " +
                                                std::to_string(cases.size()) + " measured; " +
                                                file + " left as it was");
        if (b.stored) {
            std::printf("against the file as it was (a note, not a verdict: --update):\n");
            std::fputs(
                humanSummary(compareBaseline(file, b.stored->cases, result.rows, b.notRun)).c_str(),
                stdout);
        }
        writeBaseline(file, {octraceVersion(), machine, runOptions, cases});
        std::printf("wrote %s: %zu cases\n", file.c_str(), cases.size());
        if (!b.notRun.scenes.empty() || !b.notRun.backends.empty())
            throw CommandVerdict(kExitIncomplete,
                                 "bench baseline INCOMPLETE: wrote " + file +
                                     " without the cases that cannot run here (see above)");
        return;
    }
    BaselineRule rule;
    rule.timeFactor = o.maxSlowdown;
    const BaselineReport rep = compareBaseline(file, b.stored->cases, result.rows, b.notRun, rule);
    std::fputs(humanSummary(rep).c_str(), stdout);
    if (rep.fails())
        throw CommandVerdict(kExitFail, "bench baseline FAILED against " + file + ": " +
                                            rep.failureText() + " (see the report above)");
    if (rep.incomplete())
        throw CommandVerdict(
            kExitIncomplete,
            "bench baseline INCOMPLETE: " + std::to_string(rep.count(CaseOutcome::Skipped)) +
                " cases of " + file + " skipped, " +
                std::to_string(rep.notRun.scenes.size() + rep.notRun.backends.size()) +
                " scenes or backends not run here (see above); what ran passed");
    std::printf("bench baseline PASS: %zu cases compared with %s\n",
                rep.count(CaseOutcome::Compared), file.c_str());
}

}  // namespace oct
