// The host's ray loop runs the kernel compiled twice, for the baseline x86-64 and for AVX2
// (cpu_ref/render_cpu.h, HostIsa), and picks one at run time. Both must give the same bits: the
// same t and primitive for every ray of every standard set, for every layout and for the bvh
// backend, which runs through the same loop (seen failing with FMA contraction allowed in the
// AVX2 copy: 7,617 of the teapot's rays differed). Skipped on a CPU without AVX2 (there is then
// one copy to run).
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "backends/backend_list.h"
#include "core/octree/built_scene.h"
#include "core/octree/layout_registry.h"
#include "core/scene/load_scene.h"
#include "cpu_ref/bvh_backend.h"
#include "cpu_ref/render_cpu.h"
#include "tests/paths.h"
#include "validation/rays/ray_sets.h"

namespace oct {
namespace {

// Restores the ISA the process chose, whatever a test set.
class CpuIsa : public ::testing::Test {
protected:
    void SetUp() override {
        chosen_ = hostIsa();
        if (!setHostIsa(HostIsa::Avx2)) GTEST_SKIP() << "this CPU has no AVX2: one copy runs";
    }
    void TearDown() override { setHostIsa(chosen_); }
    HostIsa chosen_ = HostIsa::Baseline;
};

struct Answers {
    std::vector<float> t;
    std::vector<int32_t> prim;
    bool operator==(const Answers& o) const {
        return t.size() == o.t.size() &&
               std::memcmp(t.data(), o.t.data(), t.size() * sizeof(float)) == 0 && prim == o.prim;
    }
};

Answers traceUnder(HostIsa isa, SceneTracer& tracer, const std::vector<float>& rays) {
    EXPECT_TRUE(setHostIsa(isa));
    Answers a;
    const uint64_t n = rays.size() / 8;
    a.t.resize(n);
    a.prim.resize(n);
    tracer.trace({rays.data(), a.t.data(), a.prim.data(), n});
    return a;
}

// Every standard set the scene can make, a few thousand rows each.
std::vector<float> raysFor(const Scene& scene) {
    RaySetSpec spec;
    for (const RaySetDesc& k : standardRaySets())
        if (raySetMisfit(k, scene).empty()) spec.sets.push_back(&k);
    const std::vector<std::string> why = raySetsUnavailable(scene, spec.sets);
    std::vector<const RaySetDesc*> usable;
    for (size_t i = 0; i < spec.sets.size(); ++i)
        if (why[i].empty()) usable.push_back(spec.sets[i]);
    spec.sets = usable;
    spec.count = 3000;
    spec.camera.width = spec.camera.height = 64;
    const BuiltScene built = buildScene(scene, findLayout("compact"), LayoutOptions{});
    const std::unique_ptr<SceneTracer> host = hostBackend().prepare(built);
    return makeRaySet(scene, spec, [&](RayBatchView b) { host->trace(b); }).rays;
}

TEST_F(CpuIsa, Avx2EqualsBaselineBitForBit) {
    for (const char* mesh : {"teapot.obj", "cornell_box.obj", "spider.obj"}) {
        const Scene scene = loadScene(octtest::meshPath(mesh));
        const std::vector<float> rays = raysFor(scene);
        std::vector<std::pair<std::string, std::unique_ptr<SceneTracer>>> tracers;
        std::vector<BuiltScene> built;
        built.reserve(5);  // the tracers hold references into it: no reallocation
        for (const char* layout : {"linear", "hash", "compact", "exhaustive"}) {
            built.push_back(buildScene(scene, findLayout(layout), LayoutOptions{}));
            tracers.emplace_back(layout, hostBackend().prepare(built.back()));
        }
        built.push_back(bareScene(scene));
        tracers.emplace_back("bvh", findBackend(bvhBackend().name)->prepare(built.back()));
        for (auto& [name, tracer] : tracers) {
            const Answers base = traceUnder(HostIsa::Baseline, *tracer, rays);
            const Answers avx2 = traceUnder(HostIsa::Avx2, *tracer, rays);
            EXPECT_TRUE(base == avx2) << mesh << ", " << name << ": " << rays.size() / 8
                                      << " rays answered differently under AVX2";
        }
    }
}

// OCTRACE_HOST_ISA=baseline is the user's way to run the baseline copy; an ISA the CPU lacks
// is refused without changing the choice.
TEST_F(CpuIsa, TheChoiceIsKeptAndNamed) {
    EXPECT_TRUE(setHostIsa(HostIsa::Baseline));
    EXPECT_EQ(hostIsa(), HostIsa::Baseline);
    EXPECT_STREQ(hostIsaName(hostIsa()), "baseline");
    EXPECT_TRUE(setHostIsa(HostIsa::Avx2));
    EXPECT_STREQ(hostIsaName(hostIsa()), "avx2");
}

}  // namespace
}  // namespace oct
