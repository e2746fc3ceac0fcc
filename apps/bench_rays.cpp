// octrace bench --rays R.npy --scene MESH: one ray file through every layout and through Embree
// (robust and fast), timed in interleaved rounds (bench/sweep/ray_bench.h does the work). This
// file picks the cases, reads the rays and the scene, prints the table and records the
// configuration, with the command that repeats the run.
#include <omp.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>

#include "apps/bench.h"
#include "apps/cli.h"
#include "bench/sweep/machine.h"
#include "bench/sweep/ray_bench.h"
#include "core/io/ray_file.h"
#include "core/scene/load_scene.h"
#include "core/system/resources.h"
#include "core/time_spread.h"

namespace oct {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

// Without --accel, every layout that walks an octree: exhaustive tracing tests every primitive
// for every ray (minutes for a million rays on the bunny), so it is asked for by name.
std::vector<const LayoutDesc*> defaultLayouts() {
    std::vector<const LayoutDesc*> out;
    for (const LayoutDesc& l : layouts())
        if (l.usesOctree) out.push_back(&l);
    return out;
}

// Without --backend: the host kernel, every backend with its own structure (Embree, robust and
// fast, and the scalar binary BVH: the peers the figures are compared with), and an
// accelerator when one answers.
std::vector<const BackendDesc*> defaultBackends(std::vector<std::string>& notes) {
    std::vector<const BackendDesc*> out = {&hostBackend()};
    for (const BackendDesc& b : backends()) {
        if (&b == &hostBackend() || (b.usesLayouts && !b.device)) continue;
        std::string why;
        if (b.available(why))
            out.push_back(&b);
        else
            notes.push_back(std::string(b.name) + " left out: " + why);
    }
    return out;
}

// Without --backend, a point cloud's cases leave out the backends that hold triangles only
// (BackendDesc::trianglesOnly), each named in `notes`: they would refuse the scene.
void dropTriangleOnlyBackends(const Scene& scene, std::vector<const BackendDesc*>& list,
                              std::vector<std::string>& notes) {
    if (scene.kind == PrimKind::Triangles) return;
    std::vector<const BackendDesc*> kept;
    for (const BackendDesc* b : list) {
        if (b->trianglesOnly)
            notes.push_back(std::string(b->name) + " left out: it traces triangle meshes only");
        else
            kept.push_back(b);
    }
    list = kept;
}

std::string shellWord(const std::string& s) {
    if (!s.empty() && s.find_first_of(" \t\n'\"\\$`;&|<>()*?[]#~") == std::string::npos) return s;
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// The command as typed (from /proc/self/cmdline), or "" where that cannot be read.
std::string typedCommandLine() {
    std::ifstream in("/proc/self/cmdline", std::ios::binary);
    std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::string line, word;
    for (char c : all) {
        if (c != '\0') {
            word += c;
            continue;
        }
        line += (line.empty() ? "" : " ") + shellWord(word);
        word.clear();
    }
    return line;
}

std::string namesOf(const std::vector<const LayoutDesc*>& ls) {
    std::string s;
    for (const LayoutDesc* l : ls) s += (s.empty() ? "" : ",") + std::string(l->name);
    return s;
}

std::string namesOf(const std::vector<const BackendDesc*>& bs) {
    std::string s;
    for (const BackendDesc* b : bs) s += (s.empty() ? "" : ",") + std::string(b->name);
    return s;
}

// The command that repeats this run with every choice written out (the defaults of a later
// octrace may differ): what docs quote beside a table.
std::string repeatCommand(const BenchOptions& o, const CLI::App& cmd, const RayBenchOptions& ro) {
    std::string c = "octrace bench --rays " + shellWord(o.rays) + " --scene " + shellWord(o.scene) +
                    " --accel " + namesOf(ro.layouts) + " --backend " + namesOf(ro.backends) +
                    " --repeats " + std::to_string(ro.repeats) + " --warmup " +
                    std::to_string(ro.warmup) + " --threads " +
                    std::to_string(omp_get_max_threads());
    if (cmd.count("--max-depth")) c += " --max-depth " + std::to_string(o.meshMaxDepth);
    if (cmd.count("--max-prims")) c += " --max-prims " + std::to_string(o.meshMaxPrims);
    for (const char* limit : {"--hash-slots", "--linear-budget", "--hash-budget", "--node-budget"})
        if (cmd.count(limit)) c += std::string(" ") + limit + " " + cmd[limit]->as<std::string>();
    return c + " --out " + shellWord(o.out);
}

json configJson(const BenchOptions& o, const CLI::App& cmd, const RayBenchOptions& ro) {
    json layoutNames = json::array(), backendNames = json::array();
    for (const LayoutDesc* l : ro.layouts) layoutNames.push_back(l->name);
    for (const BackendDesc* b : ro.backends) backendNames.push_back(b->name);
    return {{"command", repeatCommand(o, cmd, ro)},
            {"command_line", typedCommandLine()},
            {"rays_file", o.rays},
            {"scene", o.scene},
            {"layouts", layoutNames},
            {"backends", backendNames},
            {"warmup", ro.warmup},
            {"repeats", ro.repeats},
            {"threads", omp_get_max_threads()},
            {"max_depth", o.meshMaxDepth},
            {"max_prims", o.meshMaxPrims},
            {"hash_slots", o.limits.hashSlots},
            {"linear_budget_bytes", o.limits.linearBudgetBytes()},
            {"hash_budget_bytes", o.limits.hashParams().budgetBytes},
            {"node_budget", o.limits.nodeBudget}};
}

size_t caseCount(const RayBenchOptions& ro) {
    size_t ours = 0, own = 0;
    for (const BackendDesc* b : ro.backends) (b->usesLayouts ? ours : own) += 1;
    return ours * ro.layouts.size() + own;
}

}  // namespace

void runRayBenchCommand(const BenchOptions& o, const CLI::App& cmd) {
    // Every choice is checked before the rays are read: a typo costs no minute of loading.
    RayBenchOptions ro;
    ro.layouts = cmd.count("--accel") ? parseLayoutList(o.trace.accel) : defaultLayouts();
    std::vector<std::string> notes;
    ro.backends =
        cmd.count("--backend") ? parseBackendList(o.trace.backend, notes) : defaultBackends(notes);
    std::string deviceName;
    for (const BackendDesc* b : ro.backends)
        if (b->device) b->available(deviceName);
    ro.warmup = o.warmup;
    ro.repeats = o.repeats;
    ro.progress = o.progress;
    ro.layout.build.maxDepth = o.meshMaxDepth;
    ro.layout.build.maxPrims = o.meshMaxPrims;
    ro.layout.build.maxNodes = o.limits.nodeBudget;
    ro.layout.hash = o.limits.hashParams();
    ro.layout.linearBudget = o.limits.linearBudgetBytes();

    const fs::path dir = o.out;
    const std::string jsonOut = (dir / "rays-bench.json").string();
    const std::string csvOut = (dir / "rays-bench.csv").string();
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (!fs::is_directory(dir))
        throw std::runtime_error("--out '" + o.out + "': cannot create the folder" +
                                 (ec ? " (" + ec.message() + ")" : ""));
    checkOutputPaths({jsonOut, csvOut}, {o.rays, o.scene});
    checkWritable(jsonOut);
    setCpuThreadsFromOption(o.trace.threads);

    RayBenchResult r;
    auto t0 = std::chrono::steady_clock::now();
    HugeArray<float> rays;
    try {
        r.rays = readRayFileInto(o.rays, [&](uint64_t rows) {
            // The rows, then a t and a prim per row for every case.
            checkRayFileMemory("bench", o.rays, rows,
                               8 * sizeof(float) + caseCount(ro) * (sizeof(float) + 4));
            // Filled by the reader, so not zeroed; on huge pages as trace's: 4 KiB pages made
            // the read of 4M rows 0.5-0.6 s on this project's virtual machines, against trace's
            // 0.03 s.
            rays = makeHugeArray<float>(rows * 8);
            return rays.get();
        });
    } catch (const IoError& e) {
        throw IoError(std::string("--rays: ") + e.what());
    }
    if (r.rays == 0)
        throw IoError("--rays: '" + o.rays +
                      "' holds no rays, so there is nothing to time; give a file with rows "
                      "(octrace rays SCENE --out R.npy writes one)");
    r.readSeconds = secondsSince(t0);
    t0 = std::chrono::steady_clock::now();
    Scene scene;
    try {
        scene = loadScene(o.scene);
    } catch (const SceneError& e) {
        throw SceneError(std::string("--scene: ") + e.what());
    }
    r.loadSeconds = secondsSince(t0);
    if (!cmd.count("--backend")) dropTriangleOnlyBackends(scene, ro.backends, notes);
    const json config = configJson(o, cmd, ro);

    json machine = machineJson(deviceName);
    for (const std::string& n : notes) std::fprintf(stderr, "bench: %s\n", n.c_str());
    std::printf(
        "octrace bench --rays: %llu rays of %s on %s (%u %s), %zu cases, %d warm-up + %d timed "
        "rounds interleaved, %d OpenMP threads, on %s\n",
        (unsigned long long)r.rays, o.rays.c_str(), o.scene.c_str(), scene.primitiveCount(),
        primKindName(scene.kind), caseCount(ro), ro.warmup, ro.repeats, omp_get_max_threads(),
        machine["cpu_model"].get<std::string>().c_str());
    std::fflush(stdout);  // before the rounds' progress on stderr
    runRayBench(scene, rays.get(), ro, r);
    machine["load_average_end"] = loadAverage();
    writeRayBench(dir, r, machine, config);

    std::printf("%s", rayBenchTable(r).c_str());
    std::printf(
        "trace s: median of the timed rounds; x: that over the named backend's median; outside s: "
        "read rays %.3f + load scene %.3f + build + upload; other p / t: rays whose primitive / "
        "only whose t differs from %s/%s's\n",
        r.readSeconds, r.loadSeconds, r.cases[r.compared].structure().c_str(),
        r.cases[r.compared].backend->name);
    std::printf("repeat  %s\n", config["command"].get<std::string>().c_str());
    std::printf("wrote   %s %s\n", jsonOut.c_str(), csvOut.c_str());

    const std::vector<const RayBenchCase*> bad = disagreeingCases(r);
    if (!bad.empty()) {
        std::string names;
        for (const RayBenchCase* c : bad)
            names += (names.empty() ? "" : ", ") + c->structure() + "/" + c->backend->name;
        throw CommandVerdict(
            kExitFail, std::to_string(bad.size()) + " cases disagree on hits with " +
                           r.cases[r.compared].structure() + "/" +
                           r.cases[r.compared].backend->name + ", which must agree exactly (" +
                           names + "; the counts are in the table and " + jsonOut + ")");
    }
}

}  // namespace oct
