// octrace render: one frame of the paper's ray tracer (primary ray, Phong, shadow ray) with a
// chosen layout and backend; PNG plus optional per-pixel .npy arrays, a cost heat map and an
// octree overlay (teach/). Across MPI ranks each renders a band of image rows and rank 0 gathers
// the Film and writes the same files, byte for byte, as one process (dist/split_work.h).
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "apps/cli.h"
#include "core/io/npy.h"
#include "core/scene/load_scene.h"
#include "core/system/resources.h"
#include "dist/ranks.h"
#include "dist/split_work.h"
#include "teach/heatmap.h"
#include "teach/overlay.h"
#include "validation/policy/film_compare.h"

namespace oct {
namespace {

struct RenderOptions {
    SceneOptions scene;
    TraceChoice trace{kDefaultLayout, "auto"};
    std::string out, depthOut, primOut, costOut;
    CameraChoice camera;
    bool compareEmbree = false;
    std::string heatmap = "boxes", heatmapOut, overlayOut;
    uint32_t heatmapMax = 0;
    int overlayDepth = -1;
};

// The teaching images (teach/): both optional, staged with the other outputs.
struct TeachImages {
    RgbImage heatmap, overlay;
};

// Every requested file, all or none (OutputSet): a failure leaves existing files untouched.
void writeOutputs(const RenderOptions& o, const Film& f, const TeachImages& t) {
    std::vector<uint64_t> shape = {uint64_t(f.height), uint64_t(f.width)};
    OutputSet out;
    out.stage(o.out, encodePng(o.out, f.width, f.height, f.rgb));
    for (auto [path, img] : {std::pair{&o.heatmapOut, &t.heatmap}, {&o.overlayOut, &t.overlay}})
        if (!path->empty()) out.stage(*path, encodePng(*path, img->width, img->height, img->rgb));
    if (!o.depthOut.empty()) stageNpy(out, o.depthOut, "<f4", shape, f.t.data(), 4);
    if (!o.primOut.empty()) stageNpy(out, o.primOut, "<i4", shape, f.prim.data(), 4);
    if (!o.costOut.empty())
        stageNpy(out, o.costOut, "<i4", {uint64_t(f.height), uint64_t(f.width), 2},
                 costArray(f).data(), 4);
    out.commit();
}

// Before any heavy work: no output may name the scene or another output, and every output
// folder must take a new file. The outputs stay locked (NAME.lock) while the locks live.
[[nodiscard]] std::vector<OutputLock> checkOutputs(const RenderOptions& o) {
    checkOutputPaths({o.out, o.depthOut, o.primOut, o.costOut, o.heatmapOut, o.overlayOut},
                     {o.scene.path});
    for (const std::string* p :
         {&o.out, &o.depthOut, &o.primOut, &o.costOut, &o.heatmapOut, &o.overlayOut})
        if (!p->empty()) checkWritable(*p);
    return lockOutputs({o.out, o.depthOut, o.primOut, o.costOut, o.heatmapOut, o.overlayOut});
}

// The octree's shape for the legends (or what exhaustive tracing is).
std::string buildDetails(const Octree* tree) {
    if (!tree) return "no octree: every ray tests every primitive";
    return "octree: depth " + std::to_string(tree->depth) + ", split above " +
           std::to_string(tree->params.maxPrims) + " prims";
}

TeachImages teachImages(const RenderOptions& o, const Scene& scene, const BuiltScene& bs,
                        const FrameParams& frame, const Film& film) {
    TeachImages t;

    const std::string name = std::filesystem::path(scene.name).filename().string();
    if (!o.heatmapOut.empty())
        t.heatmap = heatmapImage(
            film, {parseCostQuantity(o.heatmap, "--heatmap"), o.heatmapMax, bs.layout->name, name,
                   buildDetails(bs.tree.get()), frame.shading.light});
    if (!o.overlayOut.empty()) {
        // Exhaustive tracing builds no octree; the overlay shows the one the layouts would use.
        std::shared_ptr<const Octree> tree =
            bs.tree ? bs.tree : buildSharedOctree(scene, o.scene.layoutOptions().build);
        t.overlay = overlayImage(film, frame, *tree,
                                 {o.overlayDepth, bs.layout->name, name, buildDetails(tree.get())});
    }
    return t;
}

// Before any heavy work: the teaching options make sense together and with the backend.
void checkTeachOptions(const RenderOptions& o, const BackendDesc& backend) {
    const CostQuantity quantity = parseCostQuantity(o.heatmap, "--heatmap");
    if (o.heatmapOut.empty() && (quantity != CostQuantity::Nodes || o.heatmapMax > 0))
        throw CLI::ValidationError("--heatmap", "needs --heatmap-out FILE.png to write the map to");
    if (o.overlayOut.empty() && o.overlayDepth >= 0)
        throw CLI::ValidationError("--overlay-depth", "needs --overlay-out FILE.png");
    if (!o.heatmapOut.empty() && !backend.usesLayouts)
        throw CLI::ValidationError("--heatmap-out", std::string("the ") + backend.name +
                                                        " backend counts no traversal cost; use "
                                                        "--backend cpu (or cuda)");
}

// Traces the same frame with Embree and prints the per-pixel agreement (the validation policy
// of docs/VALIDATION.md; `octrace validate` classifies the mismatches further).
void printEmbreeAgreement(const FrameParams& frame, const Scene& scene, const Film& film) {
    Film truth;
    const BuiltScene bare = bareScene(scene);
    renderWithByRows(referenceBackend(), bare, frame, truth);  // collective
    if (!Ranks::world().root()) return;
    FilmComparison c = compareFilms(film, truth, sceneExtent(scene));
    std::printf(
        "embree  %llu of %llu pixels agree (%llu both miss, %llu same primitive, %llu ties); "
        "%llu hit/miss and %llu distance mismatches; %llu shadow mismatches; "
        "max |dt| %.2e of the scene extent\n",
        (unsigned long long)c.agreeing(), (unsigned long long)c.pixels,
        (unsigned long long)c.bothMiss, (unsigned long long)c.bothHitAgree,
        (unsigned long long)c.ties, (unsigned long long)c.hitMissMismatch,
        (unsigned long long)c.distanceMismatch, (unsigned long long)c.shadowMismatch,
        c.maxRelativeDt);
}

// About the most memory a render holds at once, by pixel: the Film (and Embree's, to compare),
// the PNG's filtered rows and compressed bytes, the cost array, the teaching images and theirs.
uint64_t renderPeakBytes(const RenderOptions& o, uint64_t pixels) {
    const uint64_t png = 2 * 3;  // filtered RGB rows, then the compressed file (no smaller)
    uint64_t perPixel = kFilmBytesPerPixel + png;
    if (o.compareEmbree) perPixel += kFilmBytesPerPixel;
    if (!o.costOut.empty()) perPixel += 2 * sizeof(int32_t);
    for (const std::string* image : {&o.heatmapOut, &o.overlayOut})
        if (!image->empty()) perPixel += 3 + png;
    return saturatingMul(pixels, perPixel);
}

void runRender(const RenderOptions& o) {
    CameraOptions cam = cameraOptions(o.camera);
    const LayoutDesc& layout = parseOneLayout(o.trace.accel, "render");
    std::string note;
    const BackendDesc& backend = parseOneBackend(o.trace.backend, "render", note);
    checkTeachOptions(o, backend);
    Ranks& ranks = Ranks::world();
    std::vector<OutputLock> locks;  // rank 0 writes the outputs
    if (ranks.root()) locks = checkOutputs(o);
    ranks.checkpoint();  // an output rank 0 refuses stops every rank before the work
    setCpuThreadsFromOption(o.trace.threads);
    checkMemory(renderPeakBytes(o, uint64_t(cam.width) * uint64_t(cam.height)),
                "octrace render --size " + o.camera.size, "use a smaller --size");

    Scene scene = loadScene(o.scene.path, o.scene.loadOptions());
    if (scene.report.totalDropped() > 0)
        std::fprintf(stderr, "loading dropped %llu faces or points (see octrace info)\n",
                     (unsigned long long)scene.report.totalDropped());
    // A backend with its own structure (Embree) is given the scene alone.
    BuiltScene bs =
        backend.usesLayouts ? buildScene(scene, layout, o.scene.layoutOptions()) : bareScene(scene);
    FrameParams frame = makeFrame(scene.bounds(), cam);
    Film film;
    FrameRun t = renderWithByRows(backend, bs, frame, film);  // rank 0 holds the whole Film
    if (ranks.root()) writeOutputs(o, film, teachImages(o, scene, bs, frame, film));
    ranks.checkpoint();  // rank 0's writes done (or failed) before --compare-embree's frame
    if (!ranks.root()) {
        if (o.compareEmbree) printEmbreeAgreement(frame, scene, film);
        return;
    }

    std::printf("%s: %u primitives, %s on %s, %dx%d\n", scene.name.c_str(), scene.primitiveCount(),
                tracedStructure(backend, layout), backend.name, frame.width, frame.height);
    if (!note.empty()) std::printf("%s\n", note.c_str());
    const double seconds = t.frameSeconds.empty() ? 0.0 : t.frameSeconds[0];
    std::printf("build   %.3f s\n", t.buildSeconds);
    std::printf("frame   %.3f s\n", seconds);
    if (ranks.distributed())
        std::printf("ranks   %d, image rows split by rank (times are the slowest rank's)\n",
                    ranks.size());
    double s = seconds > 0 ? seconds : 1e-9;
    std::printf("rays    %llu primary + %llu shadow = %.3f Mrays/s\n",
                (unsigned long long)t.primaryRays, (unsigned long long)t.shadowRays,
                double(t.primaryRays + t.shadowRays) / s * 1e-6);
    if (backend.usesLayouts) {
        double nodes = 0, tested = 0;
        for (size_t i = 0; i < film.pixelCount(); ++i) {
            nodes += film.nodes[i];
            tested += film.primsTested[i];
        }
        std::printf(
            "cost    %.1f boxes tested, %.1f primitives tested per pixel (primary + "
            "shadow)\n",
            nodes / double(film.pixelCount()), tested / double(film.pixelCount()));
    }
    std::printf("wrote   %s\n", o.out.c_str());
    for (const std::string* p : {&o.heatmapOut, &o.overlayOut})
        if (!p->empty()) std::printf("wrote   %s\n", p->c_str());
    if (o.compareEmbree) printEmbreeAgreement(frame, scene, film);
}

}  // namespace

void registerRender(CLI::App& app) {
    auto o = std::make_shared<RenderOptions>();
    CLI::App* cmd = app.add_subcommand("render", "Render a frame to PNG (and .npy arrays)");
    addSceneOptions(*cmd, o->scene);
    addTraceOptions(
        *cmd, o->trace,
        "Backend: " + backendNames() + ", or auto (cuda when a device answers, else cpu)");
    cmd->add_option("--out", o->out, "PNG image to write")->required();
    cmd->add_option("--depth", o->depthOut, "Write hit distances t as float32 (H, W) .npy");
    cmd->add_option("--prim", o->primOut, "Write primitive ids as int32 (H, W) .npy (-1: miss)");
    cmd->add_option("--cost", o->costOut,
                    "Write int32 (H, W, 2) .npy: boxes tested, primitives tested");
    addCameraOptions(*cmd, o->camera);
    cmd->add_option("--heatmap-out", o->heatmapOut,
                    "Write the per-pixel traversal cost as a labelled colour map (PNG)");
    cmd->add_option("--heatmap", o->heatmap,
                    "Cost the heat map shows: boxes (boxes tested; 'nodes', its old name, is "
                    "accepted) or prims (primitives tested), primary + shadow ray. The PNG's "
                    "pixel x,y (from the top left) is explain's --pixel x,y")
        ->capture_default_str();
    cmd->add_option("--heatmap-max", o->heatmapMax,
                    "Fix the colour scale's top (default: the 99th percentile of the image's "
                    "costs, the few pixels above it drawn in the top colour), so maps of "
                    "different layouts compare")
        ->check(numberIn(1, 0xffffffffu));
    cmd->add_option("--overlay-out", o->overlayOut,
                    "Write the image with the octree's leaf cells drawn over it (PNG)");
    cmd->add_option("--overlay-depth", o->overlayDepth,
                    "Draw the cells of this depth instead of the leaves")
        ->check(numberIn(0, kMaxOctreeDepth));
    cmd->add_flag("--compare-embree", o->compareEmbree,
                  "Also trace the frame with Embree and print how many pixels agree");
    cmd->callback([o] { runRender(*o); });
}

}  // namespace oct
