// The backend interface: what a launcher of the kernel (OpenMP, Embree, CUDA) offers the rest of
// octrace. A backend prepares a built scene once (Embree builds its BVH, CUDA uploads) and then
// renders frames and traces ray batches, timing each. Plain data and a contract: the launchers
// (cpu_ref/, gpu/) implement it, and the one list of them is backends/backend_list.h.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/octree/built_scene.h"
#include "core/render/frame.h"
#include "core/render/kernel.h"

namespace oct {

// One backend prepared for one built scene. Host-only (the kernels see none of this).
class SceneTracer {
public:
    virtual ~SceneTracer() = default;
    // Seconds the preparation took: Embree's BVH build, the CUDA upload; 0 for the CPU.
    virtual double prepareSeconds() const = 0;
    // Renders `frame` warmup (untimed) + repeats (timed, at least 1) times into `film`, which
    // it sizes; returns the timed frames' seconds (CUDA: kernel time by events).
    virtual std::vector<double> render(const FrameParams& frame, Film& film, int warmup = 0,
                                       int repeats = 1) = 0;
    // Closest hits of a ray batch in host memory; returns the seconds tracing took.
    virtual double trace(RayBatchView batch) = 0;
};

// A backend's entry in the list. Fill it field by field (see cpu_ref/cpu_backend.cpp).
struct BackendDesc {
    const char* name = nullptr;     // --backend NAME
    const char* summary = nullptr;  // one line for help texts and `octrace list`
    // False for a backend that traces with its own structure (Embree): it is given the scene
    // alone (bareScene) and the layout is ignored.
    bool usesLayouts = true;
    // The structure such a backend traces, as reports name it ("embree-bvh"); null otherwise.
    const char* structure = nullptr;
    // True for a backend on an accelerator (CUDA): `auto` prefers it when available, and
    // bench records the device's description with the results.
    bool device = false;
    // True for the ground truth every check compares with (Embree, robust mode): exactly one
    // backend of the list.
    bool reference = false;
    // True for a backend whose structure holds triangles only (the scalar binary BVH): its
    // prepare refuses a point cloud with one line, and bench --rays leaves it out of its
    // default cases on one.
    bool trianglesOnly = false;
    // True when it can run here; otherwise `why` says why not in one line. Never throws.
    bool (*available)(std::string& why) = nullptr;
    // Prepares the backend for `scene` (which must outlive the tracer).
    std::unique_ptr<SceneTracer> (*prepare)(const BuiltScene& scene) = nullptr;
};

// What a frame rendered through a backend took.
struct FrameRun {
    double buildSeconds = 0.0;         // the structure traced: ours (octree + layout) or Embree's
    double prepareSeconds = 0.0;       // backend preparation (Embree's build, CUDA upload)
    std::vector<double> frameSeconds;  // the timed frames
    uint64_t primaryRays = 0;
    uint64_t shadowRays = 0;
};

// What `backend` traces with `layout`: the layout's name, or the backend's own structure.
inline const char* tracedStructure(const BackendDesc& backend, const LayoutDesc& layout) {
    return backend.usesLayouts ? layout.name : backend.structure;
}

// Prepares `backend` for `scene` and renders: the usual one-shot call of render and validate.
FrameRun renderWith(const BackendDesc& backend, const BuiltScene& scene, const FrameParams& frame,
                    Film& film, int warmup = 0, int repeats = 1);
// Prepares and traces; returns the tracing seconds.
double traceWith(const BackendDesc& backend, const BuiltScene& scene, RayBatchView batch);

// Primary and shadow rays a rendered Film cast.
void countRays(const Film& film, uint64_t& primary, uint64_t& shadow);

}  // namespace oct
