// The one list of backends. Adding one: implement SceneTracer (core/backend/backend.h) in its
// own folder, declare a function returning its BackendDesc there, and add it below.
#include "backends/backend_list.h"

#include <stdexcept>

#include "cpu_ref/bvh_backend.h"
#include "cpu_ref/cpu_backend.h"
#include "cpu_ref/embree_backend.h"
#include "cpu_ref/embree_fast_backend.h"
#ifdef OCT_HAVE_CUDA
#include "gpu/cuda_backend.h"
#endif

namespace oct {

const std::vector<BackendDesc>& backends() {
    static const std::vector<BackendDesc> all = {
        cpuBackend(),  embreeBackend(), embreeFastBackend(), bvhBackend(),
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

const BackendDesc* findBackend(const std::string& name) {
    for (const BackendDesc& b : backends())
        if (name == b.name) return &b;
    return nullptr;
}

const BackendDesc& hostBackend() {
    static const BackendDesc& host = *findBackend("cpu");
    return host;
}

const BackendDesc& referenceBackend() {
    for (const BackendDesc& b : backends())
        if (b.reference) return b;
    throw std::logic_error("the backend list has no reference backend");
}

const BackendDesc& resolveBackend(const std::string& name, std::string& note) {
    if (name == "auto") {
        // An accelerator when one answers (the kernel is the same), else the CPU.
        const BackendDesc& cpu = hostBackend();
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
    const BackendDesc* b = findBackend(name);
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

}  // namespace oct
