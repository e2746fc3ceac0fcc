// octrace rays: the standard, seeded ray sets (validation/rays/ray_sets.h, docs/CERTIFY.md) as a
// ray file in the trace format, plus the manifest beside it that `octrace certify` reads.
//   R.npy  float32 (N, 8): ox oy oz dx dy dz tmin tmax (docs/TRACE_FORMAT.md)
//   R.json the manifest (validation/rays/ray_manifest.h): scene, seed, sets and their rows, camera
//   T.npy  (--triangles) float32 (M, 9): each triangle's v0 v1 v2 in primitive id order
#include <cstdio>
#include <optional>

#include "apps/cli.h"
#include "core/io/npy.h"
#include "core/io/output_file.h"
#include "core/scene/load_scene.h"
#include "core/scene/scene_formats.h"
#include "validation/rays/standard_rays.h"

namespace oct {
namespace {

// Same bound as validate's --rays: 8 floats a ray plus the answers of a tracer.
constexpr uint64_t kMaxRays = kMaxSeededRays;

// The defaults are RaySetSpec's, which octrace.rays takes too (python/module.cpp).
struct RaysOptions {
    std::string scene;
    float radius = 0.0f;
    std::string sets = kDefaultRaySets, out, triangles;
    uint64_t count = RaySetSpec{}.count, seed = RaySetSpec{}.seed;
    CameraChoice camera;  // the camera and shadow sets: render's options, at RaySetSpec's size
    RaysOptions() {
        const CameraOptions c = RaySetSpec{}.camera;
        camera.size = std::to_string(c.width) + "x" + std::to_string(c.height);
        camera.fov = c.fovDegrees;
    }
};

// --set: chooseRaySets (validation/rays/standard_rays.h), its refusals named as --set's.
std::vector<const RaySetDesc*> parseSets(const std::string& text, const Scene& scene,
                                         std::vector<std::string>& notes) {
    try {
        return chooseRaySets(text, scene, notes);
    } catch (const RaySetChoiceError& e) {
        throw CLI::ValidationError("--set", e.what());
    }
}

void runRays(const RaysOptions& o) {
    RaySetSpec spec;
    spec.camera = cameraOptions(o.camera);
    spec.count = o.count;
    spec.seed = o.seed;
    const std::string manifestPath = manifestPathFor(o.out);
    checkOutputPaths({o.out, manifestPath, o.triangles}, {o.scene});
    for (const std::string& p : {o.out, manifestPath, o.triangles})
        if (!p.empty()) checkWritable(p);
    const std::vector<OutputLock> locks = lockOutputs({o.out, manifestPath, o.triangles});

    LoadOptions lo;
    lo.radius = o.radius;
    Scene scene = loadScene(o.scene, lo);
    if (scene.report.totalDropped() > 0)
        std::fprintf(stderr, "loading dropped %llu faces or points (see octrace info)\n",
                     (unsigned long long)scene.report.totalDropped());
    std::vector<std::string> notes;
    spec.sets = parseSets(o.sets, scene, notes);
    if (!o.triangles.empty() && scene.kind != PrimKind::Triangles)
        throw std::runtime_error("--triangles: '" + o.scene + "' is a point cloud");

    StandardRays made = makeStandardRays(
        scene, spec, "octrace rays --size " + o.camera.size + " --count " + std::to_string(o.count),
        "use a smaller --size (the camera and shadow sets hold a row per pixel each) or a smaller "
        "--count");
    const RaySet& rays = made.rays;
    const RayManifest& manifest = made.manifest;

    OutputSet out;  // all files or none
    // Written from the rays where they lie (no encoded copy of the file in memory).
    stageNpy(out, o.out, "<f4", {rays.count(), 8}, rays.rays.data(), 4);
    const std::string json = toJson(manifest).dump(2) + "\n";
    out.stage(manifestPath, json.data(), json.size());
    if (!o.triangles.empty()) {
        static_assert(sizeof(Triangle) == 36, "a triangle is nine packed floats");
        stageNpy(out, o.triangles, "<f4", {uint64_t(scene.triangles.size()), 9},
                 scene.triangles.data(), 4);
    }
    out.commit();

    notes.insert(notes.end(), rays.notes.begin(), rays.notes.end());
    for (const std::string& n : notes) std::printf("note    %s\n", n.c_str());
    std::printf("%s: %u %s; %llu rays, seed %llu\n", scene.name.c_str(), scene.primitiveCount(),
                primKindName(scene.kind), (unsigned long long)rays.count(),
                (unsigned long long)o.seed);
    for (const RaySetRange& r : rays.sets)
        std::printf("  %-10s rows %llu..%llu (%llu)\n", r.name.c_str(), (unsigned long long)r.begin,
                    (unsigned long long)(r.begin + r.count), (unsigned long long)r.count);
    std::printf("fnv1a64 %s\n", manifest.checksum.c_str());
    std::printf("wrote   %s %s%s%s\n", o.out.c_str(), manifestPath.c_str(),
                o.triangles.empty() ? "" : " ", o.triangles.c_str());
}

}  // namespace

void registerRays(CLI::App& app) {
    auto o = std::make_shared<RaysOptions>();
    CLI::App* cmd = app.add_subcommand(
        "rays",
        "Write standard, seeded ray sets (.npy, trace format) and their manifest (.json) for "
        "octrace certify (docs/CERTIFY.md)");
    cmd->add_option("scene", o->scene, sceneFormatsHelp())->required();
    cmd->add_option("--radius", o->radius, "Sphere radius for point clouds (as octrace info)")
        ->check(finiteNumber())
        ->check(positiveRadius());
    cmd->add_option("--set,--sets", o->sets, "Sets, comma-separated: " + raySetNames() + ", or all")
        ->capture_default_str();
    cmd->add_option("--count", o->count,
                    "Rays over the seeded sets together (all but camera and shadow), split "
                    "evenly; at most 1e8")
        ->capture_default_str()
        ->check(numberIn(0, double(kMaxRays)));
    cmd->add_option("--seed", o->seed, "Seed of the seeded sets")
        ->capture_default_str()
        ->check(finiteNumber());
    cmd->add_option("--out", o->out, "Ray file R.npy; the manifest goes to R.json")->required();
    cmd->add_option("--triangles", o->triangles,
                    "Also write the triangles as octrace numbers them: float32 (M, 9) .npy");
    addCameraOptions(*cmd, o->camera);  // --size, --eye, --target, --up, --fov, --light
    cmd->callback([o] { runRays(*o); });
}

}  // namespace oct
