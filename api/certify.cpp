// The façade over what `octrace rays` and `octrace certify` call after their files
// (validation/rays/standard_rays.h, validation/certify_run.h): the same library calls in the
// same order, so the package, the command line and the Python module give the same answers.
// What is done here is only the translation: arrays in, strings and arrays out, the options'
// ranges checked as the command line's validators check them, and every exception an
// octrace::Error.
#include "octrace/certify.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <new>
#include <optional>

#include "core/render/frame.h"
#include "core/scene/load_scene.h"
#include "core/system/resources.h"
#include "validation/certify_run.h"
#include "validation/rays/ray_manifest.h"
#include "validation/rays/standard_rays.h"
#include "validation/report/report.h"

namespace octrace {
namespace {

// The name the messages give the arrays: manifestPathFor("rays") is "rays.json", so a message
// about the manifest and one about the rows name the same pair.
const char* const kRaysName = "rays";
const char* const kManifestName = "rays.json";

// Runs `work`, turning whatever it throws into an Error with octrace's message, so that no
// internal exception type crosses the header (a caller catches one type). `function` names
// the call where the message alone would not say (out of memory, a foreign exception).
template <class Work>
auto translated(const char* function, Work&& work) -> decltype(work()) {
    try {
        return work();
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw Error(std::string(function) +
                    ": out of memory; use fewer rays or a machine with more memory");
    } catch (const std::exception& e) {
        throw Error(e.what());
    } catch (...) {
        throw Error(std::string(function) + ": an exception that is not a std::exception");
    }
}

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", v);
    return text;
}

// The command line's numberIn(lo, hi) for a field of an options struct (NaN is refused too).
void checkIn(const char* field, double v, double lo, double hi) {
    if (!(v >= lo && v <= hi))
        throw Error(std::string(field) + " " + number(v) + " is not in [" + number(lo) + ", " +
                    number(hi) + "]");
}

// What loading dropped, as `octrace rays` says it on stderr.
void noteDropped(const oct::Scene& scene, std::vector<std::string>& notes) {
    if (scene.report.totalDropped() > 0)
        notes.push_back("loading dropped " + std::to_string(scene.report.totalDropped()) +
                        " faces or points (see octrace info)");
}

oct::RaySetSpec raySpec(const RayOptions& o) {
    checkIn("RayOptions::count", double(o.count), 0, double(oct::kMaxSeededRays));
    checkIn("RayOptions::width", o.width, 1, oct::kMaxImageSide);
    checkIn("RayOptions::height", o.height, 1, oct::kMaxImageSide);
    if (!(std::isfinite(o.radius) && o.radius >= 0.0f))
        throw Error("RayOptions::radius " + number(o.radius) +
                    " is not a radius: give one > 0, or 0 for octrace's rule");
    oct::RaySetSpec spec;
    spec.count = o.count;
    spec.seed = o.seed;
    // `octrace rays`' camera: its --size, the framing and light of the defaults.
    spec.camera.width = o.width;
    spec.camera.height = o.height;
    return spec;
}

oct::Require requireOf(const std::string& text) {
    if (text == "all") return oct::Require::All;
    if (text == "correct") return oct::Require::Correct;
    if (text == "watertight") return oct::Require::Watertight;
    throw Error("CertifyPolicy::require '" + text + "' is not correct, watertight or all");
}

oct::QueryKind queryOf(const std::string& text) {
    if (text == "closest") return oct::QueryKind::Closest;
    if (text == "anyhit") return oct::QueryKind::AnyHit;
    throw Error("CertifyPolicy::query '" + text + "' is not closest or anyhit");
}

// The policy as `octrace certify`'s options would set it, with their ranges
// (apps/policy_options.h).
oct::CertifyRunOptions runOptions(const CertifyPolicy& p) {
    checkIn("CertifyPolicy::tTolerance", p.tTolerance, 0, 1);
    checkIn("CertifyPolicy::edgeTolerance", p.edgeTolerance, 0, 1);
    checkIn("CertifyPolicy::grazingCos", p.grazingCos, 0, 1);
    checkIn("CertifyPolicy::maxAmbiguousRate", p.maxAmbiguousRate, 0, 1);
    if (p.maxRechecks < 1)
        throw Error("CertifyPolicy::maxRechecks 0: recheck at least 1 (UINT64_MAX: every one)");
    if (p.worstCount < 0)
        throw Error("CertifyPolicy::worstCount " + std::to_string(p.worstCount) +
                    " is negative: list 0 findings or more");
    oct::CertifyRunOptions o;
    o.policy.tTolerance = p.tTolerance;
    o.policy.edgeTolerance = p.edgeTolerance;
    o.policy.grazingCos = p.grazingCos;
    o.policy.maxAmbiguousRate = p.maxAmbiguousRate;
    o.policy.maxRechecks = p.maxRechecks;
    o.policy.worstCount = p.worstCount;
    o.require = requireOf(p.require);
    o.query.ownSets = queryOf(p.query);
    o.raysName = kRaysName;
    return o;
}

// The manifest text as readManifest reads a file's: the same size limit and the same fields.
oct::RayManifest manifestOf(const std::string& text) {
    if (text.size() > oct::kMaxManifestBytes)
        throw Error(std::string("ray manifest '") + kManifestName +
                    "': " + std::to_string(text.size()) + " bytes, more than a manifest holds (" +
                    oct::bytesText(oct::kMaxManifestBytes) +
                    "); pass the manifestJson makeRays gave with the rays");
    const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_discarded())
        throw Error(std::string("ray manifest '") + kManifestName +
                    "': not JSON; pass the manifestJson makeRays gave with the rays, or \"\" to "
                    "certify them as one set");
    return oct::manifestFromJson(j, kManifestName);
}

CertifyResult resultOf(oct::CertifyReport& rep) {
    CertifyResult r;
    const oct::Outcome outcome = rep.outcome();
    r.pass = outcome == oct::Outcome::Pass;
    r.outcome = oct::outcomeName(outcome);
    r.correct = oct::outcomeName(rep.result.correct(rep.policy.maxAmbiguousRate));
    r.watertight = oct::outcomeName(rep.result.watertight());
    r.summary = oct::humanSummary(rep);
    nlohmann::json j = oct::toJson(rep);
    j["baseline"] = nullptr;  // as `octrace certify --json` without --baseline: the same fields
    r.json = j.dump(2);
    r.classes = std::move(rep.result.rayClass);
    r.reasons = std::move(rep.result.rayReasons);
    r.leaks = std::move(rep.result.rayLeak);
    return r;
}

}  // namespace

std::vector<float> loadTriangles(const std::string& scenePath) {
    return translated("octrace::loadTriangles", [&] {
        const oct::Scene scene = oct::loadScene(scenePath);
        if (scene.kind != oct::PrimKind::Triangles)
            throw Error("octrace::loadTriangles: '" + scenePath +
                        "' is a point cloud (spheres, not triangles)");
        static_assert(sizeof(oct::Triangle) == 9 * sizeof(float), "nine packed floats");
        std::vector<float> out(scene.triangles.size() * 9);
        if (!out.empty()) std::memcpy(out.data(), scene.triangles.data(), out.size() * 4);
        return out;
    });
}

StandardRays makeRays(const std::string& scenePath, const RayOptions& options) {
    return translated("octrace::makeRays", [&] {
        oct::RaySetSpec spec = raySpec(options);  // before the scene is loaded, as the CLI
        oct::LoadOptions lo;
        lo.radius = options.radius;
        const oct::Scene scene = oct::loadScene(scenePath, lo);
        StandardRays out;
        noteDropped(scene, out.notes);
        try {
            spec.sets = oct::chooseRaySets(options.sets, scene, out.notes);
        } catch (const oct::RaySetChoiceError& e) {
            throw Error(std::string("RayOptions::sets: ") + e.what());
        }
        oct::StandardRays made = oct::makeStandardRays(
            scene, spec,
            "octrace::makeRays at " + std::to_string(options.width) + "x" +
                std::to_string(options.height) + ", count " + std::to_string(options.count),
            "use a smaller width and height (the camera and shadow sets hold a row per pixel "
            "each) or a smaller count");
        out.notes.insert(out.notes.end(), made.rays.notes.begin(), made.rays.notes.end());
        out.manifestJson = oct::toJson(made.manifest).dump(2) + "\n";  // R.json's bytes
        out.rays = std::move(made.rays.rays);
        return out;
    });
}

CertifyResult certify(const std::string& scenePath, const float* rays, uint64_t count,
                      const float* t, const int32_t* prim, const std::string& manifestJson,
                      const CertifyPolicy& policy) {
    return translated("octrace::certify", [&] {
        const oct::CertifyRunOptions ro = runOptions(policy);
        if (count > 0 && (!rays || !t))
            throw Error(std::string("octrace::certify: ") + (!rays ? "rays" : "t") +
                        " is null for " + std::to_string(count) +
                        " rays; give count x 8 ray floats and count distances");
        // About 96 bytes a row, as `octrace certify` estimates it (apps/cmd_certify.cpp): the
        // row, the hits, the reference's answers, the verdicts and the classifier's results.
        oct::checkMemory(oct::saturatingMul(count, 96),
                         "octrace::certify on " + std::to_string(count) + " rays",
                         "certify the rays in parts or on a machine with more memory");
        std::optional<oct::RayManifest> manifest;
        if (!manifestJson.empty()) manifest = manifestOf(manifestJson);
        // The scene as `octrace certify` loads it: with the radius the rays were made for.
        oct::LoadOptions lo;
        lo.radius = manifest && manifest->radius ? *manifest->radius : 0.0f;
        const oct::Scene scene = oct::loadScene(scenePath, lo);
        oct::HitArrays hits;
        hits.t.assign(t, t + count);
        hits.primIds = prim != nullptr;
        if (prim) hits.prim.assign(prim, prim + count);
        oct::CertifyRun run =
            oct::certifyRows(scene, std::vector<float>(rays, rays + 8 * count), hits, manifest, ro);
        run.report.hits = prim ? "t prim" : "t";
        return resultOf(run.report);
    });
}

}  // namespace octrace
