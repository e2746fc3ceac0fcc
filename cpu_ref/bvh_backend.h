// The bvh backend: a textbook scalar binary BVH (binary_bvh.h) of its own, built on the host
// with binned SAH and traced one ray at a time in an OpenMP loop like the host backend, with
// the octree kernel's triangle test and nearest-hit rule. It is the yardstick of
// docs/PERFORMANCE.md's target "compact ≤ 1× a scalar binary BVH": the structure most ray
// tracers start from, written the way a textbook writes it. Triangle meshes only.
#pragma once

#include "core/backend/backend.h"
#include "cpu_ref/binary_bvh.h"

namespace oct {

BackendDesc bvhBackend();

class BvhSceneTracer : public SceneTracer {
public:
    // Builds the BVH over scene's triangles; throws BvhError for a point cloud.
    explicit BvhSceneTracer(const BuiltScene& scene);
    double prepareSeconds() const override { return bvh_.buildSeconds(); }
    std::vector<double> render(const FrameParams& frame, Film& film, int warmup = 0,
                               int repeats = 1) override;
    double trace(RayBatchView batch) override;
    const BinaryBvh& bvh() const { return bvh_; }

private:
    PrimitivesView prims_;
    BinaryBvh bvh_;
};

}  // namespace oct
