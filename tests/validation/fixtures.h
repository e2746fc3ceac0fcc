// Shared helpers of the validation tests: scenes, CPU tracers for every layout, and the
// deliberate corruptions of the fault-injection tests.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "backends/backend_list.h"
#include "core/octree/built_scene.h"
#include "core/scene/grid_cloud.h"
#include "core/scene/load_scene.h"
#include "cpu_ref/render_cpu.h"
#include "tests/paths.h"
#include "validation/validate.h"

namespace octtest {

// Built layouts kept alive for the tracers' callables.
struct CpuTracers {
    std::vector<std::unique_ptr<oct::BuiltScene>> built;
    std::vector<oct::TracerUnderTest> tracers;
    const oct::Octree* canonical = nullptr;
};

// The named layouts (default: every layout of the registry) on the CPU.
inline CpuTracers cpuTracers(const oct::Scene& scene, const std::vector<std::string>& names = {}) {
    CpuTracers t;
    std::vector<const oct::LayoutDesc*> chosen;
    for (const std::string& n : names) chosen.push_back(&oct::findLayout(n));
    if (names.empty())
        for (const oct::LayoutDesc& l : oct::layouts()) chosen.push_back(&l);
    for (const oct::LayoutDesc* l : chosen) {
        t.built.push_back(
            std::make_unique<oct::BuiltScene>(oct::buildScene(scene, *l, oct::LayoutOptions{})));
        const oct::BuiltScene* bs = t.built.back().get();
        if (bs->tree) t.canonical = bs->tree.get();
        oct::NodeLookupFn lookup;  // the structural check, for layouts with an octree
        if (l->usesOctree) lookup = [bs](uint64_t key) { return bs->lookupNode(key); };
        t.tracers.push_back(
            {l->name, oct::hostBackend().name,
             [bs](const oct::FrameParams& p, oct::Film& f) {
                 oct::renderWith(oct::hostBackend(), *bs, p, f);
             },
             [bs](oct::RayBatchView b) { oct::traceWith(oct::hostBackend(), *bs, b); }, lookup});
    }
    return t;
}

inline oct::ValidateOptions smallOptions(int side = 64, uint64_t rays = 3000) {
    oct::ValidateOptions o;
    o.camera.width = o.camera.height = side;
    o.rays = rays;
    o.seed = 7;
    return o;
}

// A tracer under test from any accelerator view (a layout's, or one corrupted on purpose) on the
// OpenMP launcher, without a structural lookup.
template <class Accel>
oct::TracerUnderTest cpuTracer(const std::string& name, const Accel& accel,
                               const oct::PrimitivesView& prims) {
    return {name, "cpu",
            [accel, prims](const oct::FrameParams& p, oct::Film& f) {
                f = oct::Film(p.width, p.height);
                oct::renderFrameCpu(p, accel, prims, f.view());
            },
            [accel](oct::RayBatchView b) { oct::traceRaysCpu(accel, b); }, oct::NodeLookupFn{}};
}

}  // namespace octtest
