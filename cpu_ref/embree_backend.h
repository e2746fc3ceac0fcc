// The Embree backend: ground truth. Embree builds its own BVH (robust mode) over the scene and
// answers the kernel's hit queries; shading is the core kernel's.
#pragma once

#include "core/backend/backend.h"
#include "cpu_ref/embree_tracer.h"

namespace oct {

BackendDesc embreeBackend();
// BackendDesc::available of both Embree backends: always, linked in.
bool embreeAvailable(std::string& why);

// The backend's tracer, public so that validation can also ask Embree single occlusion queries
// (embree().accel() with anyHit) on the BVH it rendered the reference with.
class EmbreeSceneTracer : public SceneTracer {
public:
    // robust = false: Embree's default mode (the embree-fast backend).
    explicit EmbreeSceneTracer(const BuiltScene& scene, bool robust = true);
    double prepareSeconds() const override { return embree_.buildSeconds(); }
    std::vector<double> render(const FrameParams& frame, Film& film, int warmup = 0,
                               int repeats = 1) override;
    double trace(RayBatchView batch) override;
    const EmbreeTracer& embree() const { return embree_; }

private:
    PrimitivesView prims_;
    EmbreeTracer embree_;
};

}  // namespace oct
