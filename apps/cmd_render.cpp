// octrace render: one frame of the paper's ray tracer (primary ray, Phong, shadow ray) with a
// chosen layout and backend; PNG plus optional per-pixel .npy arrays.
#include <cstdio>
#include <iostream>
#include <optional>

#include "apps/cli.h"
#include "core/io/npy.h"
#include "core/scene/load_scene.h"
#include "validation/film_compare.h"

namespace oct {
namespace {

struct RenderOptions {
    SceneOptions scene;
    TraceChoice trace{"linear", "auto"};
    std::string out, depthOut, primOut, costOut;
    std::string size = "512x512";
    std::string eye, target, up, light;
    float fov = 45.0f;
    bool compareEmbree = false;
};

std::optional<Vec3> optionalVec3(const char* option, const std::string& text) {
    if (text.empty()) return std::nullopt;
    return parseVec3(option, text);
}

CameraOptions cameraOptions(const RenderOptions& o) {
    CameraOptions c;
    parseImageSize(o.size, c.width, c.height);
    c.eye = optionalVec3("--eye", o.eye);
    c.target = optionalVec3("--target", o.target);
    c.up = optionalVec3("--up", o.up);
    c.light = optionalVec3("--light", o.light);
    c.fovDegrees = o.fov;
    // Checked here as well as in makeFrame so the error comes before loading anything.
    makeFrame({{-1, -1, -1}, {1, 1, 1}}, c);
    return c;
}

// Every requested file, all or none (OutputSet): a failure leaves existing files untouched.
void writeOutputs(const RenderOptions& o, const Film& f) {
    std::vector<uint64_t> shape = {uint64_t(f.height), uint64_t(f.width)};
    OutputSet out;
    out.stage(o.out, encodePng(o.out, f.width, f.height, f.rgb));
    if (!o.depthOut.empty()) out.stage(o.depthOut, encodeNpy("<f4", shape, f.t.data(), 4));
    if (!o.primOut.empty()) out.stage(o.primOut, encodeNpy("<i4", shape, f.prim.data(), 4));
    if (!o.costOut.empty()) {
        // (H, W, 2) int32: nodes visited, primitives tested (primary + shadow ray).
        std::vector<int32_t> cost(f.pixelCount() * 2);
        for (size_t i = 0; i < f.pixelCount(); ++i) {
            cost[2 * i] = int32_t(f.nodes[i]);
            cost[2 * i + 1] = int32_t(f.primsTested[i]);
        }
        out.stage(o.costOut,
                  encodeNpy("<i4", {uint64_t(f.height), uint64_t(f.width), 2}, cost.data(), 4));
    }
    out.commit();
}

// Before any heavy work: no output may name the scene or another output, and every output
// folder must take a new file.
void checkOutputs(const RenderOptions& o) {
    checkOutputPaths({o.out, o.depthOut, o.primOut, o.costOut}, {o.scene.path});
    for (const std::string* p : {&o.out, &o.depthOut, &o.primOut, &o.costOut})
        if (!p->empty()) checkWritable(*p);
}

// Traces the same frame with Embree and prints the per-pixel agreement (the validation policy
// of docs/VALIDATION.md; `octrace validate` classifies the mismatches further).
void printEmbreeAgreement(const FrameParams& frame, const Scene& scene, const Film& film) {
    Film truth;
    std::string note;
    renderWith(resolveBackend("embree", note), bareScene(scene), frame, truth);
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

void runRender(const RenderOptions& o) {
    CameraOptions cam = cameraOptions(o);
    const LayoutDesc& layout = parseOneLayout(o.trace.accel, "render");
    std::string note;
    const BackendDesc& backend = parseOneBackend(o.trace.backend, "render", note);
    checkOutputs(o);
    setCpuThreadsFromOption(o.trace.threads);

    Scene scene = loadScene(o.scene.path, o.scene.loadOptions());
    if (scene.report.totalDropped() > 0)
        std::fprintf(stderr, "loading dropped %llu faces or points (see octrace info)\n",
                     (unsigned long long)scene.report.totalDropped());
    // A backend with its own structure (Embree) is given the scene alone.
    BuiltScene bs =
        backend.usesLayouts ? buildScene(scene, layout, o.scene.layoutOptions()) : bareScene(scene);
    FrameParams frame = makeFrame(scene.bounds(), cam);
    Film film;
    FrameRun t = renderWith(backend, bs, frame, film);
    writeOutputs(o, film);

    std::printf("%s: %u primitives, %s on %s, %dx%d\n", scene.name.c_str(), scene.primitiveCount(),
                tracedStructure(backend, layout), backend.name, frame.width, frame.height);
    if (!note.empty()) std::printf("%s\n", note.c_str());
    const double seconds = t.frameSeconds.empty() ? 0.0 : t.frameSeconds[0];
    std::printf("build   %.3f s\n", t.buildSeconds);
    std::printf("frame   %.3f s\n", seconds);
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
            "cost    %.1f nodes visited, %.1f primitives tested per pixel (primary + "
            "shadow)\n",
            nodes / double(film.pixelCount()), tested / double(film.pixelCount()));
    }
    std::printf("wrote   %s\n", o.out.c_str());
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
                    "Write int32 (H, W, 2) .npy: nodes visited, primitives tested");
    cmd->add_option("--size", o->size, "Image size WxH")->capture_default_str();
    cmd->add_option("--eye", o->eye, "Camera position x,y,z (default: framed from the bounds)");
    cmd->add_option("--target", o->target, "Point looked at x,y,z (default: the bounds' centre)");
    cmd->add_option("--up", o->up, "Up vector x,y,z (default 0,1,0)");
    cmd->add_option("--fov", o->fov, "Vertical field of view, degrees")->capture_default_str();
    cmd->add_option("--light", o->light, "Point light x,y,z (default: above and right of the eye)");
    cmd->add_flag("--compare-embree", o->compareEmbree,
                  "Also trace the frame with Embree and print how many pixels agree");
    cmd->callback([o] { runRender(*o); });
}

}  // namespace oct
