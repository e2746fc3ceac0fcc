// octrace bench: the paper's experiment as a sweep (bench/sweep/sweep.h does the work). This
// file parses the options, picks the default clouds and meshes, and records the configuration;
// --baseline's file is read and judged by apps/bench_baseline.cpp.
#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "apps/bench.h"
#include "apps/cli.h"
#include "bench/sweep/machine.h"
#include "bench/sweep/sweep.h"
#include "core/scene/grid_cloud.h"
#include "core/system/resources.h"
#include "cpu_ref/render_cpu.h"

namespace oct {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

// With a GPU, two clouds beyond kDefaultClouds (apps/bench.h).
const char* kDefaultGpuExtraClouds = "4M,16M";
const char* kQuickClouds = "1k,2k,4k";

// Default meshes, ascending in triangles so the time guard's history grows with the size. Of
// the four wuson files (one model in four formats) only the OBJ is benchmarked.
const char* kDefaultMeshes[] = {"cube_binary.ply",
                                "cornell_box.obj",
                                "sphere_with_hole.stl",
                                "teapot.obj",
                                "spider.obj",
                                "wuson.obj",
                                "cache/dragon_vrip_res4.ply",
                                "cache/dragon_vrip_res3.ply",
                                "cache/bunny.obj",
                                "cache/dragon_vrip_res2.ply",
                                "cache/dragon_vrip.ply"};
const char* kQuickMeshes[] = {"cornell_box.obj", "teapot.obj"};

// --max-seconds: a case's time budget, positive (0 was refused with the double's largest value
// printed in full); a nanosecond skips every case that needs a probe frame (the tests' way to
// see the guard), and above 1e6 s (11.6 days) it is no budget.
constexpr double kMinCaseSeconds = 1e-9, kMaxCaseSeconds = 1e6;

// "1000", "64k" (x 1000), "1M" (x 1,000,000).
uint32_t parseCount(const std::string& text) {
    uint64_t scale = 1;
    std::string digits = text;
    char last = text.empty() ? 0 : text.back();
    if (last == 'k' || last == 'K') scale = 1000;
    if (last == 'm' || last == 'M') scale = 1000000;
    if (scale > 1) digits.pop_back();
    if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos ||
        digits.size() > 10)
        throw CLI::ValidationError("--clouds",
                                   "'" + text + "' is not a point count (e.g. 1000, 64k, 1M)");
    uint64_t n = std::stoull(digits) * scale;
    uint64_t maxN = uint64_t(1) << (3 * kGridCloudMaxDepth);
    if (n == 0 || n > maxN)
        throw CLI::ValidationError(
            "--clouds", "'" + text + "' must be between 1 and " + std::to_string(maxN) + " points");
    return uint32_t(n);
}

// Before the sweep: its largest case against the machine's memory. A case holds its Film and
// the reference frame's (20 bytes a pixel each) and, for a cloud, the cloud being made
// (gridCloudBytes); the octree and the layouts check their own (the builder's node budget, the
// layout budgets). Without it a 16384x16384 sweep under a memory limit skipped every case as
// "out of memory" and exited 0.
void checkSweepMemory(const BenchOptions& o, const SweepOptions& s) {
    uint64_t largestCloud = 0;
    for (const SceneSpec& scene : s.scenes)
        if (scene.cloud) largestCloud = std::max(largestCloud, gridCloudBytes(scene.n));
    const uint64_t pixels = uint64_t(s.width) * uint64_t(s.height);
    checkMemory(
        saturatingAdd(saturatingMul(pixels, 2 * kFilmBytesPerPixel), largestCloud),
        "octrace bench --size " + o.size + (o.clouds == "none" ? "" : " --clouds " + o.clouds),
        "use a smaller --size or smaller --clouds");
}

std::string joined(const std::vector<std::string>& items) {
    std::string s;
    for (const std::string& i : items) s += (s.empty() ? "" : ",") + i;
    return s;
}

fs::path findMeshesDir(const std::string& given) {
    if (!given.empty()) {
        if (!fs::is_directory(given))
            throw std::runtime_error("--meshes-dir '" + given + "' is not a directory");
        return given;
    }
    if (fs::is_directory("meshes")) return "meshes";
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        // The build folder usually sits in the source tree (build/, build-*/).
        for (fs::path p = exe.parent_path(); !p.empty() && p != p.root_path(); p = p.parent_path())
            if (fs::is_directory(p / "meshes") && fs::exists(p / "meshes" / "teapot.obj"))
                return p / "meshes";
    }
    return {};
}

// The scenes to sweep: clouds, then meshes (the defaults found, or the files given). Missing
// default meshes become notes, never errors.
std::vector<SceneSpec> sceneList(const BenchOptions& o, std::vector<std::string>& notes) {
    std::vector<SceneSpec> scenes;
    if (o.clouds != "none")
        for (const std::string& c : splitList(o.clouds))
            scenes.push_back({true, parseCount(c), ""});
    if (o.meshes.empty()) {
        fs::path dir = findMeshesDir(o.meshesDir);
        if (dir.empty()) {
            notes.push_back("no meshes/ folder found (give --meshes-dir): no meshes benchmarked");
            return scenes;
        }
        auto push = [&](const char* name) {
            fs::path p = dir / name;
            if (fs::exists(p))
                scenes.push_back({false, 0, p.lexically_normal().string()});
            else
                notes.push_back(
                    "not found, not benchmarked: " + p.string() +
                    (std::string(name).rfind("cache/", 0) == 0 ? " (run meshes/fetch)" : ""));
        };
        if (o.quick)
            for (const char* m : kQuickMeshes) push(m);
        else
            for (const char* m : kDefaultMeshes) push(m);
    } else if (o.meshes != "none") {
        for (const std::string& m : splitList(o.meshes)) {
            if (!fs::is_regular_file(m))
                throw std::runtime_error("--meshes: '" + m + "' is not a file");
            scenes.push_back({false, 0, m});
        }
    }
    return scenes;
}

void runBench(BenchOptions o, CLI::App* cmd) {
    if (!o.rays.empty()) return runRayBenchCommand(o, *cmd);
    // A baseline's backends are its own (or --backend's): no device is added to them.
    const bool backendsGiven = cmd->count("--backend") > 0 || !o.baseline.empty();
    if (o.quick) {
        // A smoke test of the whole pipeline in well under a minute; options given explicitly
        // still win.
        if (!cmd->count("--clouds")) o.clouds = kQuickClouds;
        if (!cmd->count("--size")) o.size = "128x128";
        if (!cmd->count("--repeats")) o.repeats = 2;
        if (!cmd->count("--warmup")) o.warmup = 1;
        if (!cmd->count("--max-seconds")) o.maxSeconds = 20.0;
    }
    // The file's options where the command line gives none (after --quick's, which they win).
    BaselineRun baseline;
    if (!o.baseline.empty()) baseline = prepareBaseline(o, *cmd);
    SweepOptions s;
    parseImageSize(o.size, s.width, s.height);
    setCpuThreadsFromOption(o.trace.threads);

    // Backends: by default cpu and embree, plus an accelerator when one answers (and then the
    // two larger clouds it can afford).
    std::string deviceName, note;
    if (!backendsGiven) {
        const BackendDesc& autoChoice = resolveBackend("auto", note);
        if (autoChoice.device) {
            o.trace.backend += std::string(",") + autoChoice.name;
            if (!cmd->count("--clouds") && !o.quick)
                o.clouds += std::string(",") + kDefaultGpuExtraClouds;
            note = "bench: " + note + ": adding the " + autoChoice.name + " backend";
        } else {
            note = "bench: " + note + ": cpu and embree only";
        }
    }
    std::vector<std::string> backendNotes;
    s.backends = parseBackendList(o.trace.backend, backendNotes);
    for (const BackendDesc* b : s.backends)
        if (b->device) b->available(deviceName);
    s.layouts = o.trace.accel.empty() ? parseLayoutList("all") : parseLayoutList(o.trace.accel);

    std::vector<std::string> meshNotes;
    s.scenes = sceneList(o, meshNotes);
    if (s.scenes.empty()) throw CLI::ValidationError("--clouds", "nothing to benchmark");
    checkSweepMemory(o, s);
    const json runOptions = baselineRunOptions(o, s);
    if (!o.baseline.empty()) checkBaselineOptions(o, baseline, runOptions);

    fs::path dir = o.out;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (!fs::is_directory(dir))
        throw std::runtime_error("--out '" + o.out + "': cannot create the folder" +
                                 (ec ? " (" + ec.message() + ")" : ""));

    if (!note.empty()) std::fprintf(stderr, "%s\n", note.c_str());
    for (const std::string& n : backendNotes) std::fprintf(stderr, "bench: %s\n", n.c_str());
    for (const std::string& n : meshNotes) std::fprintf(stderr, "bench: %s\n", n.c_str());

    s.warmup = o.warmup;
    s.repeats = o.repeats;
    s.maxSeconds = o.maxSeconds;
    s.seed = o.seed;
    s.meshBuild.maxDepth = o.meshMaxDepth;
    s.meshBuild.maxPrims = o.meshMaxPrims;
    s.meshBuild.maxNodes = o.limits.nodeBudget;  // clouds too: their build starts from it
    s.cloudMaxPrims = o.cloudMaxPrims;
    s.limits.hash = o.limits.hashParams();
    s.limits.linearBudget = o.limits.linearBudgetBytes();
    s.progress = o.progress;
    s.pairedReference = o.pairedReference;

    json machine = machineJson(deviceName);
    std::vector<std::string> backendNames, layoutNames, sceneNames;
    for (const BackendDesc* b : s.backends) backendNames.push_back(b->name);
    for (const LayoutDesc* l : s.layouts) layoutNames.push_back(l->name);
    for (const SceneSpec& sc : s.scenes) sceneNames.push_back(sc.label());
    json config = {{"quick", o.quick},
                   {"size", {s.width, s.height}},
                   {"warmup", o.warmup},
                   {"repeats", o.repeats},
                   {"max_seconds", o.maxSeconds},
                   {"backends", backendNames},
                   {"layouts", layoutNames},
                   {"scenes", sceneNames},
                   {"seed", o.seed},
                   {"cloud_octree", {{"max_depth", "grid depth"}, {"max_prims", o.cloudMaxPrims}}},
                   {"mesh_octree", {{"max_depth", o.meshMaxDepth}, {"max_prims", o.meshMaxPrims}}},
                   {"hash_slots", o.limits.hashSlots},
                   {"linear_budget_bytes", o.limits.linearBudgetBytes()},
                   {"hash_budget_bytes", o.limits.hashParams().budgetBytes},
                   {"node_budget", o.limits.nodeBudget},
                   {"paired_reference", o.pairedReference},
                   {"baseline", o.baseline.empty() ? json(nullptr) : json(o.baseline)},
                   {"notes", meshNotes}};

    std::printf(
        "octrace bench: %zu scenes x (%s) x (%s), %dx%d, warm-up %d, repeats %d, on %s "
        "(%d OpenMP threads)%s\n",
        s.scenes.size(), joined(layoutNames).c_str(), joined(backendNames).c_str(), s.width,
        s.height, o.warmup, o.repeats, machine["cpu_model"].get<std::string>().c_str(),
        omp_get_max_threads(), deviceName.empty() ? "" : (", GPU " + deviceName).c_str());
    const SweepResult result = runSweep(s, machine, config, dir);
    if (!o.baseline.empty()) return finishBaseline(o, baseline, result, machine, runOptions);
    const int failed = result.failed;
    if (failed > 0)
        throw CommandVerdict(
            kExitFail,
            std::to_string(failed) + " benchmark cases failed (status \"error\" in the results)");
}

}  // namespace

void registerBench(CLI::App& app) {
    auto o = std::make_shared<BenchOptions>();
    CLI::App* cmd = app.add_subcommand(
        "bench",
        "Sweep grid clouds and meshes over layouts and backends; write bench.csv and bench.json "
        "(with --rays: one ray file through every layout and Embree; rays-bench.json, .csv)");
    cmd->add_flag("--quick", o->quick,
                  "Small smoke sweep (clouds 1k,2k,4k; cornell_box, teapot; 128x128; 2 repeats)");
    cmd->add_option("--out", o->out,
                    "Folder for bench.csv and bench.json (with --rays: rays-bench.json and "
                    "rays-bench.csv)")
        ->capture_default_str();
    addTraceOptions(*cmd, o->trace,
                    "Comma list of backends: " + backendNames() +
                        " (default: cpu,embree, plus cuda when a device answers)");
    cmd->add_option("--clouds", o->clouds,
                    "Grid cloud sizes, comma list (1000, 64k, 1M), or none (default adds 4M,16M "
                    "with a GPU)")
        ->capture_default_str();
    cmd->add_option("--meshes", o->meshes,
                    "Comma list of mesh files, or none (default: the committed meshes, the bunny "
                    "and the dragons found under --meshes-dir)");
    cmd->add_option("--meshes-dir", o->meshesDir,
                    "Where the default meshes are (default: ./meshes, else the meshes/ folder "
                    "above the octrace binary)");
    cmd->add_option("--size", o->size, "Image size WxH")->capture_default_str();
    cmd->add_option("--repeats,--rounds", o->repeats,
                    "Timed frames per case (median, min, max); with --rays, timed rounds")
        ->capture_default_str()
        ->check(numberIn(1, 1000));
    cmd->add_option("--warmup", o->warmup,
                    "Untimed frames before the timed ones; with --rays, untimed rounds")
        ->capture_default_str()
        ->check(numberIn(0, 1000));
    cmd->add_option("--max-seconds", o->maxSeconds,
                    "Seconds per case: fewer frames when warm-up + repeats would take longer, "
                    "skipped when one frame would; 1e-9 to 1e6")
        ->capture_default_str()
        ->check(numberIn(kMinCaseSeconds, kMaxCaseSeconds));
    cmd->add_option("--seed", o->seed, "Grid cloud seed")
        ->capture_default_str()
        ->check(finiteNumber());
    cmd->add_option("--max-depth", o->meshMaxDepth, "Mesh octrees: deepest level")
        ->capture_default_str()
        ->check(numberIn(0, kMaxOctreeDepth));
    cmd->add_option("--max-prims", o->meshMaxPrims, "Mesh octrees: split above this many")
        ->capture_default_str()
        ->check(numberIn(1, 1u << 30));
    cmd->add_option("--cloud-max-prims", o->cloudMaxPrims,
                    "Grid cloud octrees (split down to the grid depth): split above this many")
        ->capture_default_str()
        ->check(numberIn(1, 1u << 30));
    addLayoutLimitOptions(*cmd, o->limits, "skipped");
    cmd->add_flag("!--no-progress", o->progress, "No progress lines on stderr");
    CLI::Option* baseline = cmd->add_option(
        "--baseline", o->baseline,
        "Compare each case's time (a ratio to Embree's frame, in pairs: --paired-reference) and "
        "nodes and prims per pixel with FILE; its options are the defaults (bench/README.md)");
    cmd->add_flag("--update", o->update,
                  "With --baseline: rewrite FILE from this run (a new FILE: bench's options, one "
                  "thread)")
        ->needs(baseline);
    cmd->add_option("--max-slowdown", o->maxSlowdown,
                    "With --baseline: a case fails when its ratio to Embree grew by more than "
                    "this factor (the default is twice the largest run-to-run change measured, "
                    "bench/README.md); 1 to 1e9")
        ->capture_default_str()
        ->check(numberIn(1.0, 1e9))
        ->needs(baseline);
    cmd->add_flag("--paired-reference", o->pairedReference,
                  "Trace each timed frame of our layouts next to one of Embree's, on the process's "
                  "CPU clock; ratio_to_embree is the median of the pairs' ratios (with --threads "
                  "1 it survives a loaded machine)");
    // The ray bench: the user's rays on one scene instead of the sweep's frames, so the sweep's
    // scenes, frame size, time budget and baseline do not apply and are refused beside --rays.
    CLI::Option* rays =
        cmd->add_option("--rays", o->rays,
                        "Ray bench instead of the sweep: trace this float32 (N, 8) .npy (as "
                        "octrace trace reads) on --scene through every layout of --accel (default: "
                        "those with an octree) and each backend (default: cpu, Embree robust and "
                        "fast) in interleaved rounds; writes rays-bench.json and rays-bench.csv");
    CLI::Option* scene =
        cmd->add_option("--scene", o->scene, "With --rays: the scene file the rays are traced on");
    rays->needs(scene);
    scene->needs(rays);
    for (const char* sweepOnly :
         {"--quick", "--clouds", "--meshes", "--meshes-dir", "--size", "--max-seconds", "--seed",
          "--cloud-max-prims", "--baseline", "--update", "--max-slowdown", "--paired-reference"})
        rays->excludes(cmd->get_option(sweepOnly));
    cmd->callback([o, cmd] { runBench(*o, cmd); });
}

}  // namespace oct
