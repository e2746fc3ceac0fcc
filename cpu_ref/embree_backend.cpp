#include "cpu_ref/embree_backend.h"

#include "cpu_ref/render_cpu.h"

namespace oct {

EmbreeSceneTracer::EmbreeSceneTracer(const BuiltScene& scene, bool robust)
    : prims_(scene.prims()), embree_(*scene.scene, robust) {}

std::vector<double> EmbreeSceneTracer::render(const FrameParams& frame, Film& film, int warmup,
                                              int repeats) {
    film = Film(frame.width, frameRows(frame));
    const FilmView fv = film.view();
    return timeFrames(warmup, repeats, [&] { renderFrameCpu(frame, embree_.accel(), prims_, fv); });
}

double EmbreeSceneTracer::trace(RayBatchView batch) {
    return timeFrames(0, 1, [&] { traceRaysCpu(embree_.accel(), batch); })[0];
}

namespace {

std::unique_ptr<SceneTracer> prepare(const BuiltScene& scene) {
    return std::make_unique<EmbreeSceneTracer>(scene);
}

}  // namespace

bool embreeAvailable(std::string& why) {
    why = "Embree on the host";
    return true;
}

BackendDesc embreeBackend() {
    BackendDesc d;
    d.name = "embree";
    d.summary = "ground truth: Embree's robust BVH answers the kernel's hit queries";
    d.usesLayouts = false;
    d.structure = "embree-bvh";
    d.reference = true;
    d.available = &embreeAvailable;
    d.prepare = &prepare;
    return d;
}

}  // namespace oct
