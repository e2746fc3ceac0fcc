#include "cpu_ref/render_cpu.h"

namespace oct {

void setCpuThreads(int threads) {
    if (threads > 0) omp_set_num_threads(threads);
}

double renderCpu(const FrameParams& p, const BuiltScene& scene, Film& film) {
    film = Film(p.width, p.height);
    FilmView fv = film.view();
    double start = omp_get_wtime();
    visitView(scene, [&](const auto& view) { renderFrameCpu(p, view, scene.prims(), fv); });
    return omp_get_wtime() - start;
}

double traceCpu(const BuiltScene& scene, RayBatchView batch) {
    double start = omp_get_wtime();
    visitView(scene, [&](const auto& view) { traceRaysCpu(view, batch); });
    return omp_get_wtime() - start;
}

}  // namespace oct
