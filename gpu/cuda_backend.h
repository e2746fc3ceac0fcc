// Host API of the CUDA backend; includes no CUDA header, so apps/ and tests compile with a plain
// C++ compiler. Errors are thrown as std::runtime_error subclasses with one-line messages.
#pragma once

#include <stdexcept>
#include <string>

#include "backends/backend.h"
#include "core/octree/built_scene.h"
#include "core/render/frame.h"
#include "core/render/kernel.h"

namespace oct {

class CudaError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// True when a CUDA device answers; `why` gets its name and compute capability, or the reason
// (no driver, no device) in one line. Never throws.
bool cudaDevicePresent(std::string& why);

// The backend's registry entry: the core kernel, one thread per pixel (or ray).
BackendDesc cudaBackend();

struct CudaTiming {
    double uploadSeconds = 0.0;
    double kernelSeconds = 0.0;  // median of the timed launches (CUDA events)
    double minKernelSeconds = 0.0;
    double maxKernelSeconds = 0.0;
    double downloadSeconds = 0.0;
};

// Uploads the scene and layout, launches the core per-pixel kernel (one thread per pixel)
// `warmup` + `repeats` times, reads the Film back. Returns the median kernel time in seconds.
double renderCuda(const FrameParams& p, const BuiltScene& scene, Film& film,
                  CudaTiming* timing = nullptr, int warmup = 1, int repeats = 1);
// One thread per ray; rays and results in host memory. Returns the kernel time in seconds.
double traceCuda(const BuiltScene& scene, RayBatchView batch);

}  // namespace oct
