// octrace certify: any tracer's answers for a ray file, judged per ray by the policy of
// docs/VALIDATION.md (validation/certify.h, docs/CERTIFY.md); exit status as runCli's.
// Across MPI ranks every rank reads the rows and the hits, judges its own share of the rows
// (validation/certify.h, RowShare) and merges the arrays; rank 0 writes the same report, verdict
// files and diff image as one process.
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "apps/cli.h"
#include "apps/diff_picture.h"
#include "apps/policy_options.h"
#include "core/io/output_file.h"
#include "core/io/ray_file.h"
#include "core/scene/load_scene.h"
#include "dist/ranks.h"
#include "validation/certify_baseline.h"
#include "validation/certify_run.h"
#include "validation/rays/hit_files.h"
#include "validation/rays/ray_manifest.h"
#include "validation/rays/verdict_files.h"
#include "validation/report/report.h"

namespace oct {
namespace {

struct CertifyCliOptions {
    std::string scene;
    float radius = 0.0f;
    std::string rays, hits, json, diffImage, verdicts, baseline;
    bool noPrim = false;
    ValidationPolicy policy;
    std::string requireText = "all", queryText = "closest";
    int threads = 0;
};

// Where the human summary goes: stdout, unless the JSON report does (`--json -`).
std::FILE* summaryStream(const std::string& jsonPath) { return jsonPath == "-" ? stderr : stdout; }

// The one line a verdict other than PASS ends with: what failed (or is unverified), where.
std::string verdictLine(const CertifyReport& r) {
    std::string wrongSets, leakSets;
    for (const SetCertification& s : r.result.sets) {
        if (s.counts.wrong) wrongSets += (wrongSets.empty() ? "" : ", ") + s.range.name;
        if (s.leaks) leakSets += (leakSets.empty() ? "" : ", ") + s.range.name;
    }
    char rate[64];
    std::snprintf(rate, sizeof rate, "%.3g (limit %.3g)", r.result.strict.ambiguousRate(),
                  r.policy.maxAmbiguousRate);
    const std::string overSets = r.result.setsOverAmbiguousLimit();
    const Outcome o = r.outcome();
    const std::string camera =
        r.cameraRowsOff() ? std::to_string(r.cameraRows->failures) +
                                " camera rows off the pinhole camera's definition (the rays are "
                                "not what they claim); "
                          : "";
    return std::string("certification ") + outcomeName(o) + " (--require " +
           requireName(r.require) + "): " + camera + "correct " +
           outcomeName(r.result.correct(r.policy.maxAmbiguousRate)) + ", " +
           std::to_string(r.result.all.wrong) + " wrong" +
           (wrongSets.empty() ? "" : " (in " + wrongSets + ")") + ", ambiguous rate " + rate +
           (overSets.empty() ? "" : ", ambiguous above the set's bound in " + overSets) +
           "; watertight " + outcomeName(r.result.watertight()) + ", " +
           std::to_string(r.result.leaks) + " leaks" +
           (leakSets.empty() ? "" : " (in " + leakSets + ")") + "; " +
           std::to_string(r.result.all.unverified + r.result.leakUnverified) +
           " unverified (see the report above)";
}

void runCertify(const CertifyCliOptions& o) {
    const std::string manifestPath = manifestPathFor(o.rays);
    const bool haveManifest = std::filesystem::exists(manifestPath);
    std::vector<std::string> outputs = {o.json == "-" ? "" : o.json, o.diffImage};
    if (!o.verdicts.empty())
        for (const std::string& p : {verdictClassPath(o.verdicts), verdictReasonsPath(o.verdicts),
                                     verdictLeakPath(o.verdicts)})
            outputs.push_back(p);
    const std::string primIn = o.noPrim ? "" : hitPrimPath(o.hits);
    const std::string recordIn = o.noPrim ? "" : hitRunPath(o.hits);  // trace's, when there
    std::vector<std::string> inputs = {o.scene, o.rays, haveManifest ? manifestPath : ""};
    for (const std::string& p : {hitTPath(o.hits), primIn, recordIn}) inputs.push_back(p);
    if (!o.baseline.empty())
        for (const std::string& p : {verdictClassPath(o.baseline), verdictReasonsPath(o.baseline),
                                     verdictLeakPath(o.baseline)})
            inputs.push_back(p);
    checkOutputPaths(outputs, inputs);
    Ranks& ranks = Ranks::world();
    std::vector<OutputLock> locks;  // until the outputs are in place; rank 0 writes them
    if (ranks.root()) {
        for (const std::string& p : outputs)
            if (!p.empty() && p != "-") checkWritable(p);
        locks = lockOutputs(outputs);
    }
    ranks.checkpoint();  // an output rank 0 refuses stops every rank before the work
    setCpuThreadsFromOption(o.threads);

    // Where the time goes, on every run (the phases line): the certify run is benchmarked
    // against tracing the same rays (docs/PERFORMANCE.md).
    auto clock = std::chrono::steady_clock::now();
    auto lap = [&clock] {
        const auto now = std::chrono::steady_clock::now();
        const double s = std::chrono::duration<double>(now - clock).count();
        clock = now;
        return s;
    };
    std::vector<float> rows;
    readRayFileInto(o.rays, [&](uint64_t n) {
        // About 96 bytes a row: the row (32), the hits read back (8), the reference's closest
        // and any hit (16), the verdicts (class, reasons, leak: 6) and the classifier's per-row
        // results beside them.
        checkRayFileMemory("certify", o.rays, n, 96);
        rows.resize(n * 8);
        return rows.data();
    });
    const uint64_t n = rows.size() / 8;
    if (n == 0)
        throw std::runtime_error("'" + o.rays +
                                 "' holds no rays: nothing to certify (make some "
                                 "with octrace rays)");
    HitArrays hits = readHitFiles(o.hits, n, o.rays, !o.noPrim);
    std::optional<VerdictArrays> baseline;
    if (!o.baseline.empty()) baseline = readVerdictFiles(o.baseline, n);
    std::optional<RayManifest> manifest;
    if (haveManifest) {
        manifest = readManifest(manifestPath);
        checkManifestRows(*manifest, n, o.rays);  // before the scene is loaded
    }

    const double readSeconds = lap();
    LoadOptions lo;
    lo.radius = o.radius > 0.0f ? o.radius : (manifest && manifest->radius ? *manifest->radius : 0);
    Scene scene = loadScene(o.scene, lo);
    if (scene.report.totalDropped() > 0)
        std::fprintf(stderr, "loading dropped %llu faces or points (see octrace info)\n",
                     (unsigned long long)scene.report.totalDropped());
    const double loadSeconds = lap();

    CertifyRunOptions ro;
    ro.policy = o.policy;
    ro.query.ownSets = o.queryText == "anyhit" ? QueryKind::AnyHit : QueryKind::Closest;
    ro.require = o.requireText == "correct"      ? Require::Correct
                 : o.requireText == "watertight" ? Require::Watertight
                                                 : Require::All;
    ro.raysName = o.rays;
    // Before the work: without a manifest the rows are one set "all", with no camera set.
    if (!o.diffImage.empty() &&
        (!manifest || std::none_of(manifest->sets.begin(), manifest->sets.end(),
                                   [](const RaySetRange& s) { return s.name == "camera"; })))
        throw std::runtime_error(
            "--diff-image needs a camera set: make the rays with octrace "
            "rays --set camera,... and keep " +
            manifestPath + " beside them");
    RowShare share;  // this rank's rows, merged with the others' (collective)
    if (ranks.distributed()) {
        share = {ranks.deal(n).block, uint32_t(ranks.rank()), uint32_t(ranks.size()),
                 [&ranks](void* data, uint64_t bytes) { ranks.combineOwned(data, bytes); }};
        ro.query.share = &share;
    }
    CertifyRun run = certifyRows(scene, std::move(rows), hits, manifest, ro);
    lap();
    CertifyReport& rep = run.report;
    const RaySet& rays = run.rays;
    rep.hits = o.noPrim ? hitTPath(o.hits) : hitTPath(o.hits) + " " + hitPrimPath(o.hits);

    std::optional<BaselineComparison> change;
    if (baseline) change = compareWithBaseline(rep.result, *baseline, o.baseline);
    const Outcome outcome = rep.outcome();
    // Every rank holds the same report; rank 0 prints and writes it, then all end alike.
    ranks.checkpoint();
    if (!ranks.root()) {
        if (outcome != Outcome::Pass)
            throw CommandVerdict(outcome == Outcome::Incomplete ? kExitIncomplete : kExitFail,
                                 verdictLine(rep));
        return;
    }
    std::FILE* human = summaryStream(o.json);
    std::fputs(humanSummary(rep).c_str(), human);
    if (change) std::fputs(humanSummary(*change).c_str(), human);
    std::fflush(human);
    if (!o.verdicts.empty()) {
        writeVerdictFiles(o.verdicts,
                          {rep.result.rayClass, rep.result.rayReasons, rep.result.rayLeak});
        std::fprintf(human, "wrote    %s, %s, %s\n", verdictClassPath(o.verdicts).c_str(),
                     verdictReasonsPath(o.verdicts).c_str(), verdictLeakPath(o.verdicts).c_str());
    }
    if (!o.json.empty()) {
        nlohmann::json j = toJson(rep);
        j["baseline"] = change ? toJson(*change) : nlohmann::json(nullptr);
        writeTextOutput(o.json, j.dump(2) + "\n");
    }
    if (!o.diffImage.empty()) {
        writeDiffPicture(o.diffImage, cameraDiff(rep.result, rays), rep.policy.tTolerance);
        std::fprintf(human, "wrote    %s\n", o.diffImage.c_str());
    }
    std::fprintf(human,
                 "phases   read %.3f s, load scene %.3f s, double truth %.3f s, ray sets %.3f s, "
                 "reference %.3f s, check %.3f s, report %.3f s\n",
                 readSeconds, loadSeconds, run.truthSeconds, run.setsSeconds, rep.referenceSeconds,
                 rep.checkSeconds, lap());
    if (ranks.distributed())
        std::fprintf(human, "ranks    %d, ray rows split by rank (the phases are rank 0's)\n",
                     ranks.size());
    std::fflush(stdout);
    if (outcome != Outcome::Pass)
        throw CommandVerdict(outcome == Outcome::Incomplete ? kExitIncomplete : kExitFail,
                             verdictLine(rep));
}

}  // namespace

void registerCertify(CLI::App& app) {
    auto o = std::make_shared<CertifyCliOptions>();
    CLI::App* cmd = app.add_subcommand(
        "certify",
        "Judge any tracer's hits for a ray file per ray and per set against Embree and a "
        "double-precision truth, with a leak check (docs/CERTIFY.md). Exit status: 0 PASS, 1 FAIL, "
        "2 bad input or usage, 3 INCOMPLETE (work left unverified by --max-rechecks, or a "
        "required verdict not tested)");
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
    addPolicyOptions(*cmd, o->policy, "over the sets that are not adversarial, pooled",
                     "in each set (and as many leak candidates)");
    cmd->add_option("--verdicts", o->verdicts,
                    "Write the per-ray verdicts: PREFIX.class.npy (uint8: 0 agree, 1 tie, 2 "
                    "ambiguous, 3 wrong, 4 unverified), PREFIX.reasons.npy (uint32 bits) and "
                    "PREFIX.leak.npy (uint8: 0 sealed, 1 leak, 2 not a target, 3 unsealed, 4 "
                    "unverified); docs/CERTIFY.md");
    cmd->add_option("--baseline", o->baseline,
                    "Compare with an earlier run's --verdicts PREFIX: per set, the rays that got "
                    "better and worse");
    cmd->add_option("--require", o->requireText,
                    "The verdicts that decide the exit status: correct (no wrong closest-hit or "
                    "any-hit answer), watertight (no leak), or all")
        ->check(CLI::IsMember({"correct", "watertight", "all"}))
        ->capture_default_str();
    cmd->add_option("--query", o->queryText,
                    "How to judge sets of one's own (names the manifest gives that are not "
                    "standard): closest hits, or anyhit (occlusion: any hit on the segment is "
                    "right). The standard sets' kind is fixed: shadow is anyhit")
        ->check(CLI::IsMember({"closest", "anyhit"}))
        ->capture_default_str();
    addThreadsOption(*cmd, o->threads);
    cmd->callback([o] { runCertify(*o); });
}

}  // namespace oct
