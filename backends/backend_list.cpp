// The one list of backends. Adding one: implement SceneTracer in its own folder, declare its
// BackendDesc there, and add it below.
#include <stdexcept>

#include "backends/backend.h"
#include "cpu_ref/cpu_backend.h"
#include "cpu_ref/embree_backend.h"
#include "cpu_ref/embree_fast_backend.h"
#ifdef OCT_HAVE_CUDA
#include "gpu/cuda_backend.h"
#endif

namespace oct {

const std::vector<BackendDesc>& backends() {
    static const std::vector<BackendDesc> all = {
        cpuBackend(),
        embreeBackend(),
        embreeFastBackend(),
#ifdef OCT_HAVE_CUDA
        cudaBackend(),
#endif
    };
    return all;
}

std::string backendNames() {
    std::string s;
    for (const BackendDesc& b : backends()) s += (s.empty() ? "" : ", ") + std::string(b.name);
    return s;
}

namespace {

const BackendDesc* lookup(const std::string& name) {
    for (const BackendDesc& b : backends())
        if (name == b.name) return &b;
    return nullptr;
}

}  // namespace

const BackendDesc& resolveBackend(const std::string& name, std::string& note) {
    if (name == "auto") {
        // An accelerator when one answers (the kernel is the same), else the CPU.
        const BackendDesc& cpu = *lookup("cpu");
        for (const BackendDesc& b : backends()) {
            if (!b.device) continue;
            std::string why;
            const bool present = b.available(why);
            note = std::string("auto backend: ") + (present ? b.name : cpu.name) + " (" + why + ")";
            return present ? b : cpu;
        }
        note = "auto backend: cpu (built without CUDA)";
        return cpu;
    }
    const BackendDesc* b = lookup(name);
    if (!b) {
        if (name == "cuda")
            throw std::runtime_error(
                "--backend cuda: this octrace was built without CUDA (nvcc was not found at "
                "configure time); use --backend cpu");
        throw std::runtime_error("unknown --backend '" + name + "': use " + backendNames() +
                                 " or auto");
    }
    std::string why;
    if (!b->available(why)) throw std::runtime_error("--backend " + name + ": " + why);
    return *b;
}

void countRays(const Film& film, uint64_t& primary, uint64_t& shadow) {
    primary = film.pixelCount();
    shadow = 0;
    for (uint8_t s : film.shadow) shadow += s != kNoShadowRay;
}

FrameRun renderWith(const BackendDesc& backend, const BuiltScene& scene, const FrameParams& frame,
                    Film& film, int warmup, int repeats) {
    std::unique_ptr<SceneTracer> tracer = backend.prepare(scene);
    FrameRun run;
    run.prepareSeconds = tracer->prepareSeconds();
    run.buildSeconds = backend.usesLayouts ? scene.buildSeconds() : run.prepareSeconds;
    run.frameSeconds = tracer->render(frame, film, warmup, repeats);
    countRays(film, run.primaryRays, run.shadowRays);
    return run;
}

double traceWith(const BackendDesc& backend, const BuiltScene& scene, RayBatchView batch) {
    return backend.prepare(scene)->trace(batch);
}

}  // namespace oct
