// Which launcher runs the kernel: the OpenMP loop, Embree (ground truth) or CUDA. `auto` picks
// CUDA when this build has it and a device answers, else the CPU, and says which.
#pragma once

#include <string>

#include "core/octree/accel.h"
#include "core/render/frame.h"
#include "core/render/kernel.h"

namespace oct {

enum class Backend { Cpu, Embree, Cuda };

const char* backendName(Backend b);
// Resolves "cpu", "embree", "cuda", "auto". For "cuda" without a usable device, or in a build
// without CUDA, throws with a one-line reason. `note` receives what auto chose and why.
Backend resolveBackend(const std::string& name, std::string& note);

struct FrameTiming {
    double buildSeconds = 0.0;  // acceleration structure (ours or Embree's)
    double frameSeconds = 0.0;  // tracing and shading the frame
    uint64_t primaryRays = 0;
    uint64_t shadowRays = 0;
};

// Renders with the chosen backend. For Embree, `scene.layout` is ignored (Embree builds its own
// BVH) and the build time is Embree's.
FrameTiming renderWith(Backend b, const FrameParams& p, const BuiltScene& scene, Film& film);
// Traces a ray batch (host memory) with the chosen backend; returns seconds.
double traceWith(Backend b, const BuiltScene& scene, RayBatchView batch);

}  // namespace oct
