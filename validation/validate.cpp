#include "validation/validate.h"

#include <algorithm>
#include <chrono>

#include "core/system/resources.h"
#include "cpu_ref/embree_backend.h"
#include "validation/checks/check.h"

namespace oct {
namespace {

double since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

bool RunReport::passes(double maxAmbiguousRate) const {
    for (const RunCheck* c : runChecks())
        if (!c->result(*this, maxAmbiguousRate).pass) return false;
    return true;
}

bool RunReport::complete(double maxAmbiguousRate) const {
    for (const RunCheck* c : runChecks())
        if (!c->result(*this, maxAmbiguousRate).complete) return false;
    return true;
}

bool ValidationReport::complete() const {
    for (const RunReport& r : runs)
        if (!r.complete(policy.maxAmbiguousRate)) return false;
    for (const SceneCheck* c : sceneChecks())
        if (!c->result(*this).complete) return false;
    return true;
}

uint64_t ValidationReport::wrong() const {
    uint64_t w = 0;
    for (const RunReport& r : runs) w += r.wrong();
    return w;
}

uint64_t ValidationReport::ambiguous() const {
    uint64_t a = 0;
    for (const RunReport& r : runs) a += r.ambiguous();
    return a;
}

bool ValidationReport::passes() const {
    for (const RunReport& r : runs)
        if (!r.passes(policy.maxAmbiguousRate)) return false;
    for (const SceneCheck* c : sceneChecks())
        if (!c->result(*this).pass) return false;
    return true;
}

CameraOptions insideViewCamera(const Scene& scene, const CameraOptions& camera) {
    CameraOptions inside = camera;
    const Vec3 centre = scene.bounds().center();
    const float lift = float(0.01 * sceneExtent(scene));
    inside.eye = centre;
    inside.target = centre + Vec3{0.0f, 0.0f, 1.0f};
    inside.light = centre + Vec3{0.0f, lift, 0.0f};
    return inside;
}

uint64_t validatePeakBytes(const ValidateOptions& o, size_t tracers) {
    const uint64_t pixels =
        uint64_t(std::max(o.camera.width, 0)) * uint64_t(std::max(o.camera.height, 0));
    const uint64_t views = o.lightInside ? 2 : 1;
    // FilmValidation keeps, per pixel, a primary and a shadow class and a float |dt|.
    const uint64_t keptPerPixel = 2 * sizeof(uint8_t) + sizeof(float);
    const uint64_t perPixel = views * (2 * kFilmBytesPerPixel + uint64_t(tracers) * keptPerPixel);
    const uint64_t perRay = 8 * sizeof(float) + 2 * (sizeof(float) + sizeof(int32_t));
    return saturatingAdd(saturatingMul(pixels, perPixel), saturatingMul(o.rays, perRay));
}

ValidationReport validateScene(const Scene& scene, const std::vector<TracerUnderTest>& tracers,
                               const Octree* canonical, const ValidateOptions& o) {
    auto start = std::chrono::steady_clock::now();
    HitClassifier classifier(scene, o.policy);
    ValidationReport rep;
    static_cast<JudgedScene&>(rep) = judgedScene(scene, classifier);
    rep.seed = o.seed;
    CheckInputs in(scene, canonical, o, classifier);
    in.frame = makeFrame(scene.bounds(), o.camera);
    in.frameInside = makeFrame(scene.bounds(), insideViewCamera(scene, o.camera));
    rep.width = in.frame.width;
    rep.height = in.frame.height;
    in.rays = makeValidationRays(scene, o.rays, o.seed);
    const uint64_t rayCount = in.rays.count();
    rep.rayCount = rayCount;
    rep.raySets = in.rays.sets;

    // The reference: Embree (robust mode) through the same per-pixel kernel.
    auto refStart = std::chrono::steady_clock::now();
    const BuiltScene bare = bareScene(scene);
    EmbreeSceneTracer embree(bare);
    const WorkShare::RenderCall embreeRender = [&embree](const FrameParams& p, Film& f) {
        embree.render(p, f);
    };
    const WorkShare::TraceCall embreeTrace = [&embree](RayBatchView b) { embree.trace(b); };
    auto render = [&o, &embreeRender](const FrameParams& p, Film& f) {
        o.share.render ? o.share.render(p, f, embreeRender) : embreeRender(p, f);
    };
    render(in.frame, in.reference);
    if (o.lightInside) render(in.frameInside, in.referenceInside);
    in.referenceHits.t.resize(rayCount);
    in.referenceHits.prim.resize(rayCount);
    const RayBatchView refBatch{in.rays.rays.data(), in.referenceHits.t.data(),
                                in.referenceHits.prim.data(), rayCount};
    o.share.trace ? o.share.trace(refBatch, embreeTrace) : embreeTrace(refBatch);
    rep.referenceSeconds = since(refStart);
    in.referenceOccluded = [&embree](const Ray& r) {
        TraceCost cost = {0, 0};
        return anyHit(embree.embree().accel(), r, cost);
    };

    for (const TracerUnderTest& t : tracers) {
        RunReport run;
        run.layout = t.layout;
        run.backend = t.backend;
        auto t0 = std::chrono::steady_clock::now();
        Film film;
        t.render(in.frame, film);
        run.renderSeconds = since(t0);
        // Our hits of the ray sets, certified by the rays check: the code of `octrace certify`.
        HitArrays ours;
        ours.t.resize(rayCount);
        ours.prim.resize(rayCount);
        t0 = std::chrono::steady_clock::now();
        if (rayCount > 0) t.trace({in.rays.rays.data(), ours.t.data(), ours.prim.data(), rayCount});
        run.traceSeconds = since(t0);
        t0 = std::chrono::steady_clock::now();
        for (const RunCheck* c : runChecks()) c->run(in, {t, film, ours}, run);
        run.checkSeconds = since(t0);
        rep.runs.push_back(std::move(run));
    }
    for (const SceneCheck* c : sceneChecks()) c->run(in, rep);
    rep.seconds = since(start);
    return rep;
}

}  // namespace oct
