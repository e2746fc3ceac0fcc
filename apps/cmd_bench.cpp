// octrace bench: the paper's experiment (Barboza & Clua 2011, sec. 6) as a sweep. Generated grid
// clouds of growing N and real meshes, each traced with every requested layout (exhaustive,
// linear, hash) on every requested backend (cpu, cuda), and with Embree on the same rays as
// ground truth for speed. Per case: build time, frame time (median, min, max of repeats after
// warm-up), rays per second, layout bytes, octree faces, traversal cost per pixel.
//
// Results go to DIR/bench.csv and DIR/bench.json (rewritten after every case, so a long sweep
// that is stopped keeps what it measured). Cases that cannot or should not run (the linear
// octree over its memory budget, exhaustive tracing estimated past --max-seconds) are rows with
// status "skipped" and the reason, never a crash. bench/make_results.py turns the files into
// plots and docs/RESULTS.md.
#include <embree3/rtcore_config.h>
#include <omp.h>
#include <sys/utsname.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <new>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <thread>

#include "apps/backend.h"
#include "apps/cli.h"
#include "core/scene/grid_cloud.h"
#include "core/scene/load_scene.h"
#include "core/time_spread.h"
#include "cpu_ref/embree_tracer.h"
#include "cpu_ref/render_cpu.h"
#ifdef OCT_HAVE_CUDA
#include "gpu/cuda_backend.h"
#endif

namespace oct {
namespace {

namespace fs = std::filesystem;
// Ordered, so the CSV's columns and the JSON's keys keep the order written here.
using json = nlohmann::ordered_json;

// The paper's clouds (1k .. 64k points), then two sizes beyond; with CUDA, two more. The
// four small ones place the crossover, where the octree starts to beat exhaustive tracing
// (below 1k points with this traversal).
const char* kDefaultClouds = "10,30,100,300,1k,2k,4k,8k,16k,32k,64k,256k,1M";
#ifdef OCT_HAVE_CUDA
const char* kDefaultGpuExtraClouds = "4M,16M";
#endif
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

struct BenchOptions {
    bool quick = false;
    std::string out = "bench/results/latest";
    std::string backends = "cpu,embree";  // cuda is added when a device answers
    std::string accels = "exhaustive,linear,hash";
    std::string clouds = kDefaultClouds;
    std::string meshes;  // empty: the defaults found under meshesDir
    std::string meshesDir;
    std::string size = "512x512";
    int repeats = 5;
    int warmup = 1;
    double maxSeconds = 300.0;
    uint64_t seed = kGridCloudDefaultSeed;
    int threads = 0;
    int meshMaxDepth = BuildParams{}.maxDepth;
    uint32_t meshMaxPrims = BuildParams{}.maxPrims;
    uint32_t cloudMaxPrims = 1;
    LayoutLimitOptions limits;
    bool progress = true;
};

// --- small parsers ---------------------------------------------------------------------------

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

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

// --- the machine -----------------------------------------------------------------------------

std::string cpuModel() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("model name", 0) == 0 || line.rfind("Model", 0) == 0) {
            auto colon = line.find(':');
            if (colon != std::string::npos)
                return line.substr(line.find_first_not_of(" ", colon + 1));
        }
    }
    return "unknown";
}

uint64_t memoryBytes() {
    std::ifstream in("/proc/meminfo");
    std::string key;
    uint64_t kib = 0;
    while (in >> key >> kib) {
        if (key == "MemTotal:") return kib * 1024;
        in.ignore(1 << 10, '\n');
    }
    return 0;
}

// The 1, 5 and 15 minute load averages: other work on the machine skews timings, so the
// results record it at the start and the end of the sweep.
json loadAverage() {
    std::ifstream in("/proc/loadavg");
    double a = 0, b = 0, c = 0;
    if (!(in >> a >> b >> c)) return nullptr;
    return json::array({a, b, c});
}

std::string compilerName() {
#if defined(__clang__)
    return std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
    return std::string("gcc ") + __VERSION__;
#else
    return "unknown";
#endif
}

std::string utcNow() {
    std::time_t t = std::time(nullptr);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
    return buf;
}

json machineJson(const std::string& cudaDevice) {
    utsname u{};
    uname(&u);
#ifdef __OPTIMIZE__
    bool optimized = true;
#else
    bool optimized = false;
#endif
#ifdef NDEBUG
    bool ndebug = true;
#else
    bool ndebug = false;
#endif
#ifdef OCT_HAVE_CUDA
    bool cudaBuild = true;
#else
    bool cudaBuild = false;
#endif
    return {{"cpu_model", cpuModel()},
            {"logical_cores", std::thread::hardware_concurrency()},
            {"omp_threads", omp_get_max_threads()},
            {"memory_bytes", memoryBytes()},
            {"os", std::string(u.sysname) + " " + u.release + " " + u.machine},
            {"compiler", compilerName()},
            {"build", {{"optimized", optimized}, {"ndebug", ndebug}, {"cuda", cudaBuild}}},
            {"embree_version", RTC_VERSION_STRING},
            {"cuda_device", cudaDevice.empty() ? json(nullptr) : json(cudaDevice)},
            {"date_utc", utcNow()},
            {"load_average_start", loadAverage()},
            {"load_average_end", nullptr}};
}

// --- one case --------------------------------------------------------------------------------

struct Row {
    std::string sceneType;  // "cloud" or "mesh"
    std::string scene;      // grid:N:seed or the mesh's file name
    std::string path;       // mesh path (empty for clouds)
    uint64_t n = 0;         // requested points, or triangles
    uint64_t primitives = 0;
    uint64_t vertices = 0;
    uint64_t faces = 0;
    int gridDepth = -1;
    double loadSeconds = 0.0;
    std::string layout;   // exhaustive, linear, hash, embree-bvh
    std::string backend;  // cpu, embree, cuda
    std::string status = "ok";
    std::string reason;
    std::optional<double> treeSeconds, convertSeconds, buildSeconds;
    std::optional<double> frameMedian, frameMin, frameMax, mraysPerSecond, ratioToEmbree;
    std::optional<double> uploadSeconds;  // cuda
    std::optional<uint64_t> primaryRays, shadowRays, layoutBytes, octreeNodes, octreeFaces;
    std::optional<int> octreeDepth;
    std::optional<double> nodesPerPixel, primsPerPixel, nodesPerRay, primsPerRay;
    int width = 0, height = 0, warmup = 0, repeats = 0;
};

template <class T>
json optJson(const std::optional<T>& v) {
    return v ? json(*v) : json(nullptr);
}

json rowJson(const Row& r) {
    return {{"scene_type", r.sceneType},
            {"scene", r.scene},
            {"path", r.path},
            {"n", r.n},
            {"primitives", r.primitives},
            {"vertices", r.vertices},
            {"faces", r.faces},
            {"grid_depth", r.gridDepth < 0 ? json(nullptr) : json(r.gridDepth)},
            {"load_s", r.loadSeconds},
            {"layout", r.layout},
            {"backend", r.backend},
            {"status", r.status},
            {"reason", r.reason},
            {"tree_build_s", optJson(r.treeSeconds)},
            {"convert_s", optJson(r.convertSeconds)},
            {"build_s", optJson(r.buildSeconds)},
            {"frame_s_median", optJson(r.frameMedian)},
            {"frame_s_min", optJson(r.frameMin)},
            {"frame_s_max", optJson(r.frameMax)},
            {"upload_s", optJson(r.uploadSeconds)},
            {"mrays_per_s", optJson(r.mraysPerSecond)},
            {"ratio_to_embree", optJson(r.ratioToEmbree)},
            {"primary_rays", optJson(r.primaryRays)},
            {"shadow_rays", optJson(r.shadowRays)},
            {"layout_bytes", optJson(r.layoutBytes)},
            {"octree_nodes", optJson(r.octreeNodes)},
            {"octree_depth", optJson(r.octreeDepth)},
            {"octree_faces", optJson(r.octreeFaces)},
            {"nodes_per_pixel", optJson(r.nodesPerPixel)},
            {"prims_per_pixel", optJson(r.primsPerPixel)},
            {"nodes_per_ray", optJson(r.nodesPerRay)},
            {"prims_per_ray", optJson(r.primsPerRay)},
            {"width", r.width},
            {"height", r.height},
            {"warmup", r.warmup},
            {"repeats", r.repeats}};
}

// CSV: the JSON row's fields in the same order; null is an empty cell.
std::string csvCell(const json& v) {
    if (v.is_null()) return "";
    if (v.is_string()) {
        std::string s = v.get<std::string>();
        if (s.find_first_of(",\"\n") == std::string::npos) return s;
        std::string q = "\"";
        for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
        return q + "\"";
    }
    if (v.is_number_float()) return fmt("%.9g", v.get<double>());
    return v.dump();
}

void writeResults(const fs::path& dir, const json& machine, const json& config,
                  const std::vector<Row>& rows, bool complete) {
    json all = json::array();
    for (const Row& r : rows) all.push_back(rowJson(r));
    json doc = {{"format", "octrace-bench/1"},
                {"complete", complete},
                {"machine", machine},
                {"config", config},
                {"results", all}};
    // Write to a temporary name and rename, so a reader never sees half a file.
    auto writeAtomic = [&](const fs::path& p, const std::string& text) {
        fs::path tmp = p;
        tmp += ".tmp";
        {
            std::ofstream out(tmp, std::ios::binary);
            out << text;
            if (!out) throw std::runtime_error("bench: cannot write '" + tmp.string() + "'");
        }
        fs::rename(tmp, p);
    };
    writeAtomic(dir / "bench.json", doc.dump(2) + "\n");

    std::string csv;
    json header = rowJson(Row{});
    bool first = true;
    for (auto it = header.begin(); it != header.end(); ++it) {
        csv += (first ? "" : ",") + it.key();
        first = false;
    }
    csv += "\n";
    for (const json& r : all) {
        first = true;
        for (auto it = header.begin(); it != header.end(); ++it) {
            csv += (first ? "" : ",") + csvCell(r[it.key()]);
            first = false;
        }
        csv += "\n";
    }
    writeAtomic(dir / "bench.csv", csv);
}

void fillFilmCounts(const Film& film, bool withCost, Row& r) {
    uint64_t shadow = 0;
    double nodes = 0, tested = 0;
    for (size_t i = 0; i < film.pixelCount(); ++i) {
        shadow += film.shadow[i] != kNoShadowRay;
        nodes += film.nodes[i];
        tested += film.primsTested[i];
    }
    r.primaryRays = film.pixelCount();
    r.shadowRays = shadow;
    if (withCost) {
        double pixels = double(film.pixelCount());
        double rays = double(film.pixelCount() + shadow);
        r.nodesPerPixel = nodes / pixels;
        r.primsPerPixel = tested / pixels;
        r.nodesPerRay = nodes / rays;
        r.primsPerRay = tested / rays;
    }
}

void fillTiming(const std::vector<double>& frames, Row& r) {
    const TimeSpread s = timeSpread(frames);
    r.frameMedian = s.median;
    r.frameMin = s.min;
    r.frameMax = s.max;
    double rays = double(r.primaryRays.value_or(0) + r.shadowRays.value_or(0));
    r.mraysPerSecond = s.median > 0 ? rays / s.median * 1e-6 : 0.0;
}

// --- the time guard --------------------------------------------------------------------------

// Frame times measured so far, per (primitive kind, layout, backend), to estimate the next
// larger case before running it: exhaustive time grows as N (every ray tests every
// primitive); octrees and Embree's BVH grow far slower, and sqrt(N) is a safe upper model
// (the paper reports a doubling per 16x, i.e. N^0.25).
struct Sample {
    double prims, pixels, frameSeconds;
    std::string scene;
};

struct Estimate {
    double frameSeconds;
    std::string how;
};

class TimeGuard {
public:
    void record(const std::string& key, const Sample& s) { history_[key].push_back(s); }

    std::optional<Estimate> estimate(const std::string& key, bool linearInN, double prims,
                                     double pixels) const {
        auto it = history_.find(key);
        if (it == history_.end() || it->second.empty()) return std::nullopt;
        // The largest measured case not above this one; else the smallest above it.
        const Sample* best = nullptr;
        for (const Sample& s : it->second)
            if (s.prims <= prims && (!best || s.prims > best->prims)) best = &s;
        if (!best)
            for (const Sample& s : it->second)
                if (!best || s.prims < best->prims) best = &s;
        double exponent = linearInN ? 1.0 : 0.5;
        double t =
            best->frameSeconds * std::pow(prims / best->prims, exponent) * (pixels / best->pixels);
        return Estimate{t, "history: " + best->scene + " at " + fmt("%.3g", best->frameSeconds) +
                               " s/frame, time ~ N" + (linearInN ? "" : "^0.5")};
    }

private:
    std::map<std::string, std::vector<Sample>> history_;
};

// --- progress on stderr ----------------------------------------------------------------------

class Progress {
public:
    Progress(size_t total, bool enabled)
        : total_(total),
          enabled_(enabled),
          tty_(isatty(2) != 0),
          start_(std::chrono::steady_clock::now()) {}

    // A case starts: a line per case when stderr is not a terminal.
    void begin(const std::string& label) { show(label, true); }
    // A step inside a case (loading, building): shown on a terminal only.
    void step(const std::string& label) { show(label, false); }
    void end() { ++done_; }
    // Clears the bar so a line can be printed on stdout (same terminal).
    void clear() {
        if (enabled_ && tty_ && lastWidth_) {
            std::fprintf(stderr, "\r%s\r", std::string(lastWidth_, ' ').c_str());
            std::fflush(stderr);
            lastWidth_ = 0;
        }
    }
    double elapsed() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }

private:
    void show(const std::string& label, bool isCase) {
        if (!enabled_ || (!tty_ && !isCase)) return;
        double s = elapsed();
        char head[96];
        std::snprintf(head, sizeof head, "[%zu/%zu %dm%02ds] ", done_ + 1, total_, int(s) / 60,
                      int(s) % 60);
        if (tty_) {
            const int width = 24;
            int filled = total_ ? int(double(done_) / double(total_) * width) : 0;
            std::string bar(size_t(filled), '#');
            bar.resize(size_t(width), '.');
            std::string line = "\r" + bar + " " + head + label;
            if (line.size() < lastWidth_) line += std::string(lastWidth_ - line.size(), ' ');
            lastWidth_ = line.size();
            std::fputs(line.c_str(), stderr);
        } else {
            std::fprintf(stderr, "%s%s\n", head, label.c_str());
        }
        std::fflush(stderr);
    }

    size_t total_, done_ = 0;
    bool enabled_, tty_;
    size_t lastWidth_ = 0;
    std::chrono::steady_clock::time_point start_;
};

// --- the sweep -------------------------------------------------------------------------------

struct SceneSpec {
    bool cloud = true;
    uint32_t n = 0;
    std::string path;
    std::string label() const {
        return cloud ? "grid:" + std::to_string(n) : fs::path(path).filename().string();
    }
};

class Bench {
public:
    Bench(const BenchOptions& o, std::vector<Backend> ours, bool embree,
          std::vector<Layout> layouts, std::vector<SceneSpec> scenes, json machine, json config)
        : o_(o),
          ours_(std::move(ours)),
          embree_(embree),
          layouts_(std::move(layouts)),
          scenes_(std::move(scenes)),
          machine_(std::move(machine)),
          config_(std::move(config)),
          progress_(scenes_.size() * ((embree_ ? 1 : 0) + layouts_.size() * ours_.size()),
                    o.progress) {
        parseImageSize(o.size, cam_.width, cam_.height);
    }

    // Returns the number of cases that failed (not skipped).
    int run(const fs::path& dir) {
        printHeader();
        for (const SceneSpec& spec : scenes_) runScene(spec, dir);
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
        return failed;
    }

private:
    void printHeader() {
        std::printf("%-22s %9s %-10s %-6s %8s %10s %8s %8s %11s %8s %9s  %s\n", "scene", "prims",
                    "layout", "back", "build_s", "frame_ms", "Mrays/s", "x_embree", "bytes",
                    "nodes/px", "prims/px", "status");
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

    std::string guardKey(const Scene& s, const std::string& layout, const std::string& backend) {
        return std::string(s.kind == PrimKind::Triangles ? "tri" : "sph") + "/" + layout + "/" +
               backend;
    }

    // The time guard. A case runs as asked when its estimated time for warm-up + repeats is
    // within --max-seconds; when only fewer frames fit, it runs with fewer (repeats first,
    // then warm-up, down to one timed frame; the row records the counts and why); when not
    // even one frame fits, it is skipped. The estimate comes from the history (a smaller
    // measured case, scaled); when that is missing or over the limit, probe frames decide:
    // the same camera at 1/16, then 1/4, then the full width and height. A small probe is
    // dominated by fixed costs (starting the parallel loop on a busy machine), which inflates
    // its extrapolation, so an estimate over the limit only counts once the probe itself took
    // 0.2 s or was full size. Returns false when the case is skipped (reason filled in).
    template <class RenderProbe>
    bool planFrames(const std::string& key, bool linearInN, const Scene& scene, RenderProbe&& probe,
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
            double seconds = probe(makeFrame(scene.bounds(), small));
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

    void runScene(const SceneSpec& spec, const fs::path& dir) {
        size_t casesHere = (embree_ ? 1 : 0) + layouts_.size() * ours_.size();
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
        double loadSeconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        FrameParams frame = makeFrame(scene.bounds(), cam_);

        std::optional<double> embreeFrame;
        if (embree_) {
            progress_.begin(spec.label() + " embree");
            Row r = baseRow(spec, &scene, loadSeconds);
            r.layout = "embree-bvh";
            r.backend = "embree";
            protect(r, [&] { runEmbree(scene, frame, r); });
            if (r.status == "ok") embreeFrame = r.frameMedian;
            add(std::move(r), dir);
            progress_.end();
        }

        // The canonical octree is built once per scene and shared by the linear and hash
        // layouts (each row's build_s is this build plus its own conversion).
        std::optional<Octree> tree;
        std::string treeError;
        for (Layout layout : layouts_) {
            if (layout != Layout::Exhaustive && !tree && treeError.empty() && !ours_.empty()) {
                progress_.step(spec.label() + ": building the octree");
                // A limit (OctreeError: too many references, a depth out of range; memory)
                // makes the octree rows "skipped"; anything else is an "error".
                try {
                    tree = buildOctree(scene, buildParams(scene));
                } catch (const OctreeError& e) {
                    treeError = std::string("skipped:") + e.what();
                } catch (const std::bad_alloc&) {
                    treeError = "skipped:out of memory building the octree";
                } catch (const std::exception& e) {
                    treeError = std::string("error:") + e.what();
                }
            }
            runLayout(spec, scene, loadSeconds, frame, layout, tree, treeError, embreeFrame, dir);
        }
    }

    BuildParams buildParams(const Scene& scene) const {
        BuildParams p;
        if (scene.gridDepth >= 0) {
            // One sphere per deepest cell: split down to the grid depth (the builder clamps
            // maxDepth to scene.gridDepth), leaves with at most cloudMaxPrims spheres.
            p.maxDepth = kMaxOctreeDepth;
            p.maxPrims = o_.cloudMaxPrims;
        } else {
            p.maxDepth = o_.meshMaxDepth;
            p.maxPrims = o_.meshMaxPrims;
        }
        return p;
    }

    void runLayout(const SceneSpec& spec, const Scene& scene, double loadSeconds,
                   const FrameParams& frame, Layout layout, std::optional<Octree>& tree,
                   const std::string& treeError, std::optional<double> embreeFrame,
                   const fs::path& dir) {
        const char* lname = layoutName(layout);
        Row base = baseRow(spec, &scene, loadSeconds);
        base.layout = lname;

        BuiltScene built;
        built.scene = &scene;
        built.layout = layout;
        std::string skip, error;
        if (layout != Layout::Exhaustive) {
            if (!tree) {
                bool limit = treeError.rfind("skipped:", 0) == 0;
                (limit ? skip : error) = treeError.substr(treeError.find(':') + 1);
            } else {
                base.treeSeconds = tree->buildSeconds;
                base.octreeNodes = tree->nodes.size();
                base.octreeDepth = tree->depth;
                base.octreeFaces = tree->referenceCount();
                progress_.step(spec.label() + ": converting to " + lname);
                auto t0 = std::chrono::steady_clock::now();
                try {
                    if (layout == Layout::Linear)
                        built.linear = buildLinear(*tree, o_.limits.linearBudgetBytes());
                    else
                        built.hash = buildHash(*tree, o_.limits.hashParams());
                    base.convertSeconds =
                        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
                            .count();
                    base.buildSeconds = *base.treeSeconds + *base.convertSeconds;
                    built.tree = std::move(*tree);
                } catch (const OctreeError& e) {
                    skip = e.what();  // the layout's memory budget
                } catch (const std::bad_alloc&) {
                    skip = std::string("out of memory allocating the ") + lname + " layout";
                } catch (const std::exception& e) {
                    error = std::string("converting to ") + lname + ": " + e.what();  // a row
                }
            }
        } else {
            base.buildSeconds = 0.0;
        }
        if (!skip.empty() || !error.empty()) {
            for (Backend b : ours_) {
                progress_.begin(spec.label() + " " + lname + " " + backendName(b));
                Row r = base;
                r.backend = backendName(b);
                r.status = error.empty() ? "skipped" : "error";
                r.reason = error.empty() ? skip : error;
                r.warmup = r.repeats = 0;
                add(std::move(r), dir);
                progress_.end();
            }
            return;
        }
        base.layoutBytes = built.layoutBytes();
        built.buildSeconds = base.buildSeconds.value_or(0.0);

        for (Backend b : ours_) {
            progress_.begin(spec.label() + " " + lname + " " + backendName(b));
            Row r = base;
            r.backend = backendName(b);
            protect(r, [&] {
                if (b == Backend::Cuda)
                    runCudaCase(scene, frame, built, r);
                else
                    runCpuCase(scene, frame, built, r);
            });
            if (r.status == "ok" && b == Backend::Cpu && embreeFrame && *embreeFrame > 0)
                r.ratioToEmbree = *r.frameMedian / *embreeFrame;
            add(std::move(r), dir);
            progress_.end();
        }
        // Hand the canonical tree back for the next layout.
        if (layout != Layout::Exhaustive) tree = std::move(built.tree);
    }

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

    void runEmbree(const Scene& scene, const FrameParams& frame, Row& r) {
        EmbreeTracer tracer(scene);
        r.buildSeconds = tracer.buildSeconds();
        PrimitivesView prims = primitivesView(scene);
        auto render = [&](const FrameParams& p, Film& film) {
            film = Film(p.width, p.height);
            FilmView fv = film.view();
            double start = omp_get_wtime();
            renderFrameCpu(p, tracer.accel(), prims, fv);
            return omp_get_wtime() - start;
        };
        std::string key = guardKey(scene, "embree-bvh", "embree");
        auto probe = [&](const FrameParams& p) {
            Film f;
            return render(p, f);
        };
        if (!planFrames(key, false, scene, probe, r)) return;
        Film film;
        std::vector<double> frames;
        for (int i = 0; i < r.warmup; ++i) render(frame, film);
        for (int i = 0; i < r.repeats; ++i) frames.push_back(render(frame, film));
        fillFilmCounts(film, false, r);
        fillTiming(frames, r);
        guard_.record(key, {double(scene.primitiveCount()), double(frame.width) * frame.height,
                            *r.frameMedian, r.scene});
    }

    void runCpuCase(const Scene& scene, const FrameParams& frame, const BuiltScene& built, Row& r) {
        std::string key = guardKey(scene, r.layout, r.backend);
        bool linearInN = built.layout == Layout::Exhaustive;
        auto probe = [&](const FrameParams& p) {
            Film f;
            return renderCpu(p, built, f);
        };
        if (!planFrames(key, linearInN, scene, probe, r)) return;
        Film film;
        std::vector<double> frames;
        for (int i = 0; i < r.warmup; ++i) renderCpu(frame, built, film);
        for (int i = 0; i < r.repeats; ++i) frames.push_back(renderCpu(frame, built, film));
        fillFilmCounts(film, true, r);
        fillTiming(frames, r);
        guard_.record(key, {double(scene.primitiveCount()), double(frame.width) * frame.height,
                            *r.frameMedian, r.scene});
    }

    void runCudaCase(const Scene& scene, const FrameParams& frame, const BuiltScene& built,
                     Row& r) {
#ifdef OCT_HAVE_CUDA
        std::string key = guardKey(scene, r.layout, r.backend);
        bool linearInN = built.layout == Layout::Exhaustive;
        auto probe = [&](const FrameParams& p) {
            Film f;
            return renderCuda(p, built, f, nullptr, 0, 1);
        };
        if (!planFrames(key, linearInN, scene, probe, r)) return;
        Film film;
        CudaTiming tm;
        renderCuda(frame, built, film, &tm, r.warmup, r.repeats);
        fillFilmCounts(film, true, r);
        r.uploadSeconds = tm.uploadSeconds;
        r.frameMedian = tm.kernelSeconds;
        r.frameMin = tm.minKernelSeconds;
        r.frameMax = tm.maxKernelSeconds;
        double rays = double(r.primaryRays.value_or(0) + r.shadowRays.value_or(0));
        r.mraysPerSecond = tm.kernelSeconds > 0 ? rays / tm.kernelSeconds * 1e-6 : 0.0;
        guard_.record(key, {double(scene.primitiveCount()), double(frame.width) * frame.height,
                            *r.frameMedian, r.scene});
#else
        (void)scene, (void)frame, (void)built;
        r.status = "error";
        r.reason = "built without CUDA";
#endif
    }

    const BenchOptions& o_;
    std::vector<Backend> ours_;  // cpu and/or cuda, in the order asked
    bool embree_;
    std::vector<Layout> layouts_;
    std::vector<SceneSpec> scenes_;
    json machine_, config_;
    CameraOptions cam_;
    TimeGuard guard_;
    Progress progress_;
    std::vector<Row> rows_;
};

// --- options to a sweep ----------------------------------------------------------------------

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

void runBench(BenchOptions o, CLI::App* cmd) {
    if (o.quick) {
        // A smoke test of the whole pipeline in well under a minute; options given explicitly
        // still win.
        if (!cmd->count("--clouds")) o.clouds = kQuickClouds;
        if (!cmd->count("--size")) o.size = "128x128";
        if (!cmd->count("--repeats")) o.repeats = 2;
        if (!cmd->count("--warmup")) o.warmup = 1;
        if (!cmd->count("--max-seconds")) o.maxSeconds = 20.0;
    }
    int w = 0, h = 0;
    parseImageSize(o.size, w, h);
    setCpuThreads(o.threads);

    // Backends: cpu and cuda run our layouts; embree runs once per scene.
    std::vector<Backend> ours;
    bool embree = false;
    std::string cudaDevice, note;
    bool cudaDefault = !cmd->count("--backends");
#ifdef OCT_HAVE_CUDA
    if (cudaDefault && cudaDevicePresent(cudaDevice)) {
        o.backends += ",cuda";
        if (!cmd->count("--clouds") && !o.quick)
            o.clouds += std::string(",") + kDefaultGpuExtraClouds;
        note = "bench: CUDA device present (" + cudaDevice + "): adding the cuda backend";
    } else if (cudaDefault) {
        note = "bench: no CUDA device (" + cudaDevice + "): cpu and embree only";
        cudaDevice.clear();
    }
#else
    if (cudaDefault) note = "bench: built without CUDA: cpu and embree only";
#endif
    for (const std::string& name : splitList(o.backends)) {
        if (name == "embree") {
            embree = true;
            continue;
        }
        if (name != "cpu" && name != "cuda")
            throw CLI::ValidationError("--backends", "'" + name + "': use cpu, embree, cuda");
        Backend b = Backend::Cpu;
        if (name == "cuda") {
#ifdef OCT_HAVE_CUDA
            if (cudaDevice.empty() && !cudaDevicePresent(cudaDevice))
                throw std::runtime_error("--backends cuda: " + cudaDevice);
            b = Backend::Cuda;
#else
            throw std::runtime_error(
                "--backends cuda: this octrace was built without CUDA (nvcc was not found at "
                "configure time); use --backends cpu,embree");
#endif
        }
        if (std::find(ours.begin(), ours.end(), b) == ours.end()) ours.push_back(b);
    }
    std::vector<Layout> layouts;
    for (const std::string& name : splitList(o.accels)) {
        Layout l = parseLayout(name);
        if (std::find(layouts.begin(), layouts.end(), l) == layouts.end()) layouts.push_back(l);
    }
    if (ours.empty() && !embree) throw CLI::ValidationError("--backends", "no backend given");
    if (!ours.empty() && layouts.empty()) throw CLI::ValidationError("--accels", "no layout given");

    std::vector<SceneSpec> scenes;
    if (o.clouds != "none")
        for (const std::string& c : splitList(o.clouds))
            scenes.push_back({true, parseCount(c), ""});
    std::vector<std::string> meshNotes;
    if (o.meshes.empty()) {
        fs::path dir = findMeshesDir(o.meshesDir);
        if (dir.empty()) {
            meshNotes.push_back(
                "no meshes/ folder found (give --meshes-dir): no meshes benchmarked");
        } else {
            auto push = [&](const char* name) {
                fs::path p = dir / name;
                if (fs::exists(p))
                    scenes.push_back({false, 0, p.lexically_normal().string()});
                else
                    meshNotes.push_back(
                        "not found, not benchmarked: " + p.string() +
                        (std::string(name).rfind("cache/", 0) == 0 ? " (run meshes/fetch)" : ""));
            };
            if (o.quick)
                for (const char* m : kQuickMeshes) push(m);
            else
                for (const char* m : kDefaultMeshes) push(m);
        }
    } else if (o.meshes != "none") {
        for (const std::string& m : splitList(o.meshes)) {
            if (!fs::is_regular_file(m))
                throw std::runtime_error("--meshes: '" + m + "' is not a file");
            scenes.push_back({false, 0, m});
        }
    }
    if (scenes.empty()) throw CLI::ValidationError("--clouds", "nothing to benchmark");

    fs::path dir = o.out;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (!fs::is_directory(dir))
        throw std::runtime_error("--out '" + o.out + "': cannot create the folder" +
                                 (ec ? " (" + ec.message() + ")" : ""));

    if (!note.empty()) std::fprintf(stderr, "%s\n", note.c_str());
    for (const std::string& n : meshNotes) std::fprintf(stderr, "bench: %s\n", n.c_str());

    json machine = machineJson(cudaDevice);
    std::vector<std::string> backendNames;
    if (embree) backendNames.push_back("embree");
    for (Backend b : ours) backendNames.push_back(backendName(b));
    std::vector<std::string> layoutNames;
    for (Layout l : layouts) layoutNames.push_back(layoutName(l));
    std::vector<std::string> sceneNames;
    for (const SceneSpec& s : scenes) sceneNames.push_back(s.label());
    json config = {{"quick", o.quick},
                   {"size", {w, h}},
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
                   {"notes", meshNotes}};

    std::printf(
        "octrace bench: %zu scenes x (%s) x (%s), %dx%d, warm-up %d, repeats %d, on %s "
        "(%d OpenMP threads)%s\n",
        scenes.size(), o.accels.c_str(), o.backends.c_str(), w, h, o.warmup, o.repeats,
        machine["cpu_model"].get<std::string>().c_str(), omp_get_max_threads(),
        cudaDevice.empty() ? "" : (", GPU " + cudaDevice).c_str());
    Bench bench(o, ours, embree, layouts, scenes, machine, config);
    int failed = bench.run(dir);
    if (failed > 0)
        throw std::runtime_error(std::to_string(failed) +
                                 " benchmark cases failed (status \"error\" in the results)");
}

}  // namespace

void registerBench(CLI::App& app) {
    auto o = std::make_shared<BenchOptions>();
    CLI::App* cmd = app.add_subcommand(
        "bench",
        "Sweep grid clouds and meshes over layouts and backends; write bench.csv and bench.json");
    cmd->add_flag("--quick", o->quick,
                  "Small smoke sweep (clouds 1k,2k,4k; cornell_box, teapot; 128x128; 2 repeats)");
    cmd->add_option("--out", o->out, "Folder for bench.csv and bench.json")->capture_default_str();
    cmd->add_option("--backends", o->backends,
                    "Comma list of cpu, embree, cuda (default: cpu,embree, plus cuda when a "
                    "device answers)");
    cmd->add_option("--accels", o->accels, "Comma list of exhaustive, linear, hash")
        ->capture_default_str();
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
    cmd->add_option("--repeats", o->repeats, "Timed frames per case (median, min, max)")
        ->capture_default_str()
        ->check(CLI::Range(1, 1000));
    cmd->add_option("--warmup", o->warmup, "Untimed frames before the timed ones")
        ->capture_default_str()
        ->check(CLI::Range(0, 1000));
    cmd->add_option("--max-seconds", o->maxSeconds,
                    "Seconds per case: fewer frames when warm-up + repeats would take longer, "
                    "skipped when one frame would")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--seed", o->seed, "Grid cloud seed")->capture_default_str();
    cmd->add_option("--threads", o->threads,
                    "OpenMP threads (default: OMP_NUM_THREADS or all cores)")
        ->check(CLI::Range(1, 4096));
    cmd->add_option("--max-depth", o->meshMaxDepth, "Mesh octrees: deepest level")
        ->capture_default_str()
        ->check(CLI::Range(0, kMaxOctreeDepth));
    cmd->add_option("--max-prims", o->meshMaxPrims, "Mesh octrees: split above this many")
        ->capture_default_str()
        ->check(CLI::Range(1u, 1u << 30));
    cmd->add_option("--cloud-max-prims", o->cloudMaxPrims,
                    "Grid cloud octrees (split down to the grid depth): split above this many")
        ->capture_default_str()
        ->check(CLI::Range(1u, 1u << 30));
    addLayoutLimitOptions(*cmd, o->limits, "skipped");
    cmd->add_flag("!--no-progress", o->progress, "No progress lines on stderr");
    cmd->callback([o, cmd] { runBench(*o, cmd); });
}

}  // namespace oct
