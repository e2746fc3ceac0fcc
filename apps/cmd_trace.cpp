// octrace trace: closest hits for a user's own ray set, the certification entry point.
// Input  R.npy: float32 (N, 8) = ox oy oz dx dy dz tmin tmax (see docs/TRACE_FORMAT.md).
// Output PREFIX.t.npy float32 (N,), +inf on a miss; PREFIX.prim.npy int32 (N,), -1 on a miss;
//        PREFIX.run.json, the record that the two are one run's pair (validation/rays/hit_files.h).
// While it runs it holds PREFIX.lock (core/io/output_file.h, OutputLock): a second run into the
// same prefix is refused instead of mixing its pair with this one's.
// Across MPI ranks (dist/ranks.h) each rank reads and traces its own rows of the file and rank 0
// gathers the hits and writes the same three files, byte for byte, as one process.
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>

#include "apps/cli.h"
#include "core/io/npy.h"
#include "core/io/ray_file.h"
#include "core/scene/load_scene.h"
#include "core/system/resources.h"
#include "dist/ranks.h"
#include "validation/rays/hit_files.h"

namespace oct {
namespace {

struct TraceOptions {
    SceneOptions scene;
    std::string rays, out;
    TraceChoice trace{kDefaultLayout, "auto"};
};

// Every row by trace's rule, across ranks: the ranks agree on the lowest bad row of the file,
// and only its rank throws (the others learn it at their next collective call), so the run
// names the row one process names. `rays` holds this rank's blocks, packed.
// `firstBad` is the first bad row of `rays` as read (readRayFileRowsInto), packed.
void checkRowsOfRanks(Ranks& ranks, const std::string& path, const float* rays,
                      const std::vector<RowRange>& blocks, uint64_t firstBad) {
    uint64_t packed = 0, lowest = UINT64_MAX;
    for (const RowRange& b : blocks) {
        if (firstBad < packed + b.count()) {
            lowest = b.begin + (firstBad - packed);
            packed = firstBad;
            break;
        }
        packed += b.count();
    }
    const uint64_t first = ranks.minOver(lowest);
    if (first == UINT64_MAX) return;
    if (first == lowest)
        throw IoError(badRayRowMessage("'" + path + "'", first, rays + 8 * packed));
    ranks.checkpoint();  // throws RankFailed: the row's rank failed
}

void runTrace(const TraceOptions& o) {
    const LayoutDesc& layout = parseOneLayout(o.trace.accel, "trace");
    std::string note;
    const BackendDesc& backend = parseOneBackend(o.trace.backend, "trace", note);
    const std::string tOut = hitTPath(o.out), primOut = hitPrimPath(o.out);
    const std::string runOut = hitRunPath(o.out);
    checkOutputPaths({tOut, primOut, runOut}, {o.scene.path, o.rays});
    Ranks& ranks = Ranks::world();
    std::optional<OutputLock> lock;  // until the three files are in place; rank 0 writes them
    if (ranks.root()) {
        checkWritable(tOut);
        lock.emplace(o.out);
    }
    ranks.checkpoint();  // an output rank 0 refuses stops every rank before the work
    setCpuThreadsFromOption(o.trace.threads);
    // Every buffer below is filled before it is read, so none is zeroed: the rays straight from
    // the file, the hits straight into the output files' data sections.
    using Clock = std::chrono::steady_clock;
    auto since = [](Clock::time_point t) {
        return std::chrono::duration<double>(Clock::now() - t).count();
    };
    Clock::time_point t0 = Clock::now();
    HugeArray<float> rays;
    std::vector<RowRange> blocks;  // this rank's rows (dist/ranks.h, RowDeal), read packed
    uint64_t mine = 0, firstBad = 0;
    const uint64_t n = readRayFileRowsInto(
        o.rays,
        [&](uint64_t rows) {
            blocks = ranks.blocksOf(rows);
            std::vector<RowSpan> spans;
            for (const RowRange& b : blocks) spans.push_back({b.begin, b.end});
            return spans;
        },
        [&](uint64_t rows) {
            // The rows, then a t and a prim per row in the output files (rank 0: every row's).
            checkRayFileMemory("trace", o.rays, rows, 8 * sizeof(float) + sizeof(float) + 4);
            rays = makeHugeArray<float>(rows * 8);  // not zeroed: the file fills it
            mine = rows;
            return rays.get();
        },
        &firstBad);
    checkRowsOfRanks(ranks, o.rays, rays.get(), blocks, firstBad);

    const double readSeconds = since(t0);
    t0 = Clock::now();
    Scene scene = loadScene(o.scene.path, o.scene.loadOptions());
    const double loadSeconds = since(t0);
    BuiltScene bs =
        backend.usesLayouts ? buildScene(scene, layout, o.scene.layoutOptions()) : bareScene(scene);
    // One process traces straight into the output files' data sections; across ranks each traces
    // its packed rows into its own arrays, which rank 0 then gathers into their places there.
    std::optional<NpyBuffer> tFile, primFile;
    std::vector<float> tMine;
    std::vector<int32_t> primMine;
    float *t = nullptr, *tTraced = nullptr;
    int32_t *prim = nullptr, *primTraced = nullptr;
    if (ranks.root()) {
        // Across ranks rank 0 holds every row's answer besides its own rows' (checked above).
        if (ranks.distributed()) checkRayFileMemory("trace", o.rays, n, sizeof(float) + 4);
        tFile.emplace("<f4", std::vector<uint64_t>{n}, 4);
        primFile.emplace("<i4", std::vector<uint64_t>{n}, 4);
        t = tTraced = static_cast<float*>(tFile->data());
        prim = primTraced = static_cast<int32_t*>(primFile->data());
    }
    if (ranks.distributed()) {
        tMine.resize(mine);
        primMine.resize(mine);
        tTraced = tMine.data();
        primTraced = primMine.data();
    }
    double seconds = traceWith(backend, bs, {rays.get(), tTraced, primTraced, mine});
    t0 = Clock::now();
    ranks.gatherRows(tTraced, t, n, sizeof(float));
    ranks.gatherRows(primTraced, prim, n, sizeof(int32_t));
    const double gatherSeconds = since(t0);
    // The largest rank's peak memory: no rank holds all rays (rank 0 holds every answer).
    struct rusage use {};
    getrusage(RUSAGE_SELF, &use);
    const double peakMiB = ranks.maxOver(double(use.ru_maxrss) / 1024.0);  // KiB on Linux
    const double fastest = -ranks.maxOver(-seconds);  // the balance of the deal (RowDeal)
    seconds = ranks.maxOver(seconds);                 // the slowest rank's
    const double outside[] = {ranks.maxOver(readSeconds), ranks.maxOver(loadSeconds),
                              ranks.maxOver(bs.treeSeconds), ranks.maxOver(bs.convertSeconds)};
    if (!ranks.root()) return;
    t0 = Clock::now();
    OutputSet out;  // the three files or none
    out.stage(tOut, tFile->bytes(), tFile->size());
    out.stage(primOut, primFile->bytes(), primFile->size());
    const std::string record = hitRunRecord(o.out, t, prim, n, out);
    out.stage(runOut, record.data(), record.size());
    out.commit();
    const double writeSeconds = since(t0);
    if (!note.empty()) std::printf("%s\n", note.c_str());
    uint64_t hits = 0;
    for (uint64_t i = 0; i < n; ++i) hits += prim[i] >= 0;
    std::printf("%llu rays, %llu hits, %s on %s, %.3f s (%.3f Mrays/s)\n", (unsigned long long)n,
                (unsigned long long)hits, tracedStructure(backend, layout), backend.name, seconds,
                seconds > 0 ? double(n) / seconds * 1e-6 : 0.0);
    // Where the time outside tracing goes. Not shown: process start, the output buffers, and the
    // backend's set-up before its trace clock starts (Embree's BVH build, the copies to a GPU).
    std::printf(
        "phases  read rays %.3f s, load scene %.3f s, octree %.3f s, layout %.3f s, trace %.3f "
        "s, write %.3f s\n",
        outside[0], outside[1], outside[2], outside[3], seconds, writeSeconds);
    if (ranks.distributed())
        std::printf(
            "ranks   %d, rows split by rank (the phases above are the slowest rank's), "
            "gather %.3f s; the fastest rank traced in %.3f s; the largest rank's peak memory "
            "%.0f MiB\n",
            ranks.size(), gatherSeconds, fastest, peakMiB);
    std::printf("wrote   %s %s %s\n", tOut.c_str(), primOut.c_str(), runOut.c_str());
}

}  // namespace

void registerTrace(CLI::App& app) {
    auto o = std::make_shared<TraceOptions>();
    CLI::App* cmd = app.add_subcommand("trace", "Closest hits of a ray set given as .npy");
    addSceneOptions(*cmd, o->scene);
    addTraceOptions(
        *cmd, o->trace,
        "Backend: " + backendNames() + ", or auto (cuda when a device answers, else cpu)");
    cmd->add_option("--rays", o->rays, "float32 (N, 8) .npy: ox oy oz dx dy dz tmin tmax")
        ->required();
    cmd->add_option("--out", o->out,
                    "Output prefix: PREFIX.t.npy, PREFIX.prim.npy and PREFIX.run.json")
        ->required();
    cmd->callback([o] { runTrace(*o); });
}

}  // namespace oct
