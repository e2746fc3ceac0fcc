// The launchers of the kernel behind one small interface: the OpenMP loop (cpu_ref/), Embree
// as ground truth (cpu_ref/) and CUDA (gpu/). A backend prepares a built scene once (Embree
// builds its BVH, CUDA uploads) and then renders frames and traces ray batches, timing each.
// The list of backends is backend_list.cpp; render, trace, validate and bench use it and
// nothing else to choose a launcher.
#pragma once

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

struct BackendDesc {
    const char* name;
    const char* summary;
    // False for a backend that traces with its own structure (Embree): it is given the scene
    // alone (bareScene) and the layout is ignored.
    bool usesLayouts;
    // The structure such a backend traces, as reports name it ("embree-bvh"); null otherwise.
    const char* structure;
    // True for a backend on an accelerator (CUDA): `auto` prefers it when available, and
    // bench records the device's description with the results.
    bool device;
    // True when it can run here; otherwise `why` says why not in one line. Never throws.
    bool (*available)(std::string& why);
    // Prepares the backend for `scene` (which must outlive the tracer).
    std::unique_ptr<SceneTracer> (*prepare)(const BuiltScene& scene);
};

// Every backend this build has, in list order.
const std::vector<BackendDesc>& backends();
// "cpu, embree, cuda" (those this build has).
std::string backendNames();
// The backend called `name`, or for "auto" the CUDA one when a device answers, else the CPU;
// `note` receives what auto chose and why. Throws std::runtime_error naming the value and the
// choices for an unknown name, and the reason for a backend that cannot run here.
const BackendDesc& resolveBackend(const std::string& name, std::string& note);

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
