#include "validation/validate.h"

#include <chrono>

#include "cpu_ref/embree_backend.h"

namespace oct {
namespace {

double since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

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
    return (!replication || replication->passes()) && (!boxContract || boxContract->passes());
}

ValidationReport validateScene(const Scene& scene, const std::vector<TracerUnderTest>& tracers,
                               const Octree* canonical, const ValidateOptions& o) {
    auto start = std::chrono::steady_clock::now();
    ValidationReport rep;
    rep.scene = scene.name;
    rep.kind = scene.kind;
    rep.primitives = scene.primitiveCount();
    rep.policy = o.policy;
    rep.seed = o.seed;

    HitClassifier classifier(scene, o.policy);
    rep.extent = classifier.extent();
    FrameParams frame = makeFrame(scene.bounds(), o.camera);
    // The inside view (validate.h): eye and light at the box's centre, the light 1% of the
    // extent above the eye so shadow rays do not retrace the primary rays exactly.
    CameraOptions insideCamera = o.camera;
    const Vec3 centre = scene.bounds().center();
    const float lift = float(0.01 * sceneExtent(scene));
    insideCamera.eye = centre;
    insideCamera.target = centre + Vec3{0.0f, 0.0f, 1.0f};
    insideCamera.light = centre + Vec3{0.0f, lift, 0.0f};
    const FrameParams frameInside = makeFrame(scene.bounds(), insideCamera);
    rep.width = frame.width;
    rep.height = frame.height;
    const RaySet rays = makeValidationRays(scene, o.rays, o.seed);
    rep.rayCount = rays.count();
    rep.raySets = rays.sets;

    // The reference: Embree (robust mode) through the same per-pixel kernel.
    auto refStart = std::chrono::steady_clock::now();
    const BuiltScene bare = bareScene(scene);
    EmbreeSceneTracer embree(bare);
    Film refFilm;
    embree.render(frame, refFilm);
    Film refInside;
    if (o.lightInside) embree.render(frameInside, refInside);
    HitArrays ref;
    ref.t.resize(rays.count());
    ref.prim.resize(rays.count());
    embree.trace({rays.rays.data(), ref.t.data(), ref.prim.data(), rays.count()});
    rep.referenceSeconds = since(refStart);
    OcclusionQuery occluded = [&embree](const Ray& r) {
        TraceCost cost = {0, 0};
        return anyHit(embree.embree().accel(), r, cost);
    };

    for (const TracerUnderTest& t : tracers) {
        RunReport run;
        run.layout = t.layout;
        run.backend = t.backend;
        auto t0 = std::chrono::steady_clock::now();
        Film film;
        t.render(frame, film);
        run.renderSeconds = since(t0);
        // Generate our hits, then certify them: the same code as `octrace certify`.
        HitArrays ours;
        ours.t.resize(rays.count());
        ours.prim.resize(rays.count());
        t0 = std::chrono::steady_clock::now();
        if (rays.count() > 0)
            t.trace({rays.rays.data(), ours.t.data(), ours.prim.data(), rays.count()});
        run.traceSeconds = since(t0);
        t0 = std::chrono::steady_clock::now();
        run.film = validateFilm(classifier, frame, film, refFilm, occluded);
        if (o.lightInside) {
            Film inside;
            t.render(frameInside, inside);
            run.lightInside = validateFilm(classifier, frameInside, inside, refInside, occluded);
        }
        if (t.lookup && canonical) run.structure = checkLayoutStructure(*canonical, t.lookup);
        run.rays = certifyRays(classifier, rays, ours, ref);
        run.checkSeconds = since(t0);
        rep.runs.push_back(std::move(run));
    }
    if (o.replication && canonical) rep.replication = checkReplication(scene, *canonical);
    if (o.boxContractRays > 0 && canonical)
        rep.boxContract = checkBoxContract(*canonical, o.boxContractRays, o.seed);
    rep.seconds = since(start);
    return rep;
}

}  // namespace oct
