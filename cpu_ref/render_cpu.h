// The OpenMP launcher: a parallel loop over pixels (or rays) calling the core kernel, nothing
// else. Embree's ground truth runs through the same loops with its own accelerator.
#pragma once

#include <omp.h>

#include <vector>

#include "core/octree/built_scene.h"
#include "core/render/frame.h"
#include "core/render/kernel.h"

namespace oct {

// Threads for the OpenMP loops: `threads` when positive, else OMP_NUM_THREADS / all cores.
void setCpuThreads(int threads);

template <class Accel>
void renderFrameCpu(const FrameParams& p, const Accel& accel, const PrimitivesView& prims,
                    FilmView film) {
    const int rows = frameRows(p);
#pragma omp parallel for schedule(dynamic, 4)
    for (int j = 0; j < rows; ++j) {
        const int y = imageRowOf(p, j);
        for (int x = 0; x < p.width; ++x) renderPixel(x, y, p, accel, prims, film);
    }
}

template <class Accel>
void traceRaysCpu(const Accel& accel, RayBatchView batch) {
    const int64_t n = static_cast<int64_t>(batch.count);
#pragma omp parallel for schedule(dynamic, 256)
    for (int64_t i = 0; i < n; ++i) traceRayAt(static_cast<uint64_t>(i), accel, batch);
}

// Runs frame() warmup times untimed, then max(1, repeats) times timed by the wall clock;
// returns the timed seconds. The one timing rule of the CPU backends (OpenMP and Embree).
template <class F>
std::vector<double> timeFrames(int warmup, int repeats, F&& frame) {
    for (int i = 0; i < warmup; ++i) frame();
    std::vector<double> times;
    for (int i = 0; i < (repeats < 1 ? 1 : repeats); ++i) {
        const double start = omp_get_wtime();
        frame();
        times.push_back(omp_get_wtime() - start);
    }
    return times;
}

}  // namespace oct
