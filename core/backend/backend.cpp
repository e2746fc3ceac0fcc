#include "core/backend/backend.h"

namespace oct {

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
