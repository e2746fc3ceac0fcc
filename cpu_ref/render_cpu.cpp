#include "cpu_ref/render_cpu.h"

namespace oct {

void setCpuThreads(int threads) {
    if (threads > 0) omp_set_num_threads(threads);
}

double renderCpu(const FrameParams& p, const BuiltScene& scene, Film& film) {
    film = Film(p.width, p.height);
    const FilmView fv = film.view();
    const PrimitivesView prims = scene.prims();
    return timeFrames(0, 1, [&] {
        scene.visit([&](const auto& view) { renderFrameCpu(p, view, prims, fv); });
    })[0];
}

double traceCpu(const BuiltScene& scene, RayBatchView batch) {
    return timeFrames(
        0, 1, [&] { scene.visit([&](const auto& view) { traceRaysCpu(view, batch); }); })[0];
}

}  // namespace oct
