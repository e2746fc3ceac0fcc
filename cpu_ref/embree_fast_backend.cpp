#include "cpu_ref/embree_fast_backend.h"

#include "cpu_ref/embree_backend.h"

namespace oct {
namespace {

std::unique_ptr<SceneTracer> prepare(const BuiltScene& scene) {
    return std::make_unique<EmbreeSceneTracer>(scene, /*robust=*/false);
}

}  // namespace

BackendDesc embreeFastBackend() {
    BackendDesc d;
    d.name = "embree-fast";
    d.summary = "Embree in its default (non-robust) mode: a third-party tracer to certify";
    d.usesLayouts = false;
    d.structure = "embree-bvh-fast";
    d.available = &embreeAvailable;
    d.prepare = &prepare;
    return d;
}

}  // namespace oct
