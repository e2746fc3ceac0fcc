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
#include "core/system/resources.h"
#include "validation/rays/ray_manifest.h"

namespace oct {
namespace {

// Same bound as validate's --rays: 8 floats a ray plus the answers of a tracer.
constexpr uint64_t kMaxRays = kMaxSeededRays;

struct RaysOptions {
    std::string scene;
    float radius = 0.0f;
    std::string sets = "all", out, triangles;
    uint64_t count = 30000, seed = 1;
    CameraChoice camera;  // the camera and shadow sets: render's options, at 256x256
    RaysOptions() { camera.size = "256x256"; }
};

// --set: names or "all" (every set the scene can make: on a point cloud those that need no
// triangles, on a mesh without a shared edge or a closed fan no edges or vertices set, each
// left out with a note). A set named explicitly that the scene cannot make is refused.
std::vector<const RaySetDesc*> parseSets(const std::string& text, const Scene& scene,
                                         std::vector<std::string>& notes) {
    std::vector<const RaySetDesc*> listed;
    std::vector<bool> named;  // given by name, not by "all"
    for (const std::string& name : splitList(text)) {
        if (name == "all") {
            for (const RaySetDesc& kind : standardRaySets())
                if (std::find(listed.begin(), listed.end(), &kind) == listed.end()) {
                    listed.push_back(&kind);
                    named.push_back(false);
                }
            continue;
        }
        const RaySetDesc* k = findRaySet(name);
        if (!k)
            throw CLI::ValidationError("--set",
                                       "unknown set '" + name + "' (" + raySetNames() + ", all)");
        if (std::find(listed.begin(), listed.end(), k) != listed.end())
            throw CLI::ValidationError("--set", "'" + name + "' is named twice");
        listed.push_back(k);
        named.push_back(true);
    }
    const std::vector<std::string> why = raySetsUnavailable(scene, listed);
    std::vector<const RaySetDesc*> out;
    for (size_t i = 0; i < listed.size(); ++i) {
        if (why[i].empty())
            out.push_back(listed[i]);
        else if (named[i])
            throw CLI::ValidationError("--set", std::string(listed[i]->name) + ": " + why[i] +
                                                    " (leave the set out, or use --set all)");
        else
            notes.push_back(std::string("set ") + listed[i]->name + " left out: " + why[i]);
    }
    if (out.empty())
        throw CLI::ValidationError("--set",
                                   "'" + text + "' names no set (" + raySetNames() + ", all)");
    return out;
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

    // Before a row is drawn: the sets' memory against the machine's (core/system/resources.h).
    checkMemory(raySetPeakBytes(spec),
                "octrace rays --size " + o.camera.size + " --count " + std::to_string(o.count),
                "use a smaller --size (the camera and shadow sets hold a row per pixel each) or a "
                "smaller --count");

    // The shadow set starts at the reference's camera hits: the backend list's reference.
    std::unique_ptr<SceneTracer> reference;
    BuiltScene bare = bareScene(scene);
    if (std::any_of(spec.sets.begin(), spec.sets.end(),
                    [](const RaySetDesc* k) { return k->needsReference; }))
        reference = referenceBackend().prepare(bare);
    TraceBatch trace;
    if (reference) trace = [&reference](RayBatchView b) { reference->trace(b); };
    RaySet rays = makeRaySet(scene, spec, trace);
    RayManifest manifest = describeRaySet(scene, spec, rays);

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
