// octrace certify: any tracer's answers for a ray file, judged per ray by the policy of
// docs/VALIDATION.md against Embree and the double-precision truth, per ray set, with the leak
// check of the edges and vertices sets (validation/certify.h, docs/CERTIFY.md). Exit status 0
// only on PASS.
#include <cstdio>
#include <filesystem>

#include "apps/cli.h"
#include "apps/policy_options.h"
#include "core/io/output_file.h"
#include "core/io/ray_file.h"
#include "core/scene/load_scene.h"
#include "validation/rays/hit_files.h"
#include "validation/rays/ray_manifest.h"
#include "validation/report/diff_image.h"
#include "validation/report/report.h"

namespace oct {
namespace {

struct CertifyCliOptions {
    std::string scene;
    float radius = 0.0f;
    std::string rays, hits, json, diffImage;
    bool noPrim = false;
    ValidationPolicy policy;
    int threads = 0;
};

// Where the human summary goes: stdout, unless the JSON report does (`--json -`).
std::FILE* summaryStream(const std::string& jsonPath) { return jsonPath == "-" ? stderr : stdout; }

std::string failure(const CertifyReport& r) {
    std::string sets;
    for (const SetCertification& s : r.result.sets)
        if (!s.clean()) sets += (sets.empty() ? "" : ", ") + s.range.name;
    char rate[64];
    std::snprintf(rate, sizeof rate, "%.3g (limit %.3g)", r.result.strict.ambiguousRate(),
                  r.policy.maxAmbiguousRate);
    return "certification FAILED: " + std::to_string(r.result.all.wrong) + " wrong, " +
           std::to_string(r.result.leaks) + " leaks" + (sets.empty() ? "" : " (in " + sets + ")") +
           ", ambiguous rate " + rate + " (see the report above)";
}

void runCertify(const CertifyCliOptions& o) {
    const std::string manifestPath = manifestPathFor(o.rays);
    const bool haveManifest = std::filesystem::exists(manifestPath);
    checkOutputPaths({o.json == "-" ? "" : o.json, o.diffImage},
                     {o.scene, o.rays, haveManifest ? manifestPath : "", hitTPath(o.hits),
                      o.noPrim ? "" : hitPrimPath(o.hits)});
    for (const std::string& p : {o.json, o.diffImage})
        if (!p.empty() && p != "-") checkWritable(p);
    setCpuThreadsFromOption(o.threads);

    std::vector<float> rows = readRayFile(o.rays);
    const uint64_t n = rows.size() / 8;
    if (n == 0)
        throw std::runtime_error("'" + o.rays +
                                 "' holds no rays: nothing to certify (make some "
                                 "with octrace rays)");
    HitArrays hits = readHitFiles(o.hits, n, o.rays, !o.noPrim);
    std::optional<RayManifest> manifest;
    if (haveManifest) {
        manifest = readManifest(manifestPath);
        checkManifestRows(*manifest, n, o.rays);  // before the scene is loaded
    }

    LoadOptions lo;
    lo.radius = o.radius > 0.0f ? o.radius : (manifest && manifest->radius ? *manifest->radius : 0);
    Scene scene = loadScene(o.scene, lo);
    if (scene.report.totalDropped() > 0)
        std::fprintf(stderr, "loading dropped %llu faces or points (see octrace info)\n",
                     (unsigned long long)scene.report.totalDropped());
    std::vector<std::string> notes;
    // raySetFromFile checks the scene against the manifest (checkSameScene) before it rebuilds.
    RaySet rays = raySetFromFile(scene, std::move(rows), manifest, o.rays, notes);
    if (!o.diffImage.empty() && !rays.find("camera"))
        throw std::runtime_error(
            "--diff-image needs a camera set: make the rays with octrace "
            "rays --set camera,... and keep " +
            manifestPath + " beside them");

    CertifyReport rep = certifyTracer(scene, rays, hits, o.policy);
    rep.rays = o.rays;
    rep.hits = o.noPrim ? hitTPath(o.hits) : hitTPath(o.hits) + " " + hitPrimPath(o.hits);
    rep.manifest = haveManifest;
    rep.seed = manifest ? manifest->seed : 0;
    rep.notes = notes;

    std::FILE* human = summaryStream(o.json);
    std::fputs(humanSummary(rep).c_str(), human);
    std::fflush(human);
    if (!o.json.empty()) writeTextOutput(o.json, toJson(rep).dump(2) + "\n");
    if (!o.diffImage.empty()) {
        writeDiffImage(o.diffImage, cameraDiff(rep.result, rays), rep.policy.tTolerance);
        std::fprintf(human, "wrote    %s\n", o.diffImage.c_str());
    }
    std::fflush(stdout);
    if (!rep.passes()) throw CommandVerdict(kExitFail, failure(rep));
}

}  // namespace

void registerCertify(CLI::App& app) {
    auto o = std::make_shared<CertifyCliOptions>();
    CLI::App* cmd = app.add_subcommand(
        "certify",
        "Judge any tracer's hits for a ray file per ray and per set against Embree and a "
        "double-precision truth, with a leak check (docs/CERTIFY.md); exit 0 only on PASS");
    cmd->add_option("scene", o->scene, "The scene the rays were traced in")->required();
    cmd->add_option("--radius", o->radius,
                    "Sphere radius for point clouds (default: the manifest's, else as octrace "
                    "info)")
        ->check(finiteNumber())
        ->check(positiveRadius());
    cmd->add_option("--rays", o->rays,
                    "Ray file R.npy, float32 (N, 8); its manifest R.json is read when present")
        ->required();
    cmd->add_option("--hits", o->hits,
                    "Prefix of the answers: PREFIX.t.npy float32 (N,), PREFIX.prim.npy int32 (N,)")
        ->required();
    cmd->add_flag("--no-prim", o->noPrim,
                  "Certify distances only (no PREFIX.prim.npy): a hit's primitive is inferred");
    addJsonOption(*cmd, o->json, "the report");
    cmd->add_option("--diff-image", o->diffImage,
                    "Write a PNG heat map of the camera set's |dt| with wrong pixels marked");
    addPolicyOptions(*cmd, o->policy, "per set");
    cmd->add_option("--threads", o->threads,
                    "OpenMP threads (default: OMP_NUM_THREADS or all cores)")
        ->check(numberIn(1, 4096));
    cmd->callback([o] { runCertify(*o); });
}

}  // namespace oct
