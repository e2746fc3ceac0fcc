#include "bench/sweep/sweep.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <new>
#include <optional>

#include "bench/sweep/machine.h"
#include "bench/sweep/progress.h"
#include "bench/sweep/results.h"
#include "bench/sweep/time_guard.h"
#include "core/scene/grid_cloud.h"
#include "core/scene/load_scene.h"
#include "core/time_spread.h"

namespace oct {

std::string SceneSpec::label() const {
    return cloud ? "grid:" + std::to_string(n) : std::filesystem::path(path).filename().string();
}

namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

// Runs f; a failure becomes the row's status instead of ending the sweep.
template <class F>
void protect(Row& r, F&& f) {
    try {
        f();
    } catch (const std::bad_alloc&) {
        r.status = "skipped";
        r.reason = "out of memory";
    } catch (const std::exception& e) {
        r.status = "error";
        r.reason = e.what();
    }
}

// Our frames and the reference's traced alternately (SweepOptions::pairedReference): pair i
// traces the reference first when i is even and ours first when it is odd (ABBA), so a load that
// rises or falls across the pairs tilts neither side. One warm-up frame of the reference first:
// our warm-up frames have just evicted its BVH from the caches.
struct PairedFrames {
    std::vector<double> ours, reference;  // each frame's own time (wall clock, CUDA events)
    std::vector<double> ratios;           // ours / the reference's, a pair each
};

// The process's CPU time. A frame's wall time on a shared machine includes the time the process
// waited for a core, which other people's work sets; its CPU time is the work (one thread) the
// frame needed. Measured on this project's 2-core machine at load 6 to 7, one thread: paired
// wall-clock ratios moved by up to 2.3x between runs, paired CPU-time ratios by up to 1.14x
// (bench/README.md, "Performance baselines").
double processCpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// One frame; returns {its own time, the process CPU time of the call}. The call's CPU time also
// holds sizing the Film (20 bytes a pixel), the same for both tracers of a pair.
std::pair<double, double> timedFrame(SceneTracer& t, const FrameParams& frame, Film& film) {
    const double c0 = processCpuSeconds();
    const double own = t.render(frame, film)[0];
    return {own, processCpuSeconds() - c0};
}

// cpuClock: the ratios from the process's CPU time (a host backend of ours); else from each
// frame's own time (a device backend: its kernel time by events against Embree's wall time).
PairedFrames pairedFrames(SceneTracer& ours, SceneTracer& reference, const FrameParams& frame,
                          Film& film, int warmup, int repeats, bool cpuClock) {
    PairedFrames p;
    Film referenceFilm;
    if (warmup > 0) ours.render(frame, film, warmup - 1, 1);
    reference.render(frame, referenceFilm, 0, 1);
    for (int i = 0; i < repeats; ++i) {
        std::pair<double, double> o, r;
        if (i % 2 == 0) {
            r = timedFrame(reference, frame, referenceFilm);
            o = timedFrame(ours, frame, film);
        } else {
            o = timedFrame(ours, frame, film);
            r = timedFrame(reference, frame, referenceFilm);
        }
        p.ours.push_back(o.first);
        p.reference.push_back(r.first);
        const double a = cpuClock ? o.second : o.first, b = cpuClock ? r.second : r.first;
        p.ratios.push_back(b > 0 ? a / b : INFINITY);
    }
    return p;
}

class Sweep {
public:
    Sweep(const SweepOptions& o, json machine, const json& config)
        : o_(o),
          machine_(std::move(machine)),
          config_(config),
          progress_(caseCount(o), o.progress) {
        cam_.width = o.width;
        cam_.height = o.height;
        for (const BackendDesc* b : o.backends) (b->usesLayouts ? ours_ : references_).push_back(b);
    }

    SweepResult run(const fs::path& dir) {
        printHeader();
        for (const SceneSpec& spec : o_.scenes) runScene(spec, dir);
        progress_.clear();
        machine_["load_average_end"] = loadAverage();
        writeResults(dir, machine_, config_, rows_, true);
        int ok = 0, skipped = 0, failed = 0;
        for (const Row& r : rows_) {
            ok += r.status == "ok";
            skipped += r.status == "skipped";
            failed += r.status == "error";
        }
        std::printf("%d cases: %d ok, %d skipped, %d failed, in %.1f s; wrote %s and %s\n",
                    int(rows_.size()), ok, skipped, failed, progress_.elapsed(),
                    (dir / "bench.csv").string().c_str(), (dir / "bench.json").string().c_str());
        return {rows_, failed};
    }

private:
    static size_t caseCount(const SweepOptions& o) {
        size_t ours = 0, refs = 0;
        for (const BackendDesc* b : o.backends) (b->usesLayouts ? ours : refs)++;
        return o.scenes.size() * (refs + o.layouts.size() * ours);
    }

    void printHeader() {
        std::printf("%-22s %9s %-10s %-6s %8s %10s %8s %8s %11s %8s %9s  %s\n", "scene", "prims",
                    "layout", "back", "build_s", "frame_ms", "Mrays/s", "x_embree", "bytes",
                    "boxes/px", "prims/px", "status");
        std::fflush(stdout);
    }

    void printRow(const Row& r) {
        progress_.clear();
        auto num = [](const std::optional<double>& v, const char* f) {
            return v ? fmt(f, *v) : std::string("-");
        };
        std::string status = r.status + (r.reason.empty() ? "" : ": " + r.reason);
        std::printf("%-22s %9llu %-10s %-6s %8s %10s %8s %8s %11s %8s %9s  %s\n",
                    r.scene.substr(0, 22).c_str(), (unsigned long long)r.primitives,
                    r.layout.c_str(), r.backend.c_str(), num(r.buildSeconds, "%.3f").c_str(),
                    r.frameMedian ? fmt("%.2f", *r.frameMedian * 1e3).c_str() : "-",
                    num(r.mraysPerSecond, "%.2f").c_str(), num(r.ratioToEmbree, "%.2f").c_str(),
                    r.layoutBytes ? std::to_string(*r.layoutBytes).c_str() : "-",
                    num(r.nodesPerPixel, "%.1f").c_str(), num(r.primsPerPixel, "%.1f").c_str(),
                    status.c_str());
        std::fflush(stdout);
    }

    void add(Row r, const fs::path& dir) {
        printRow(r);
        rows_.push_back(std::move(r));
        writeResults(dir, machine_, config_, rows_, false);
    }

    Row baseRow(const SceneSpec& spec, const Scene* scene, double loadSeconds) {
        Row r;
        r.sceneType = spec.cloud ? "cloud" : "mesh";
        r.scene = spec.cloud ? "grid:" + std::to_string(spec.n) + ":" + std::to_string(o_.seed)
                             : fs::path(spec.path).filename().string();
        r.path = spec.cloud ? "" : spec.path;
        r.n = spec.n;
        r.loadSeconds = loadSeconds;
        if (scene) {
            r.primitives = scene->primitiveCount();
            r.n = spec.cloud ? spec.n : scene->primitiveCount();
            r.vertices = scene->report.verticesRead;
            r.faces = scene->report.facesRead;
            r.gridDepth = scene->gridDepth;
        }
        r.width = cam_.width;
        r.height = cam_.height;
        r.warmup = o_.warmup;
        r.repeats = o_.repeats;
        return r;
    }

    static std::string guardKey(const Scene& s, const Row& r) {
        return std::string(s.kind == PrimKind::Triangles ? "tri" : "sph") + "/" + r.layout + "/" +
               r.backend;
    }

    // The time guard. A case runs as asked when its estimated time for warm-up + repeats is
    // within maxSeconds; when only fewer frames fit, it runs with fewer (repeats first, then
    // warm-up, down to one timed frame; the row records the counts and why); when not even one
    // frame fits, it is skipped. The estimate comes from the history (a smaller measured case,
    // scaled); when that is missing or over the limit, probe frames decide: the same camera at
    // 1/16, then 1/4, then the full width and height. A small probe is dominated by fixed costs
    // (starting the parallel loop on a busy machine), which inflates its extrapolation, so an
    // estimate over the limit only counts once the probe itself took 0.2 s or was full size.
    // Returns false when the case is skipped (reason filled in).
    bool planFrames(const std::string& key, bool linearInN, const Scene& scene, SceneTracer& tracer,
                    Row& r) {
        const int frames = o_.warmup + o_.repeats;
        const double asked = o_.maxSeconds / frames;  // per frame, for the frames asked
        const double pixels = double(cam_.width) * cam_.height;
        r.warmup = o_.warmup;
        r.repeats = o_.repeats;
        std::optional<Estimate> history =
            guard_.estimate(key, linearInN, scene.primitiveCount(), pixels);
        if (history && history->frameSeconds <= asked) return true;
        double estimate = 0.0;
        std::string how;
        for (int shrink = 16;; shrink /= 4) {
            CameraOptions small = cam_;
            small.width = std::max(1, (cam_.width + shrink - 1) / shrink);
            small.height = std::max(1, (cam_.height + shrink - 1) / shrink);
            Film probe;
            double seconds = tracer.render(makeFrame(scene.bounds(), small), probe, 0, 1)[0];
            estimate = seconds * pixels / (double(small.width) * small.height);
            if (estimate <= asked) return true;
            if (shrink == 1 || seconds >= 0.2) {
                how = "from a " + std::to_string(small.width) + "x" + std::to_string(small.height) +
                      " probe frame" + (history ? "; " + history->how : "");
                break;
            }
        }
        int fit = int(std::floor(o_.maxSeconds / estimate));
        if (fit < 1) {
            r.status = "skipped";
            r.warmup = r.repeats = 0;
            r.reason = "estimated " + fmt("%.0f", estimate) + " s per frame > --max-seconds " +
                       fmt("%g", o_.maxSeconds) + " (" + how + ")";
            return false;
        }
        r.repeats = std::min(o_.repeats, fit);
        r.warmup = std::min(o_.warmup, fit - r.repeats);
        r.reason = "frames reduced to " + std::to_string(r.warmup) + " warm-up + " +
                   std::to_string(r.repeats) + " timed: estimated " + fmt("%.1f", estimate) +
                   " s per frame, --max-seconds " + fmt("%g", o_.maxSeconds) + " (" + how + ")";
        return true;
    }

    // One case: prepare the backend, plan the frames, render them, fill the row.
    void runCase(const Scene& scene, const FrameParams& frame, const BuiltScene& built,
                 const BackendDesc& backend, bool linearInN, Row& r) {
        std::unique_ptr<SceneTracer> tracer = backend.prepare(built);
        if (backend.usesLayouts) {
            if (tracer->prepareSeconds() > 0) r.uploadSeconds = tracer->prepareSeconds();
        } else {
            r.buildSeconds = tracer->prepareSeconds();  // the backend's own structure
        }
        const std::string key = guardKey(scene, r);
        if (!planFrames(key, linearInN, scene, *tracer, r)) return;
        Film film;
        std::vector<double> frames;
        if (backend.usesLayouts && pairReference_) {
            PairedFrames p = pairedFrames(*tracer, *pairReference_, frame, film, r.warmup,
                                          r.repeats, !backend.device);
            frames = p.ours;
            r.ratioToEmbree = timeSpread(p.ratios).median;
        } else {
            frames = tracer->render(frame, film, r.warmup, r.repeats);
        }
        fillFilmCounts(film, backend.usesLayouts, r);
        fillTiming(frames, r);
        guard_.record(key, {double(scene.primitiveCount()), double(frame.width) * frame.height,
                            *r.frameMedian, r.scene});
        // The scene's first reference that ran is the one our frames pair with.
        if (!backend.usesLayouts && o_.pairedReference && !pairReference_)
            pairReference_ = std::move(tracer);
    }

    void runScene(const SceneSpec& spec, const fs::path& dir) {
        const size_t casesHere = references_.size() + o_.layouts.size() * ours_.size();
        progress_.step(spec.label() + ": loading");
        Scene scene;
        auto t0 = std::chrono::steady_clock::now();
        try {
            scene = spec.cloud ? makeGridCloud(spec.n, o_.seed) : loadScene(spec.path);
        } catch (const std::exception& e) {
            // One error row per scene: nothing else can run on it.
            Row r = baseRow(spec, nullptr, 0.0);
            r.layout = "-";
            r.backend = "-";
            r.status = "error";
            r.reason = std::string("loading: ") + e.what();
            add(std::move(r), dir);
            for (size_t i = 0; i < casesHere; ++i) progress_.end();
            return;
        }
        const double loadSeconds = secondsSince(t0);
        const FrameParams frame = makeFrame(scene.bounds(), cam_);

        // Backends with their own structure: the reference rows, and the reference frame time
        // (the first such backend's) for every other row's ratio.
        std::optional<double> referenceFrame;
        const BuiltScene bare = bareScene(scene);
        pairReference_.reset();
        for (const BackendDesc* b : references_) {
            progress_.begin(spec.label() + " " + b->name);
            Row r = baseRow(spec, &scene, loadSeconds);
            r.layout = b->structure;
            r.backend = b->name;
            protect(r, [&] { runCase(scene, frame, bare, *b, false, r); });
            if (r.status == "ok" && !referenceFrame) referenceFrame = r.frameMedian;
            add(std::move(r), dir);
            progress_.end();
        }

        // The canonical octree is built once per scene and shared by every layout converted
        // from it (each row's build_s is this build plus its own conversion).
        std::shared_ptr<const Octree> tree;
        std::string treeSkip, treeError;
        for (const LayoutDesc* layout : o_.layouts) {
            if (layout->usesOctree && !tree && treeSkip.empty() && treeError.empty() &&
                !ours_.empty()) {
                progress_.step(spec.label() + ": building the octree");
                // A limit (OctreeError: too many references, a depth out of range; memory)
                // makes the octree rows "skipped"; anything else is an "error".
                try {
                    tree = buildSharedOctree(scene, buildParams(scene));
                } catch (const OctreeError& e) {
                    treeSkip = e.what();
                } catch (const std::bad_alloc&) {
                    treeSkip = "out of memory building the octree";
                } catch (const std::exception& e) {
                    treeError = e.what();
                }
            }
            runLayout(spec, scene, loadSeconds, frame, *layout, tree, treeSkip, treeError,
                      referenceFrame, dir);
        }
        pairReference_.reset();  // it traces `bare`, which ends here
    }

    BuildParams buildParams(const Scene& scene) const {
        BuildParams p = o_.meshBuild;
        if (scene.gridDepth >= 0) {
            // One sphere per deepest cell: split down to the grid depth (the builder clamps
            // maxDepth to scene.gridDepth), leaves with at most cloudMaxPrims spheres.
            p.maxDepth = kMaxOctreeDepth;
            p.maxPrims = o_.cloudMaxPrims;
        }
        return p;
    }

    void runLayout(const SceneSpec& spec, const Scene& scene, double loadSeconds,
                   const FrameParams& frame, const LayoutDesc& layout,
                   const std::shared_ptr<const Octree>& tree, const std::string& treeSkip,
                   const std::string& treeError, std::optional<double> referenceFrame,
                   const fs::path& dir) {
        Row base = baseRow(spec, &scene, loadSeconds);
        base.layout = layout.name;

        BuiltScene built;
        std::string skip = layout.usesOctree ? treeSkip : "";
        std::string error = layout.usesOctree ? treeError : "";
        if (skip.empty() && error.empty()) {
            if (layout.usesOctree) {
                base.treeSeconds = tree->buildSeconds;
                base.octreeNodes = tree->nodes.size();
                base.octreeDepth = tree->depth;
                base.octreeFaces = tree->referenceCount();
                progress_.step(spec.label() + ": converting to " + layout.name);
            }
            try {
                built = convertLayout(scene, tree, layout, o_.limits);
                if (layout.usesOctree) {
                    base.convertSeconds = built.convertSeconds;
                    base.buildSeconds = *base.treeSeconds + *base.convertSeconds;
                } else {
                    base.buildSeconds = 0.0;
                }
            } catch (const OctreeError& e) {
                skip = e.what();  // the layout's memory budget
            } catch (const std::bad_alloc&) {
                skip = std::string("out of memory allocating the ") + layout.name + " layout";
            } catch (const std::exception& e) {
                error = std::string("converting to ") + layout.name + ": " + e.what();
            }
        }
        if (!skip.empty() || !error.empty()) {
            for (const BackendDesc* b : ours_) {
                progress_.begin(spec.label() + " " + layout.name + " " + b->name);
                Row r = base;
                r.backend = b->name;
                r.status = error.empty() ? "skipped" : "error";
                r.reason = error.empty() ? skip : error;
                r.warmup = r.repeats = 0;
                add(std::move(r), dir);
                progress_.end();
            }
            return;
        }
        base.layoutBytes = built.layoutBytes();

        for (const BackendDesc* b : ours_) {
            progress_.begin(spec.label() + " " + layout.name + " " + b->name);
            Row r = base;
            r.backend = b->name;
            // A layout without a structure tests every primitive: time grows as N.
            protect(r, [&] { runCase(scene, frame, built, *b, !layout.usesOctree, r); });
            if (r.status == "ok" && !r.ratioToEmbree && referenceFrame && *referenceFrame > 0)
                r.ratioToEmbree = *r.frameMedian / *referenceFrame;
            add(std::move(r), dir);
            progress_.end();
        }
    }

    const SweepOptions& o_;
    std::vector<const BackendDesc*> ours_;        // backends that trace our layouts
    std::vector<const BackendDesc*> references_;  // backends with their own structure
    json machine_, config_;
    CameraOptions cam_;
    // The scene's reference tracer, kept for pairedFrames (only with pairedReference).
    std::unique_ptr<SceneTracer> pairReference_;
    TimeGuard guard_;
    Progress progress_;
    std::vector<Row> rows_;
};

}  // namespace

SweepResult runSweep(const SweepOptions& options, json machine, const json& config,
                     const fs::path& dir) {
    Sweep sweep(options, std::move(machine), config);
    return sweep.run(dir);
}

}  // namespace oct
