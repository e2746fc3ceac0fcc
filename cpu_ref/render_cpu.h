// The OpenMP launcher: a parallel loop over pixels (or rays) calling the core kernel, nothing
// else. Embree's ground truth runs through the same loops with its own accelerator.
#pragma once

#include <omp.h>

#include <algorithm>
#include <string>
#include <vector>

#include "core/octree/built_scene.h"
#include "core/render/frame.h"
#include "core/render/kernel.h"

namespace oct {

// Threads for the OpenMP loops: `threads` when positive, else OMP_NUM_THREADS / all cores.
void setCpuThreads(int threads);

// BackendDesc::available of the backends that run these loops alone (cpu, bvh): always, on the
// host's OpenMP.
bool availableOnHost(std::string& why);

// The instruction set traceRaysCpu runs the kernel in. The same source, compiled twice: for
// the baseline x86-64 (SSE2) and, on CPUs that have it, for AVX2: VEX encoding (three-operand
// SSE, no register copies) and wider auto-vectorised loops, but no FMA and no reassociation
// (-ffp-contract=off, no fast-math), so every float operation and its rounding is the
// baseline's and the answers are the same bits (CpuIsa.Avx2EqualsBaselineBitForBit). Chosen
// once: AVX2 where __builtin_cpu_supports says so, unless OCTRACE_HOST_ISA=baseline.
enum class HostIsa { Baseline, Avx2 };
HostIsa hostIsa();
// For tests and A/B timing: returns false (and changes nothing) where the CPU lacks `isa`.
bool setHostIsa(HostIsa isa);
const char* hostIsaName(HostIsa isa);

// Each compiled copy is a whole loop over a range of rays with the kernel flattened
// into it (`flatten`: every call inlined), so no out-of-line kernel function is shared between
// the two copies: a header's inline function compiled once for AVX2 could otherwise be the one
// the linker keeps for every caller, and fault on a CPU without AVX2.
#if defined(__x86_64__) && defined(__GNUC__)
#define OCT_HOST_ISA_DISPATCH 1
#define OCT_FLAT_BASELINE __attribute__((flatten))
#define OCT_FLAT_AVX2 __attribute__((flatten, target("avx2")))
#else
#define OCT_FLAT_BASELINE
#endif

namespace cpu_detail {

template <class Accel>
void traceRange(int64_t from, int64_t to, const Accel& accel, RayBatchView batch) {
    for (int64_t i = from; i < to; ++i) traceRayAt(static_cast<uint64_t>(i), accel, batch);
}

template <class Accel>
OCT_FLAT_BASELINE void traceRangeBaseline(int64_t from, int64_t to, const Accel& accel,
                                          RayBatchView batch) {
    traceRange(from, to, accel, batch);
}
#if defined(OCT_HOST_ISA_DISPATCH)
template <class Accel>
OCT_FLAT_AVX2 void traceRangeAvx2(int64_t from, int64_t to, const Accel& accel,
                                  RayBatchView batch) {
    traceRange(from, to, accel, batch);
}
#endif

}  // namespace cpu_detail

// Frames run the baseline copy: under AVX2 the bunny's 512x512 frame took 62.2-63.1 ms against
// 61.2-61.3 ms (compact, one thread, three paired runs), while ray files gain 7-9 %.
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

// 256 rays a piece: the dynamic schedule's grain (rays cost what their geometry costs).
constexpr int64_t kRaysPerPiece = 256;

template <class Accel>
void traceRaysCpu(const Accel& accel, RayBatchView batch) {
    const int64_t n = static_cast<int64_t>(batch.count);
    const int64_t pieces = (n + kRaysPerPiece - 1) / kRaysPerPiece;
    const bool avx2 = hostIsa() == HostIsa::Avx2;
#pragma omp parallel for schedule(dynamic, 1)
    for (int64_t k = 0; k < pieces; ++k) {
        const int64_t from = k * kRaysPerPiece, to = std::min(n, from + kRaysPerPiece);
#if defined(OCT_HOST_ISA_DISPATCH)
        if (avx2) {
            cpu_detail::traceRangeAvx2(from, to, accel, batch);
            continue;
        }
#endif
        cpu_detail::traceRangeBaseline(from, to, accel, batch);
    }
    (void)avx2;
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
