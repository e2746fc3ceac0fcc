#include "cpu_ref/bvh_backend.h"

#include "cpu_ref/render_cpu.h"

namespace oct {

BvhSceneTracer::BvhSceneTracer(const BuiltScene& scene)
    : prims_(scene.prims()), bvh_(*scene.scene) {}

std::vector<double> BvhSceneTracer::render(const FrameParams& frame, Film& film, int warmup,
                                           int repeats) {
    film = Film(frame.width, frameRows(frame));
    const FilmView fv = film.view();
    const BvhView view = bvh_.view();
    return timeFrames(warmup, repeats, [&] { renderFrameCpu(frame, view, prims_, fv); });
}

double BvhSceneTracer::trace(RayBatchView batch) {
    const BvhView view = bvh_.view();
    return timeFrames(0, 1, [&] { traceRaysCpu(view, batch); })[0];
}

namespace {

std::unique_ptr<SceneTracer> prepare(const BuiltScene& scene) {
    return std::make_unique<BvhSceneTracer>(scene);
}

}  // namespace

BackendDesc bvhBackend() {
    BackendDesc d;
    d.name = "bvh";
    d.summary = "a textbook scalar binary BVH (binned SAH), the compact layout's yardstick";
    d.usesLayouts = false;
    d.structure = "binary-bvh";
    d.trianglesOnly = true;
    d.available = &availableOnHost;
    d.prepare = &prepare;
    return d;
}

}  // namespace oct
