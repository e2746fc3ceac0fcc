// octrace validate: every chosen layout on every chosen backend against Embree, per pixel
// (primary and shadow rays) and per ray of seeded ray sets, plus the replication check of the
// canonical octree against CGAL's exact test (docs/VALIDATION.md). Exit status 0 only on PASS.
// `octrace validate --table1` prints the paper's Table 1 for the committed and fetched meshes.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "apps/cli.h"
#include "apps/diff_picture.h"
#include "apps/policy_options.h"
#include "apps/rank_share.h"
#include "bench/table1/table1.h"
#include "core/io/name_list.h"
#include "core/io/output_file.h"
#include "core/scene/load_scene.h"
#include "core/system/resources.h"
#include "cpu_ref/render_cpu.h"
#include "dist/ranks.h"
#include "validation/regression/artifacts.h"
#include "validation/regression/regression_run.h"
#include "validation/report/report.h"
#include "validation/validate.h"

namespace oct {
namespace {

// Ray sets keep 8 floats per ray plus four answer arrays per tracer: 1e8 rays are about 5 GB,
// and the per-ray indices stay far below 2^32. More is a typo, refused before any allocation.
constexpr uint64_t kMaxValidateRays = 100000000;
// The box-test contract checks each ray in exact rational arithmetic on one thread: 1e8 rays are
// a soak (docs/ROBUSTNESS.md gives the figures). The same bound as --rays.
constexpr uint64_t kMaxBoxContractRays = 100000000;

struct ValidateCliOptions {
    SceneOptions scene;
    TraceChoice trace{kDefaultLayouts, hostBackend().name};
    std::string size = "256x256";
    uint64_t rays = ValidateOptions{}.rays;
    uint64_t seed = ValidateOptions{}.seed;
    std::string json, diffImage;
    ValidationPolicy policy;
    bool noReplication = false;
    uint64_t boxRays = ValidateOptions{}.boxContractRays;
    bool table1 = false;
    std::string meshes = "meshes";
    std::string regression;      // the regression set's manifest (docs/VALIDATION.md)
    std::string regressionAdd;   // a scene to add to it
    std::string regressionName;  // its entry's name
    std::string addLayouts, addViews;
    double addScale = 0.0;  // 0: not given
    bool update = false;
    // What was given explicitly (--regression-add records only those as the scene's own).
    bool backendGiven = false, sizeGiven = false, maxDepthGiven = false, maxPrimsGiven = false,
         radiusGiven = false;
    std::string artifacts;  // what a failing regression check leaves to look at
    bool artifactsAlways = false;
};

// The backends under test: Embree (any backend with its own structure) is the reference.
std::vector<const BackendDesc*> backendsUnderTest(const std::string& text) {
    std::vector<std::string> notes;
    std::vector<const BackendDesc*> out = parseBackendList(text, notes);
    for (const std::string& n : notes) std::fprintf(stderr, "%s\n", n.c_str());
    for (const BackendDesc* b : out)
        if (!b->usesLayouts)
            throw std::runtime_error(std::string("--backend ") + b->name + ": " + b->name +
                                     " traces its own structure, not our layouts (embree is "
                                     "the reference; certify other tracers with octrace "
                                     "certify); use a backend that traces our layouts");
    return out;
}

// The backends the regression set (--regression) renders with: --backend's list, where a backend
// that cannot run here is kept, to be reported as skipped (runRegression), instead of refused as
// for a scene's checks.
std::vector<const BackendDesc*> regressionBackends(const std::string& text) {
    std::vector<std::string> notes;
    std::vector<const BackendDesc*> out = parseBackendList(text, notes, true);
    for (const std::string& n : notes) std::fprintf(stderr, "%s\n", n.c_str());
    return out;
}

// Where the human summary goes: stdout, unless the JSON report does (`--json -`), which must
// then be the only thing on stdout so that it can be piped into a JSON reader.
std::FILE* summaryStream(const std::string& jsonPath) { return jsonPath == "-" ? stderr : stdout; }

void checkRayCount(uint64_t rays) {
    if (rays > kMaxValidateRays)
        throw std::runtime_error("--rays " + std::to_string(rays) + " is more than the " +
                                 std::to_string(kMaxValidateRays) +
                                 " seeded rays validate supports (each costs about 50 bytes "
                                 "per tracer); use fewer");
}

// diff.png for one run; with several runs, diff-LAYOUT-BACKEND.png.
std::string diffPath(const std::string& path, const RunReport& run, size_t runs) {
    if (runs == 1) return path;
    size_t dot = path.rfind('.');
    size_t slash = path.rfind('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) dot = path.size();
    return path.substr(0, dot) + "-" + run.layout + "-" + run.backend + path.substr(dot);
}

void runTable1(const ValidateCliOptions& o) {
    std::vector<Table1Row> rows;
    for (const std::string& path : table1Meshes(o.meshes))
        rows.push_back(table1Row(path, o.scene.layoutOptions().build));
    std::fprintf(summaryStream(o.json), "Table 1 (max depth %d, max prims %u)\n%s",
                 o.scene.maxDepth, o.scene.maxPrims, humanTable1(rows).c_str());
    if (!o.json.empty()) writeTextOutput(o.json, toJson(rows).dump(2) + "\n");
}

// What --regression-add records for the new scene: the options given on its command line.
RegressionAddition regressionAddition(const ValidateCliOptions& o) {
    RegressionAddition a;
    a.scene = o.regressionAdd;
    if (!o.regressionName.empty()) a.name = o.regressionName;
    if (o.sizeGiven) {
        int w = 0, h = 0;
        parseImageSize(o.size, w, h);
        a.settings.width = w;
        a.settings.height = h;
    }
    if (o.maxDepthGiven) a.settings.maxDepth = o.scene.maxDepth;
    if (o.maxPrimsGiven) a.settings.maxPrims = o.scene.maxPrims;
    if (o.radiusGiven) a.settings.radius = o.scene.radius;
    if (o.addScale != 0.0) a.settings.scale = o.addScale;
    if (!o.addLayouts.empty()) {
        std::vector<std::string> names;
        for (const LayoutDesc* l : parseLayoutList(o.addLayouts)) names.push_back(l->name);
        a.settings.layouts = names;
    }
    if (!o.addViews.empty()) {
        std::vector<std::string> views = splitList(o.addViews);
        for (const std::string& v : views)
            if (!isRegressionView(v)) {
                std::string names;
                for (const std::string& n : regressionViewNames()) names += " " + n;
                throw std::runtime_error("--views: '" + v + "' is not one of" + names);
            }
        a.settings.views = views;
    }
    return a;
}

// --regression's mode from the options: check, --update or --regression-add SCENE.
RegressionMode regressionMode(const ValidateCliOptions& o) {
    if (o.backendGiven && (o.update || !o.regressionAdd.empty()))
        throw std::runtime_error(std::string(o.update ? "--update" : "--regression-add") +
                                 " renders on the host backend (" + hostBackend().name +
                                 ") alone; drop --backend, then check the other backends");
    if (!o.regressionAdd.empty()) {
        if (o.update)
            throw std::runtime_error(
                "--regression-add adds one scene; --update re-renders every scene: give one");
        if (!o.scene.path.empty())
            throw std::runtime_error("--regression-add " + o.regressionAdd +
                                     " takes the scene itself; drop the SCENE argument '" +
                                     o.scene.path + "'");
        return RegressionMode::Add;
    }
    if (!o.addLayouts.empty() || !o.addViews.empty() || !o.regressionName.empty() ||
        o.addScale != 0.0)
        throw std::runtime_error(
            "--layouts, --views, --scale and --regression-name set what --regression-add "
            "records");
    return o.update ? RegressionMode::Update : RegressionMode::Check;
}

void runValidate(const ValidateCliOptions& o) {
    Ranks& ranks = Ranks::world();
    if (ranks.distributed() && (o.table1 || !o.regression.empty() || o.scene.path.empty()))
        throw std::runtime_error(
            "across MPI ranks validate checks a SCENE; run --table1 and the regression set "
            "(--regression) in one process");
    if (o.table1) return runTable1(o);
    // Option errors first (cheap), then the regression set (seconds), then the scene.
    checkRayCount(o.rays);
    // The diff images get per-run names when several runs are compared; the plain name is
    // checked here (the per-run names differ from it and from each other).
    checkOutputPaths({o.json == "-" ? "" : o.json, o.diffImage}, {o.scene.path});
    std::vector<const LayoutDesc*> layoutList = parseLayoutList(o.trace.accel);
    // Without a scene only the regression set runs: a backend absent here is skipped there.
    const std::vector<const BackendDesc*> backendList = o.scene.path.empty()
                                                            ? regressionBackends(o.trace.backend)
                                                            : backendsUnderTest(o.trace.backend);
    if (!o.scene.path.empty()) agreeOnBackends(backendList, o.trace.backend);
    setCpuThreadsFromOption(o.trace.threads);
    if (o.regression.empty() && (o.update || !o.regressionAdd.empty()))
        throw std::runtime_error(std::string(o.update ? "--update" : "--regression-add") +
                                 " needs --regression FILE, the manifest to write");
    RegressionReport reg;
    if (!o.regression.empty()) {
        const RegressionMode mode = regressionMode(o);
        const RegressionAddition add =
            mode == RegressionMode::Add ? regressionAddition(o) : RegressionAddition{};
        // --backend not given: the manifest's backends.
        const std::vector<const BackendDesc*> none;
        reg = runRegression(o.regression, mode, ".", o.backendGiven ? backendList : none, &add);
    }
    std::fputs(humanSummary(reg).c_str(), summaryStream(o.json));
    if (!o.artifacts.empty()) {
        const ArtifactsWritten w = writeRegressionArtifacts(o.artifacts, reg, o.artifactsAlways);
        if (!w.files.empty())
            std::fprintf(summaryStream(o.json),
                         "wrote    %s (%llu failing images, %llu failing cost rows, %zu files)\n",
                         w.files.front().c_str(), (unsigned long long)w.failingImages,
                         (unsigned long long)w.failingCostRows, w.files.size());
    }
    if (o.scene.path.empty()) {
        if (o.regression.empty())
            throw std::runtime_error(
                "validate needs a SCENE (or --table1, or --regression FILE); see --help");
        nlohmann::json j = {{"pass", true}, {"format", "octrace-validate-report"}, {"version", 2}};
        addToJson(j, reg);
        if (!o.json.empty()) writeTextOutput(o.json, j.dump(2) + "\n");
        if (!reg.passes())
            throw CommandVerdict(
                kExitFail, "validation FAILED" + reg.failureText() + " (see the report above)");
        if (!reg.skipped.empty())
            throw CommandVerdict(kExitIncomplete,
                                 "validation INCOMPLETE: " + std::to_string(reg.skipped.size()) +
                                     " backend(s) asked for could not run here (see above); "
                                     "what ran passed");
        return;
    }
    ValidateOptions vo;
    if (ranks.distributed()) vo.share = rankShare();
    parseImageSize(o.size, vo.camera.width, vo.camera.height);
    vo.rays = o.rays;
    vo.seed = o.seed;
    vo.policy = o.policy;
    vo.replication = !o.noReplication;
    vo.boxContractRays = o.boxRays;

    // The films and rays against the machine's memory, before the scene is loaded.
    checkMemory(validatePeakBytes(vo, layoutList.size() * backendList.size()),
                "octrace validate --size " + o.size + " --rays " + std::to_string(o.rays) + " (" +
                    std::to_string(layoutList.size() * backendList.size()) + " runs)",
                "use a smaller --size or fewer --rays");

    Scene scene = loadScene(o.scene.path, o.scene.loadOptions());
    if (scene.report.totalDropped() > 0)
        std::fprintf(stderr, "loading dropped %llu faces or points (see octrace info)\n",
                     (unsigned long long)scene.report.totalDropped());
    LayoutOptions lo = o.scene.layoutOptions();
    // One canonical octree, shared by every layout converted from it and checked for
    // replication (also built for an exhaustive-only run when replication is asked).
    std::shared_ptr<const Octree> canonical;
    bool needTree = vo.replication;
    for (const LayoutDesc* l : layoutList) needTree = needTree || l->usesOctree;
    BuildParams build = lo.build;  // refused at the first level one of the layouts cannot store
    for (const LayoutDesc* l : layoutList) l->limitBuild(build, lo);
    if (needTree) canonical = buildSharedOctree(scene, build);
    std::vector<std::unique_ptr<BuiltScene>> built;
    std::vector<std::shared_ptr<SceneTracer>> prepared;
    std::vector<TracerUnderTest> tracers;
    for (const LayoutDesc* l : layoutList) {
        built.push_back(std::make_unique<BuiltScene>(convertLayout(scene, canonical, *l, lo)));
        // The structural check reads the layout's host arrays through its own view.
        NodeLookupFn lookup;
        if (l->usesOctree)
            lookup = [b = built.back().get()](uint64_t key) { return b->lookupNode(key); };
        for (const BackendDesc* b : backendList) {
            std::shared_ptr<SceneTracer> t = b->prepare(*built.back());
            prepared.push_back(t);
            tracers.push_back({l->name, b->name,
                               [t](const FrameParams& p, Film& film) { t->render(p, film); },
                               [t](RayBatchView batch) { t->trace(batch); }, lookup});
            if (ranks.distributed()) shareTracer(tracers.back(), vo.share);
        }
    }

    ValidationReport rep = validateScene(scene, tracers, canonical.get(), vo);
    ranks.checkpoint();
    if (!ranks.root()) {  // the same report as rank 0's, which prints and writes it
        if (!rep.passes()) throw CommandVerdict(kExitFail, "validation FAILED");
        if (!rep.complete()) throw CommandVerdict(kExitIncomplete, "validation INCOMPLETE");
        return;
    }
    std::FILE* human = summaryStream(o.json);
    std::fputs(humanSummary(rep).c_str(), human);
    std::fflush(human);
    nlohmann::json j = toJson(rep);
    if (reg.ran()) addToJson(j, reg);
    if (!o.json.empty()) writeTextOutput(o.json, j.dump(2) + "\n");
    if (!o.diffImage.empty())
        for (const RunReport& run : rep.runs) {
            std::string path = diffPath(o.diffImage, run, rep.runs.size());
            writeDiffPicture(path, run.film, rep.policy.tTolerance);
            std::fprintf(human, "wrote    %s\n", path.c_str());
        }
    if (ranks.distributed())
        std::fprintf(human,
                     "ranks    %d, films by image rows and rays by ray rows (each rank then "
                     "judges the whole)\n",
                     ranks.size());
    std::fflush(stdout);
    if (!rep.passes() || !reg.passes())
        throw CommandVerdict(kExitFail, "validation FAILED: " + failureText(rep) +
                                            reg.failureText() + " (see the report above)");
    if (!rep.complete())
        throw CommandVerdict(
            kExitIncomplete,
            "validation INCOMPLETE: nothing wrong, but mismatches past --max-rechecks are "
            "unverified (see the report above; raise or drop the cap to judge them)");
}

}  // namespace

void registerValidate(CLI::App& app) {
    auto o = std::make_shared<ValidateCliOptions>();
    CLI::App* cmd = app.add_subcommand(
        "validate",
        "Check layouts and backends against Embree per pixel and per ray, and the octree's "
        "leaf lists against an exact overlap test (docs/VALIDATION.md). Exit status: 0 PASS, 1 "
        "FAIL, 2 bad input or usage, 3 INCOMPLETE (work left unverified by --max-rechecks)");
    addSceneOptions(*cmd, o->scene);
    cmd->get_option("scene")->required(false);  // not needed with --table1
    addTraceOptions(*cmd, o->trace,
                    "Backends to check, comma-separated: those that trace our layouts (" +
                        backendNames() + " without the reference embree), or auto");
    cmd->get_option("--accel")->description(
        "Layouts to check, comma-separated: " + layoutNames() +
        ", or all (exhaustive costs pixels x primitives: minutes on the bunny)");
    cmd->add_option("--size", o->size, "Image size WxH of the per-pixel check")
        ->capture_default_str();
    cmd->add_option("--rays", o->rays,
                    "Seeded rays (around, inside, axis-parallel); 0 for none, at most 1e8")
        ->capture_default_str()
        ->check(finiteNumber());
    cmd->add_option("--seed", o->seed, "Seed of the ray sets")
        ->capture_default_str()
        ->check(finiteNumber());
    addJsonOption(*cmd, o->json, "the report");
    cmd->add_option("--diff-image", o->diffImage,
                    "Write a PNG heat map of |dt| with wrong pixels marked (one per run: "
                    "NAME-LAYOUT-BACKEND.png when there are several)");
    addPolicyOptions(*cmd, o->policy, "primary pixels, shadow rays and the ray sets, each",
                     "in each (primary pixels, shadow rays, the ray sets)");
    cmd->add_flag("--no-replication", o->noReplication, "Skip the replication check");
    cmd->add_option("--box-rays", o->boxRays,
                    "Rays of the box-test contract (exact rationals against the kernel's slab "
                    "tests on the octree's boxes, docs/VALIDATION.md); 0 for none, at most 1e8 "
                    "(a soak)")
        ->capture_default_str()
        ->check(numberIn(0, double(kMaxBoxContractRays),
                         "exact arithmetic on one thread: 1e8 is a soak"));
    cmd->add_flag("--table1", o->table1,
                  "Print the paper's Table 1 (vertices, faces, octree faces) for the meshes in "
                  "--meshes and its cache/ instead of validating a scene");
    cmd->add_option("--meshes", o->meshes, "Mesh folder for --table1")->capture_default_str();
    cmd->add_option("--regression", o->regression,
                    "Also run the regression set of FILE (tests/data/regression/regression.json): "
                    "each scene's frames by its layouts and views on each backend, against their "
                    "golden images and cost baselines; a SCENE is then optional");
    cmd->add_option("--regression-add", o->regressionAdd,
                    "Add SCENE to the --regression FILE and write its images and baselines "
                    "(with --layouts, --views, and --size, --max-depth, --max-prims, --radius "
                    "when given; the file's defaults otherwise)");
    cmd->add_option("--regression-name", o->regressionName,
                    "With --regression-add: the entry's name, for a scene listed in several "
                    "configurations (its images are named after it; default the file name)");
    cmd->add_option("--layouts", o->addLayouts,
                    "With --regression-add: the layouts the scene is held to (default all)");
    cmd->add_option("--scale", o->addScale,
                    "With --regression-add: every vertex times this (a mesh at a tiny or huge "
                    "absolute scale; 1e-6 to 1e6)")
        ->check(numberIn(1e-6, 1e6, "the regression set's scales"));
    cmd->add_option("--views", o->addViews,
                    "With --regression-add: the views, comma-separated: default, +x, -x, +y, "
                    "-y, -z, inside (default: the file's)");
    CLI::Option* artifacts = cmd->add_option(
        "--artifacts", o->artifacts,
        "When the --regression check fails (or a backend is skipped), "
        "write DIR/index.html with each failing frame, its golden and a diff image, "
        "and each failing cost row (for a CI job to keep)");
    cmd->add_flag("--artifacts-always", o->artifactsAlways,
                  "Write --artifacts DIR on a pass as well")
        ->needs(artifacts);
    cmd->add_flag("--update", o->update,
                  "Rewrite the --regression FILE's images and baselines from this build and "
                  "print what changed, instead of checking them");
    cmd->callback([o, cmd] {
        o->backendGiven = cmd->count("--backend") > 0;
        o->sizeGiven = cmd->count("--size") > 0;
        o->maxDepthGiven = cmd->count("--max-depth") > 0;
        o->maxPrimsGiven = cmd->count("--max-prims") > 0;
        o->radiusGiven = cmd->count("--radius") > 0;
        runValidate(*o);
    });
}

}  // namespace oct
