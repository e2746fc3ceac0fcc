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
#include "tests/cpu_ref/standard_rays.h"
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

bool sameBits(const octtest::TracedHits& a, const octtest::TracedHits& b) {
    return a.t.size() == b.t.size() &&
           std::memcmp(a.t.data(), b.t.data(), a.t.size() * sizeof(float)) == 0 && a.prim == b.prim;
}

octtest::TracedHits traceUnder(HostIsa isa, SceneTracer& tracer, const std::vector<float>& rays) {
    EXPECT_TRUE(setHostIsa(isa));
    return octtest::traceAll(tracer, rays);
}

TEST_F(CpuIsa, Avx2EqualsBaselineBitForBit) {
    for (const char* mesh : {"teapot.obj", "cornell_box.obj", "spider.obj"}) {
        const Scene scene = loadScene(octtest::meshPath(mesh));
        const std::vector<float> rays = octtest::standardRays(scene);
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
            const octtest::TracedHits base = traceUnder(HostIsa::Baseline, *tracer, rays);
            const octtest::TracedHits avx2 = traceUnder(HostIsa::Avx2, *tracer, rays);
            EXPECT_TRUE(sameBits(base, avx2)) << mesh << ", " << name << ": " << rays.size() / 8
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
