// Test rays and their answers, for tests that compare two tracers of the same scene ray by ray
// (tests/cpu_ref).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "backends/backend_list.h"
#include "core/octree/built_scene.h"
#include "core/octree/layout_registry.h"
#include "validation/rays/ray_sets.h"

namespace octtest {

// The t and primitive of every ray (8 floats a row), as a tracer answers them.
struct TracedHits {
    std::vector<float> t;
    std::vector<int32_t> prim;
};

inline TracedHits traceAll(oct::SceneTracer& tracer, const std::vector<float>& rays) {
    TracedHits h;
    const uint64_t n = rays.size() / 8;
    h.t.resize(n);
    h.prim.resize(n);
    tracer.trace({rays.data(), h.t.data(), h.prim.data(), n});
    return h;
}

// Every standard set a scene can make, a few thousand rows each, the shadow set's camera hits
// from the host kernel on the compact layout.
inline std::vector<float> standardRays(const oct::Scene& scene) {
    oct::RaySetSpec spec;
    for (const oct::RaySetDesc& k : oct::standardRaySets())
        if (oct::raySetMisfit(k, scene).empty()) spec.sets.push_back(&k);
    const std::vector<std::string> why = oct::raySetsUnavailable(scene, spec.sets);
    std::vector<const oct::RaySetDesc*> usable;
    for (size_t i = 0; i < spec.sets.size(); ++i)
        if (why[i].empty()) usable.push_back(spec.sets[i]);
    spec.sets = usable;
    spec.count = 3000;
    spec.camera.width = spec.camera.height = 64;
    const oct::BuiltScene built =
        oct::buildScene(scene, oct::findLayout("compact"), oct::LayoutOptions{});
    const std::unique_ptr<oct::SceneTracer> host = oct::hostBackend().prepare(built);
    return oct::makeRaySet(scene, spec, [&](oct::RayBatchView b) { host->trace(b); }).rays;
}

}  // namespace octtest
