#include "apps/backend.h"

#include "cpu_ref/embree_tracer.h"
#include "cpu_ref/render_cpu.h"
#ifdef OCT_HAVE_CUDA
#include "gpu/cuda_backend.h"
#endif

namespace oct {

const char* backendName(Backend b) {
    switch (b) {
        case Backend::Embree:
            return "embree";
        case Backend::Cuda:
            return "cuda";
        case Backend::Cpu:
        default:
            return "cpu";
    }
}

Backend resolveBackend(const std::string& name, std::string& note) {
    if (name == "cpu") return Backend::Cpu;
    if (name == "embree") return Backend::Embree;
    if (name != "cuda" && name != "auto")
        throw std::runtime_error("unknown --backend '" + name + "': use cpu, embree, cuda or auto");
#ifdef OCT_HAVE_CUDA
    std::string why;
    bool present = cudaDevicePresent(why);
    if (name == "cuda") {
        if (!present) throw std::runtime_error("--backend cuda: " + why);
        return Backend::Cuda;
    }
    note = present ? "auto backend: cuda (" + why + ")" : "auto backend: cpu (" + why + ")";
    return present ? Backend::Cuda : Backend::Cpu;
#else
    if (name == "cuda")
        throw std::runtime_error(
            "--backend cuda: this octrace was built without CUDA (nvcc was not found at "
            "configure time); use --backend cpu");
    note = "auto backend: cpu (built without CUDA)";
    return Backend::Cpu;
#endif
}

namespace {

void countRays(const Film& film, FrameTiming& t) {
    t.primaryRays = film.pixelCount();
    t.shadowRays = 0;
    for (uint8_t s : film.shadow) t.shadowRays += s != kNoShadowRay;
}

}  // namespace

FrameTiming renderWith(Backend b, const FrameParams& p, const BuiltScene& scene, Film& film) {
    FrameTiming t;
    t.buildSeconds = scene.buildSeconds;
    if (b == Backend::Embree) {
        EmbreeTracer embree(*scene.scene);
        t.buildSeconds = embree.buildSeconds();
        film = Film(p.width, p.height);
        double start = omp_get_wtime();
        renderFrameCpu(p, embree.accel(), scene.prims(), film.view());
        t.frameSeconds = omp_get_wtime() - start;
#ifdef OCT_HAVE_CUDA
    } else if (b == Backend::Cuda) {
        t.frameSeconds = renderCuda(p, scene, film);
#endif
    } else {
        t.frameSeconds = renderCpu(p, scene, film);
    }
    countRays(film, t);
    return t;
}

double traceWith(Backend b, const BuiltScene& scene, RayBatchView batch) {
    if (b == Backend::Embree) {
        EmbreeTracer embree(*scene.scene);
        double start = omp_get_wtime();
        traceRaysCpu(embree.accel(), batch);
        return omp_get_wtime() - start;
    }
#ifdef OCT_HAVE_CUDA
    if (b == Backend::Cuda) return traceCuda(scene, batch);
#endif
    return traceCpu(scene, batch);
}

}  // namespace oct
