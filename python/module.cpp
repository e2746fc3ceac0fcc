// The octrace Python module (pybind11): scenes, cast_rays, the standard ray sets, certification,
// render and explain in process, numpy in and out (docs/PYTHON.md). Every call runs the library
// code the command line runs (the CLI's commands only parse options and write files around the
// same calls), so a result here is bit for bit the file the matching command writes. Arguments
// are checked before any work (python/arrays.h); octrace's errors become Python's
// (python/errors.h); the GIL is released while octrace traces, builds or certifies.
#include <omp.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "backends/backend_list.h"
#include "core/io/name_list.h"
#include "core/io/ray_file.h"
#include "core/octree/layout_registry.h"
#include "core/octree/octree_limits.h"
#include "core/render/film.h"
#include "core/render/frame.h"
#include "core/scene/load_scene.h"
#include "core/system/resources.h"
#include "cpu_ref/render_cpu.h"
#include "python/arrays.h"
#include "python/errors.h"
#include "python/scene_object.h"
#include "teach/explain.h"
#include "validation/certify_run.h"
#include "validation/rays/standard_rays.h"
#include "validation/report/report.h"
#include "validation/report/scene_info.h"

namespace oct::python {
namespace {

using namespace pybind11::literals;

// --- option values, checked as the command line checks them -------------------------------

// %g: integers without a fraction ("0", "21"), large bounds short ("1.8e+19").
std::string numberText(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

// A number option in [lo, hi]: a ValueError naming the option otherwise (NaN included).
template <class T>
T inRange(const char* name, double value, double lo, double hi) {
    if (!(value >= lo && value <= hi))
        throw py::value_error(std::string(name) + ": " + numberText(value) + " is not in [" +
                              numberText(lo) + ", " + numberText(hi) + "]");
    return T(value);
}

// A Python int as uint64 (count=, seed=): a negative one or one past 2^64 - 1 is a ValueError
// naming it, not pybind11's "incompatible function arguments".
uint64_t unsignedOf(const char* name, const py::int_& value) {
    if (value < py::int_(0) || value > py::int_(UINT64_MAX))
        throw py::value_error(std::string(name) + ": " + py::repr(value).cast<std::string>() +
                              " is not in [0, 2^64 - 1]");
    return value.cast<uint64_t>();
}

// threads=None leaves OpenMP's default (OMP_NUM_THREADS or every core); else at most
// maxThreads(), as --threads, for this call only: the count in force before is restored when
// the call ends (OpenMP keeps it per calling thread, and a later call without threads= must
// not inherit it).
class ThreadsForCall {
public:
    explicit ThreadsForCall(const std::optional<int>& threads) {
        if (!threads) return;
        const int n = inRange<int>("threads", *threads, 1, maxThreads());
        saved_ = omp_get_max_threads();
        setCpuThreads(n);
    }
    ~ThreadsForCall() { setCpuThreads(saved_); }  // 0: nothing was changed
    ThreadsForCall(const ThreadsForCall&) = delete;
    ThreadsForCall& operator=(const ThreadsForCall&) = delete;

private:
    int saved_ = 0;
};

const LayoutDesc& layoutNamed(const std::string& name) {
    for (const LayoutDesc& d : layouts())
        if (name == d.name) return d;
    throw py::value_error("layout: unknown '" + name + "' (" + layoutNames() + ")");
}

// A backend of the list, or "auto" (CUDA when a device answers, else the CPU) as --backend.
// An unknown name is a ValueError; one that cannot run here a RuntimeError saying why.
const BackendDesc& backendNamed(const std::string& name) {
    const BackendDesc* b = findBackend(name);
    if (name != "auto" && !b)
        throw py::value_error("backend: unknown '" + name + "' (" + backendNames() + ", auto)");
    std::string why;
    if (b && !b->available(why))
        throw std::runtime_error("backend: '" + name + "' cannot run here: " + why);
    std::string note;
    return resolveBackend(name, note);
}

Vec3 vec3Of(const char* name, const py::handle& value) {
    std::vector<double> v;
    try {
        v = value.cast<std::vector<double>>();
    } catch (const py::cast_error&) {
    }
    if (v.size() != 3 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
        throw py::value_error(std::string(name) + ": give three finite numbers (x, y, z), not " +
                              std::string(py::repr(value)));
    return {float(v[0]), float(v[1]), float(v[2])};
}

std::optional<Vec3> optionalVec3(const char* name, const py::object& value) {
    if (value.is_none()) return std::nullopt;
    return vec3Of(name, value);
}

// The camera of render, explain and the camera and shadow ray sets, as --size, --eye, --target,
// --up, --fov and --light give it; checked by makeFrame before anything is traced.
CameraOptions cameraOf(const std::pair<int, int>& size, const py::object& eye,
                       const py::object& target, const py::object& up, double fov,
                       const py::object& light) {
    CameraOptions c;
    c.width = inRange<int>("size[0] (width)", size.first, 1, kMaxImageSide);
    c.height = inRange<int>("size[1] (height)", size.second, 1, kMaxImageSide);
    c.eye = optionalVec3("eye", eye);
    c.target = optionalVec3("target", target);
    c.up = optionalVec3("up", up);
    c.light = optionalVec3("light", light);
    if (!(fov > 0.0 && fov < 180.0))
        throw py::value_error("fov: " + numberText(fov) +
                              " must be strictly between 0 and 180 degrees");
    c.fovDegrees = float(fov);
    makeFrame({{-1, -1, -1}, {1, 1, 1}}, c);  // its FrameError before any work
    return c;
}

// --max-depth, --max-prims, --hash-slots, --linear-budget, --hash-budget, --node-budget.
LayoutOptions layoutOptionsOf(int maxDepth, int64_t maxPrims, int64_t hashSlots,
                              int64_t linearBudgetMiB, int64_t hashBudgetMiB, int64_t nodeBudget) {
    LayoutOptions o;
    o.build.maxDepth = inRange<int>("max_depth", double(maxDepth), 0, kMaxOctreeDepth);
    o.build.maxPrims = inRange<uint32_t>("max_prims", double(maxPrims), 1, 1u << 30);
    o.build.maxNodes =
        inRange<uint64_t>("node_budget", double(nodeBudget), 1, double(kMaxNodeBudget));
    o.hash.bucketSlots = inRange<uint32_t>("hash_slots", double(hashSlots), 1, 64);
    o.hash.budgetBytes =
        inRange<uint64_t>("hash_budget_mib", double(hashBudgetMiB), 1, double(uint64_t(1) << 24))
        << 20;
    o.linearBudget = inRange<uint64_t>("linear_budget_mib", double(linearBudgetMiB), 1,
                                       double(uint64_t(1) << 24))
                     << 20;
    return o;
}

float radiusOf(const std::optional<double>& radius) {
    if (!radius) return 0.0f;  // the default rule (load_scene.h)
    const float r = float(*radius);
    if (!(std::isfinite(r) && r > 0.0f))
        throw py::value_error("radius: " + py::str(py::float_(*radius)).cast<std::string>() +
                              " is not a positive finite radius; give one, or None for the "
                              "default rule");
    return r;
}

// A path's bytes as os.fsencode gives them (str, bytes or os.PathLike; a name that is not UTF-8
// keeps its bytes). An embedded NUL is refused as open() refuses it: C would read the prefix.
std::string pathText(const py::object& path) {
    const std::string bytes =
        py::module_::import("os").attr("fsencode")(path).cast<py::bytes>().cast<std::string>();
    if (bytes.find('\0') != std::string::npos)
        throw py::value_error("path: embedded null byte in " + py::repr(path).cast<std::string>());
    return bytes;
}

// --- Scene ------------------------------------------------------------------------------------

const char* kSceneOptionsDoc = R"(
    radius: sphere radius of a point cloud (None: half the median nearest-neighbour distance,
        as octrace info says); unused for a mesh.
    max_depth: deepest octree level (root = 0), 0..21 (--max-depth).
    max_prims: split a node holding more primitives than this (--max-prims).
    hash_slots: slots per hash bucket, 1..64 (--hash-slots).
    linear_budget_mib, hash_budget_mib: largest linear / hash octree to allocate, MiB; a layout
        needing more is refused with a ValueError naming the budget (--linear-budget,
        --hash-budget).
    node_budget: most octree nodes to build (--node-budget).)";

// The command line's defaults for the octree options (apps/cli.h's SceneOptions).
struct LayoutLimitDefaults {
    int maxDepth = BuildParams{}.maxDepth;
    int64_t maxPrims = BuildParams{}.maxPrims;
    int64_t hashSlots = HashParams{}.bucketSlots;
    int64_t linearBudgetMiB = int64_t(kDefaultLinearBudget >> 20);
    int64_t hashBudgetMiB = int64_t(kDefaultHashBudget >> 20);
    int64_t nodeBudget = int64_t(kDefaultNodeBudget);
};

struct SceneArgs {
    std::optional<double> radius;
    int maxDepth;
    int64_t maxPrims, hashSlots, linearBudgetMiB, hashBudgetMiB, nodeBudget;
    LayoutOptions layout() const {
        return layoutOptionsOf(maxDepth, maxPrims, hashSlots, linearBudgetMiB, hashBudgetMiB,
                               nodeBudget);
    }
};

std::unique_ptr<SceneObject> loadSceneObject(const py::object& path, const SceneArgs& a) {
    const std::string p = pathText(path);
    const LayoutOptions lo = a.layout();
    LoadOptions opts;
    opts.radius = radiusOf(a.radius);
    Scene scene;
    {
        py::gil_scoped_release free;
        scene = loadScene(p, opts);
    }
    return std::make_unique<SceneObject>(std::move(scene), lo);
}

std::unique_ptr<SceneObject> trianglesObject(const py::handle& array, const std::string& name,
                                             const SceneArgs& a) {
    const auto rows = checkedArray<float>(array, "triangles", {{3, 3}, {9}},
                                          "float32 (M, 3, 3) or (M, 9): v0 v1 v2 per row");
    const LayoutOptions lo = a.layout();
    Scene scene;
    {
        py::gil_scoped_release free;  // `rows` keeps the array alive
        scene = sceneFromTriangles(rows.data(), rowsOf(rows), name);
    }
    return std::make_unique<SceneObject>(std::move(scene), lo);
}

std::unique_ptr<SceneObject> pointsObject(const py::handle& array,
                                          const std::optional<double>& radius,
                                          const std::string& name, const SceneArgs& a) {
    const auto rows = checkedArray<float>(array, "points", {{3}}, "float32 (N, 3): x y z per row");
    const LayoutOptions lo = a.layout();
    LoadOptions opts;
    opts.radius = radiusOf(radius);
    return std::make_unique<SceneObject>(sceneFromPoints(rows.data(), rowsOf(rows), opts, name),
                                         lo);
}

py::dict castRays(SceneObject& s, const py::handle& raysArg, const std::string& layoutName,
                  const std::string& backendName, const std::optional<int>& threads) {
    const auto given = checkedArray<float>(raysArg, "rays", {{8}, {6}},
                                           "float32 (N, 8) ox oy oz dx dy dz tmin tmax, or (N, 6) "
                                           "with tmin 0 and tmax inf");
    const LayoutDesc& layout = layoutNamed(layoutName);
    const BackendDesc& backend = backendNamed(backendName);
    const ThreadsForCall threadsForCall(threads);
    const uint64_t n = rowsOf(given);
    const bool cost = backend.usesLayouts;  // Embree counts no traversal cost
    checkMemory(saturatingMul(n, (given.shape(1) == 6 ? 32 : 0) + 8 + (cost ? 8 : 0)),
                "cast_rays of " + std::to_string(n) + " rays", "trace fewer rays a call");
    // (N, 6): the rows widened to the trace format, tmin 0 and tmax +inf (a copy); (N, 8) as given.
    std::vector<float> widened;
    const float* rows = given.data();
    if (given.shape(1) == 6) {
        widened.resize(n * 8);
        for (uint64_t i = 0; i < n; ++i) {
            std::copy(rows + 6 * i, rows + 6 * i + 6, &widened[8 * i]);
            widened[8 * i + 6] = 0.0f;
            widened[8 * i + 7] = INFINITY;
        }
        rows = widened.data();
    }
    auto t = py::array_t<float>(std::vector<ssize_t>{ssize_t(n)});
    auto prim = py::array_t<int32_t>(std::vector<ssize_t>{ssize_t(n)});
    py::array_t<uint32_t> nodes, tested;
    RayBatchView batch{rows, t.mutable_data(), prim.mutable_data(), n};
    if (cost) {
        nodes = py::array_t<uint32_t>(std::vector<ssize_t>{ssize_t(n)});
        tested = py::array_t<uint32_t>(std::vector<ssize_t>{ssize_t(n)});
        batch.nodes = nodes.mutable_data();
        batch.primsTested = tested.mutable_data();
    }
    double seconds = 0.0;
    {
        py::gil_scoped_release free;
        checkRayRows(rows, n, "rays");  // trace's rule, row by row (core/io/ray_file.h)
        auto lock = s.lock();
        seconds = s.tracer(layout, backend).trace(batch);
    }
    py::dict out("t_hit"_a = t, "primitive_ids"_a = prim, "seconds"_a = seconds);
    if (cost) {
        // The words of docs/TEACHING.md ("Words"); earlier builds named them "nodes" and "prims".
        out["boxes_tested"] = nodes;
        out["prims_tested"] = tested;
    }
    return out;
}

py::dict render(SceneObject& s, const std::pair<int, int>& size, const std::string& layoutName,
                const std::string& backendName, const py::object& eye, const py::object& target,
                const py::object& up, double fov, const py::object& light,
                const std::optional<int>& threads) {
    const CameraOptions cam = cameraOf(size, eye, target, up, fov, light);
    const LayoutDesc& layout = layoutNamed(layoutName);
    const BackendDesc& backend = backendNamed(backendName);
    const ThreadsForCall threadsForCall(threads);
    const uint64_t pixels = uint64_t(cam.width) * uint64_t(cam.height);
    checkMemory(saturatingMul(pixels, kFilmBytesPerPixel + 8),
                "render at " + std::to_string(cam.width) + "x" + std::to_string(cam.height),
                "use a smaller size");
    auto* film = new Film();
    py::capsule owner(film, [](void* p) { delete static_cast<Film*>(p); });
    double seconds = 0.0;
    {
        py::gil_scoped_release free;
        const FrameParams frame = makeFrame(s.scene().bounds(), cam);
        auto lock = s.lock();
        const std::vector<double> times = s.tracer(layout, backend).render(frame, *film);
        seconds = times.empty() ? 0.0 : times[0];
    }
    const ssize_t h = film->height, w = film->width;
    py::dict out("image"_a = py::array_t<uint8_t>({h, w, ssize_t(3)}, film->rgb.data(), owner),
                 "t"_a = py::array_t<float>({h, w}, film->t.data(), owner),
                 "prim"_a = py::array_t<int32_t>({h, w}, film->prim.data(), owner),
                 "shadow"_a = py::array_t<uint8_t>({h, w}, film->shadow.data(), owner),
                 "seconds"_a = seconds);
    if (backend.usesLayouts) out["cost"] = ownedArray(costArray(*film), {h, w, 2});  // --cost's
    return out;
}

py::object explain(SceneObject& s, const py::object& pixel, const py::object& ray,
                   const std::string& layoutName, const std::pair<int, int>& size,
                   const py::object& eye, const py::object& target, const py::object& up,
                   double fov, const py::object& light) {
    const CameraOptions cam = cameraOf(size, eye, target, up, fov, light);
    const LayoutDesc& layout = layoutNamed(layoutName);
    if (!pixel.is_none() && !ray.is_none())
        throw py::value_error("explain: give pixel or ray, not both");
    int x = cam.width / 2, y = cam.height / 2;  // default: the image's centre pixel
    std::vector<float> row;
    if (!ray.is_none()) {
        std::vector<double> v;
        try {
            v = ray.cast<std::vector<double>>();
        } catch (const py::cast_error&) {
        }
        if (v.size() != 6 && v.size() != 8)
            throw py::value_error(
                "ray: give six or eight numbers ox, oy, oz, dx, dy, dz[, tmin, "
                "tmax], not " +
                std::string(py::repr(ray)));
        row = {0, 0, 0, 0, 0, 0, 0.0f, INFINITY};
        for (size_t k = 0; k < v.size(); ++k) row[k] = float(v[k]);
        const std::string problem = rayRowProblem(row.data());  // trace's rule
        if (!problem.empty()) throw py::value_error("ray: " + problem);
    } else if (!pixel.is_none()) {
        std::pair<int, int> p;
        try {
            p = pixel.cast<std::pair<int, int>>();
        } catch (const py::cast_error&) {
            throw py::value_error("pixel: give two integers (x, y), not " +
                                  std::string(py::repr(pixel)));
        }
        x = p.first;
        y = p.second;
    }
    if (row.empty() && (x < 0 || y < 0 || x >= cam.width || y >= cam.height))
        throw py::value_error("pixel: (" + std::to_string(x) + ", " + std::to_string(y) +
                              ") is outside the " + std::to_string(cam.width) + "x" +
                              std::to_string(cam.height) + " image (size=)");
    std::string json;
    {
        py::gil_scoped_release free;
        auto lock = s.lock();
        const BuiltScene& bs = s.built(layout, hostBackend());
        const FrameParams frame = makeFrame(s.scene().bounds(), cam);
        const Explanation e =
            row.empty() ? explainPixel(bs, frame, x, y) : explainRay(bs, frame, row.data());
        json = explainJson(e);
    }
    return jsonToPython(json);
}

py::object info(SceneObject& s) {
    std::string json;
    {
        py::gil_scoped_release free;
        json = sceneInfo(s.scene(), s.options()).dump();
    }
    return jsonToPython(json);
}

// --- the standard ray sets and certification ---------------------------------------------------

py::tuple standardRays(SceneObject& s, const std::string& sets, const py::int_& countArg,
                       const py::int_& seedArg, const std::pair<int, int>& size,
                       const py::object& eye, const py::object& target, const py::object& up,
                       double fov, const py::object& light) {
    RaySetSpec spec;
    spec.camera = cameraOf(size, eye, target, up, fov, light);
    const uint64_t count = unsignedOf("count", countArg);
    spec.count = inRange<uint64_t>("count", double(count), 0, double(kMaxSeededRays));
    spec.seed = unsignedOf("seed", seedArg);
    std::vector<std::string> notes;
    spec.sets = chooseRaySets(sets, s.scene(), notes);
    StandardRays made;
    {
        py::gil_scoped_release free;
        made = makeStandardRays(s.scene(), spec,
                                "octrace.rays(size=(" + std::to_string(spec.camera.width) + ", " +
                                    std::to_string(spec.camera.height) +
                                    "), count=" + std::to_string(count) + ")",
                                "use a smaller size (the camera and shadow sets hold a row per "
                                "pixel each) or a smaller count");
    }
    notes.insert(notes.end(), made.rays.notes.begin(), made.rays.notes.end());
    // What was left out or drawn again, as the CLI's "note" lines: Python warnings.
    for (const std::string& note : notes)
        if (PyErr_WarnEx(PyExc_UserWarning, ("octrace.rays: " + note).c_str(), 1) < 0)
            throw py::error_already_set();  // warnings made errors (-W error)
    const ssize_t rows = ssize_t(made.rays.count());
    py::array_t<float> rays = ownedArray(std::move(made.rays.rays), {rows, 8});
    return py::make_tuple(rays, jsonToPython(toJson(made.manifest).dump()));
}

// The manifest certify reads beside R.npy: a dict as octrace.rays returns it, or the path of a
// manifest file (R.json).
std::optional<RayManifest> manifestOf(const py::object& manifest) {
    if (manifest.is_none()) return std::nullopt;
    if (py::isinstance<py::dict>(manifest)) {
        const std::string text = pythonToJson(manifest);
        nlohmann::json j;
        try {
            j = nlohmann::json::parse(text);
        } catch (const nlohmann::json::exception& e) {
            throw py::value_error(std::string("manifest: not JSON: ") + e.what());
        }
        return manifestFromJson(j, "manifest");
    }
    const std::string path = pathText(manifest);
    // A file that cannot be opened is an OSError as for a scene (readManifest's IoError, a
    // ValueError, is for one that was read and is malformed).
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    int error = 0;
    if (status.type() == std::filesystem::file_type::not_found)
        error = ENOENT;
    else if (ec)
        error = ec.value();
    else if (std::filesystem::is_directory(status))
        error = EISDIR;
    else if (FILE* f = std::fopen(path.c_str(), "rb"))
        std::fclose(f);
    else
        error = errno;
    if (error != 0) {
        setOsError(error, ("cannot open the ray manifest '" + path + "': " + std::strerror(error) +
                           "; check the path, or give the dict octrace.rays returned")
                              .c_str());
        throw py::error_already_set();
    }
    return readManifest(path);
}

Require requireNamed(const std::string& name) {
    for (Require r : {Require::Correct, Require::Watertight, Require::All})
        if (name == requireName(r)) return r;
    throw py::value_error("require: '" + name + "' is not correct, watertight or all");
}

py::dict certify(SceneObject& s, const py::handle& raysArg, const py::handle& tArg,
                 const py::object& primArg, const py::object& manifestArg,
                 const std::string& require, const std::string& query, double tTolerance,
                 double edgeTolerance, double grazingCos, double maxAmbiguousRate,
                 const std::optional<double>& maxRechecks, const std::optional<int>& threads) {
    const auto rays = checkedArray<float>(raysArg, "rays", {{8}},
                                          "float32 (N, 8) ox oy oz dx dy dz tmin tmax, the rays "
                                          "traced");
    const uint64_t n = rowsOf(rays);
    const auto t = checkedArray<float>(tArg, "t_hit", {{}}, "float32 (N,), +inf on a miss");
    HitArrays hits;
    hits.primIds = !primArg.is_none();
    std::optional<py::array_t<int32_t, py::array::c_style>> prim;
    if (hits.primIds)
        prim = checkedArray<int32_t>(primArg, "primitive_ids", {{}}, "int32 (N,), -1 on a miss");
    if (rowsOf(t) != n || (prim && rowsOf(*prim) != n))
        throw py::value_error("t_hit holds " + std::to_string(rowsOf(t)) +
                              (prim ? " and primitive_ids " + std::to_string(rowsOf(*prim)) : "") +
                              " values for " + std::to_string(n) + " rays; give one per ray");
    CertifyRunOptions o;
    o.policy.tTolerance = inRange<double>("t_tolerance", tTolerance, 0, 1);
    o.policy.edgeTolerance = inRange<double>("edge_tolerance", edgeTolerance, 0, 1);
    o.policy.grazingCos = inRange<double>("grazing_cos", grazingCos, 0, 1);
    o.policy.maxAmbiguousRate = inRange<double>("max_ambiguous_rate", maxAmbiguousRate, 0, 1);
    if (maxRechecks)
        o.policy.maxRechecks = inRange<uint64_t>("max_rechecks", *maxRechecks, 1, 1.8e19);
    o.require = requireNamed(require);
    if (query != "closest" && query != "anyhit")
        throw py::value_error("query: '" + query + "' is not closest or anyhit");
    o.query.ownSets = query == "anyhit" ? QueryKind::AnyHit : QueryKind::Closest;
    o.raysName = "the rays";
    const ThreadsForCall threadsForCall(threads);
    const std::optional<RayManifest> manifest = manifestOf(manifestArg);
    checkMemory(saturatingMul(n, 96), "certify of " + std::to_string(n) + " rays",
                "certify fewer rays a call");
    // The classifier keeps its own copies: the rows (moved into the ray sets) and the hits.
    std::vector<float> rows(rays.data(), rays.data() + 8 * n);
    hits.t.assign(t.data(), t.data() + n);
    if (prim) hits.prim.assign(prim->data(), prim->data() + n);
    std::optional<CertifyRun> run;
    std::string report, summary;
    {
        py::gil_scoped_release free;
        run.emplace(certifyRows(s.scene(), std::move(rows), hits, manifest, o));
        run->report.hits = hits.primIds ? "t_hit, primitive_ids" : "t_hit";  // the arrays
        nlohmann::json j = toJson(run->report);
        j["baseline"] = nullptr;  // as certify --json without --baseline
        report = j.dump();
        summary = humanSummary(run->report);
    }
    RayCertification& r = run->report.result;
    py::dict out = jsonToPython(report);
    out["outcome"] = outcomeName(run->report.outcome());
    out["summary"] = summary;
    out["classes"] = ownedArray(std::move(r.rayClass), {ssize_t(n)});
    out["reasons"] = ownedArray(std::move(r.rayReasons), {ssize_t(n)});
    out["leak_states"] = ownedArray(std::move(r.rayLeak), {ssize_t(n)});  // "leaks": the count
    return out;
}

std::vector<std::string> layoutList() {
    std::vector<std::string> out;
    for (const LayoutDesc& d : layouts()) out.push_back(d.name);
    return out;
}

std::vector<std::string> backendList() {
    std::vector<std::string> out;
    for (const BackendDesc& d : backends()) out.push_back(d.name);
    return out;
}

void defineScene(py::module_& m) {
    const LayoutLimitDefaults d;
    // pybind11 keeps the pointer: the text lives as long as the module.
    static const std::string doc =
        R"(A scene and its octree options: a triangle mesh or a point cloud.

Scene(path, *, radius=None, max_depth=7, max_prims=8, ...) loads a file (.obj .ply .off .stl
.xyz) or a generator spec ("grid:N", "slivers:N") as `octrace info PATH` does, keeping what the
loaders keep and counting what they drop (info()["load"]). Scene.from_triangles and
Scene.from_points make one from arrays. The octree of a layout is built on first use and kept.
Options:)" +
        std::string(kSceneOptionsDoc);
    py::class_<SceneObject> scene(m, "Scene", doc.c_str());
    scene.def(py::init([](const py::object& path, std::optional<double> radius, int maxDepth,
                          int64_t maxPrims, int64_t hashSlots, int64_t linearBudgetMiB,
                          int64_t hashBudgetMiB, int64_t nodeBudget) {
                  return loadSceneObject(path, {radius, maxDepth, maxPrims, hashSlots,
                                                linearBudgetMiB, hashBudgetMiB, nodeBudget});
              }),
              "path"_a, py::kw_only(), "radius"_a = py::none(), "max_depth"_a = d.maxDepth,
              "max_prims"_a = d.maxPrims, "hash_slots"_a = d.hashSlots,
              "linear_budget_mib"_a = d.linearBudgetMiB, "hash_budget_mib"_a = d.hashBudgetMiB,
              "node_budget"_a = d.nodeBudget,
              "Loads PATH (str or os.PathLike). OSError when it cannot be read; ValueError when it "
              "is malformed or outside octrace's numeric range.");
    scene.def_static(
        "from_triangles",
        [](const py::handle& triangles, const std::string& name, int maxDepth, int64_t maxPrims,
           int64_t hashSlots, int64_t linearBudgetMiB, int64_t hashBudgetMiB, int64_t nodeBudget) {
            return trianglesObject(triangles, name,
                                   {std::nullopt, maxDepth, maxPrims, hashSlots, linearBudgetMiB,
                                    hashBudgetMiB, nodeBudget});
        },
        "triangles"_a, py::kw_only(), "name"_a = "<triangles>", "max_depth"_a = d.maxDepth,
        "max_prims"_a = d.maxPrims, "hash_slots"_a = d.hashSlots,
        "linear_budget_mib"_a = d.linearBudgetMiB, "hash_budget_mib"_a = d.hashBudgetMiB,
        "node_budget"_a = d.nodeBudget,
        R"(A mesh of the given triangles: float32 (M, 3, 3) or (M, 9), v0 v1 v2 per row.

Primitive id i is row i. A row a loader would drop (a non-finite coordinate, zero area) is a
ValueError naming the row, since dropping it would shift every id after it. `name` names the
scene in reports and manifests.)");
    scene.def_static(
        "from_points",
        [](const py::handle& points, std::optional<double> radius, const std::string& name,
           int maxDepth, int64_t maxPrims, int64_t hashSlots, int64_t linearBudgetMiB,
           int64_t hashBudgetMiB, int64_t nodeBudget) {
            return pointsObject(points, radius, name,
                                {std::nullopt, maxDepth, maxPrims, hashSlots, linearBudgetMiB,
                                 hashBudgetMiB, nodeBudget});
        },
        "points"_a, "radius"_a = py::none(), py::kw_only(), "name"_a = "<points>",
        "max_depth"_a = d.maxDepth, "max_prims"_a = d.maxPrims, "hash_slots"_a = d.hashSlots,
        "linear_budget_mib"_a = d.linearBudgetMiB, "hash_budget_mib"_a = d.hashBudgetMiB,
        "node_budget"_a = d.nodeBudget,
        R"(A point cloud: float32 (N, 3), one sphere of `radius` per row (primitive id = row).

radius None: the default rule (half the median nearest-neighbour distance).)");
    scene.def_property_readonly("name", [](const SceneObject& s) { return s.scene().name; });
    scene.def_property_readonly(
        "kind", [](const SceneObject& s) { return std::string(primKindName(s.scene().kind)); },
        "\"triangles\" or \"spheres\"");
    scene.def(
        "__len__", [](const SceneObject& s) { return s.scene().primitiveCount(); },
        "The number of primitives (triangles or spheres).");
    scene.def_property_readonly(
        "bounds",
        [](const SceneObject& s) {
            const Aabb b = s.scene().bounds();
            return py::make_tuple(py::make_tuple(b.lo.x, b.lo.y, b.lo.z),
                                  py::make_tuple(b.hi.x, b.hi.y, b.hi.z));
        },
        "((xmin, ymin, zmin), (xmax, ymax, zmax)): the box around every primitive.");
    scene.def_property_readonly(
        "triangles",
        [](const py::object& self) -> py::object {
            const Scene& sc = self.cast<const SceneObject&>().scene();
            if (sc.kind != PrimKind::Triangles) return py::none();
            static_assert(sizeof(Triangle) == 36, "a triangle is nine packed floats");
            return viewOf(reinterpret_cast<const float*>(sc.triangles.data()),
                          {ssize_t(sc.triangles.size()), 3, 3}, self);
        },
        "float32 (M, 3, 3), read-only: each triangle's v0 v1 v2 in primitive id order (what "
        "`octrace rays --triangles` writes); None for a point cloud.");
    scene.def_property_readonly(
        "spheres",
        [](const py::object& self) -> py::object {
            const Scene& sc = self.cast<const SceneObject&>().scene();
            if (sc.kind != PrimKind::Spheres) return py::none();
            static_assert(sizeof(Sphere) == 16, "a sphere is four packed floats");
            return viewOf(reinterpret_cast<const float*>(sc.spheres.data()),
                          {ssize_t(sc.spheres.size()), 4}, self);
        },
        "float32 (N, 4), read-only: x y z radius per sphere; None for a mesh.");
    scene.def("info", &info,
              "What `octrace info --json` reports: loading (kept, dropped), topology, the "
              "octree's shape, every layout's bytes. A dict.");
    scene.def("cast_rays", &castRays, "rays"_a, "layout"_a = kDefaultLayout,
              "backend"_a = hostBackend().name, "threads"_a = py::none(),
              R"(Closest hits of a ray batch, as `octrace trace` computes them.

Args:
    rays: float32 (N, 8), one ray per row: ox oy oz dx dy dz tmin tmax; or (N, 6) for tmin 0
        and tmax inf. Every row must pass trace's rule (finite origin, a direction of
        reasonable length, 0 <= tmin <= tmax): ValueError names the first row that does not.
        A C-contiguous array is read in place; float64 is refused, not rounded.
    layout: the acceleration structure, one of octrace.layouts().
    backend: one of octrace.backends(), or "auto" (CUDA when a device answers, else the CPU).
    threads: OpenMP threads (None: OMP_NUM_THREADS or every core).

Returns a dict: "t_hit" float32 (N,) (+inf on a miss) and "primitive_ids" int32 (N,) (-1 on a
miss), bit for bit what `octrace trace` writes for the same rows; "boxes_tested" and
"prims_tested" uint32 (N,), the node boxes and primitives each ray tested (not for Embree, which counts none); and
"seconds", the trace's time. The GIL is released while tracing.)");
    scene.def(
        "render", &render, py::kw_only(), "size"_a = std::pair<int, int>(512, 512),
        "layout"_a = kDefaultLayout, "backend"_a = hostBackend().name, "eye"_a = py::none(),
        "target"_a = py::none(), "up"_a = py::none(), "fov"_a = 45.0, "light"_a = py::none(),
        "threads"_a = py::none(),
        R"(One frame of the paper's ray tracer (primary ray, Phong, shadow ray), as `octrace render`.

Args:
    size: (width, height), each 1..16384.
    layout, backend, threads: as cast_rays.
    eye, target, up, light: (x, y, z) or None for render's framing rule; fov: vertical degrees.

Returns a dict: "image" uint8 (H, W, 3), the pixels of the PNG render writes; "t" float32 (H, W)
and "prim" int32 (H, W) (render --depth, --prim); "cost" int32 (H, W, 2), boxes tested and
primitives tested, primary + shadow ray (render --cost; not for Embree); "shadow" uint8 (H, W);
"seconds".)");
    scene.def(
        "explain", &explain, py::kw_only(), "pixel"_a = py::none(), "ray"_a = py::none(),
        "layout"_a = kDefaultLayout, "size"_a = std::pair<int, int>(512, 512), "eye"_a = py::none(),
        "target"_a = py::none(), "up"_a = py::none(), "fov"_a = 45.0, "light"_a = py::none(),
        R"(One pixel's (or one ray's) traversal step by step: the dict of `octrace explain --json`.

Args:
    pixel: (x, y) of the image render draws with the same camera (row 0 at the top; default the
        centre), or
    ray: (ox, oy, oz, dx, dy, dz[, tmin, tmax]), a row of a trace ray file.
    layout, size, eye, target, up, fov, light: as render.)");
    scene.def("__repr__", [](const SceneObject& s) {
        return "<octrace.Scene '" + s.scene().name +
               "': " + std::to_string(s.scene().primitiveCount()) + " " +
               primKindName(s.scene().kind) + ">";
    });
}

void defineFunctions(py::module_& m) {
    // `octrace rays`' defaults, from the one definition both read (validation/rays/ray_sets.h).
    const RaySetSpec rs;
    m.def("rays", &standardRays, "scene"_a, py::kw_only(), "sets"_a = kDefaultRaySets,
          "count"_a = rs.count, "seed"_a = rs.seed,
          "size"_a = std::pair<int, int>(rs.camera.width, rs.camera.height), "eye"_a = py::none(),
          "target"_a = py::none(), "up"_a = py::none(), "fov"_a = double(rs.camera.fovDegrees),
          "light"_a = py::none(),
          R"(The standard, seeded ray sets, as `octrace rays`: returns (rays, manifest).

Args:
    scene: an octrace.Scene.
    sets: comma-separated set names (camera, shadow, around, inside, axis, edges, vertices,
        grazing, tmin-tmax, slivers) or "all": every set the scene can make (those it cannot
        are left out with a UserWarning); a set named that the scene cannot make is a
        ValueError.
    count: rays over the seeded sets together, split evenly (at most 1e8).
    seed: the seed of the seeded sets.
    size, eye, target, up, fov, light: the camera of the camera and shadow sets (256x256).

Returns rays, float32 (N, 8) in the trace format, the bytes `octrace rays` writes to R.npy, and
the manifest R.json holds, as a dict (pass it to octrace.certify).)");
    const ValidationPolicy p;
    m.def("certify", &certify, "scene"_a, "rays"_a, "t_hit"_a, "primitive_ids"_a = py::none(),
          "manifest"_a = py::none(), py::kw_only(), "require"_a = "all", "query"_a = "closest",
          "t_tolerance"_a = p.tTolerance, "edge_tolerance"_a = p.edgeTolerance,
          "grazing_cos"_a = p.grazingCos, "max_ambiguous_rate"_a = p.maxAmbiguousRate,
          "max_rechecks"_a = py::none(), "threads"_a = py::none(),
          R"(Judges a tracer's answers per ray, as `octrace certify` (docs/CERTIFY.md).

Args:
    scene: the octrace.Scene the rays were traced in.
    rays: float32 (N, 8), the rays traced (octrace.rays' array, or your own).
    t_hit: float32 (N,), your distances (+inf on a miss).
    primitive_ids: int32 (N,) (-1 on a miss), or None to certify distances only.
    manifest: octrace.rays' manifest dict, or the path of an R.json, or None (then the rows are
        one set "all" and there is no leak check).
    require: the verdicts that decide "pass": "correct", "watertight" or "all".
    query: how sets of your own are judged: "closest" or "anyhit".
    t_tolerance, edge_tolerance, grazing_cos, max_ambiguous_rate, max_rechecks: the policy
        (docs/VALIDATION.md), as certify's options of the same names.

Returns the report `octrace certify --json` writes, as a dict ("pass", "verdict", "result" with
the per-set table under "by_set", ...),
plus "outcome" ("PASS", "FAIL", "INCOMPLETE"), "summary" (the text certify prints), and per ray
"classes" uint8 (0 agree, 1 tie, 2 ambiguous, 3 wrong, 4 unverified), "reasons" uint32 (the
ambiguity and fault bits) and "leak_states" uint8 (0 sealed, 1 leak, 2 not a target, 3 unsealed,
4 unverified): rep["classes"] == 3 selects the wrong rays.)");
    m.def("layouts", &layoutList,
          "The layouts of the registry, in list order (cast_rays' layout=).");
    m.def("backends", &backendList,
          "The backends this build has, in list order (cast_rays' backend=); one may still be "
          "unable to run here (cuda without a device): it raises RuntimeError saying why.");
    m.attr("__version__") = octraceVersion();
}

}  // namespace

PYBIND11_MODULE(octrace, m) {
    m.doc() =
        "octrace: octree ray tracing and certification of any tracer's hits, in process "
        "(docs/PYTHON.md).";
    registerErrorTranslator();
    defineScene(m);
    defineFunctions(m);
}

}  // namespace oct::python
