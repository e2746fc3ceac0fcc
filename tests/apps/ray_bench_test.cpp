// The ray bench's hit comparison in process (bench/sweep/ray_bench.h): cases built here with
// chosen hits, so what counts as another primitive or another t, and which cases must agree
// exactly, are checked without tracing. tests/apps/bench_rays_cli_test.cpp runs the command.
#include "bench/sweep/ray_bench.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "backends/backend_list.h"
#include "core/octree/layout_registry.h"

namespace oct {
namespace {

RayBenchCase withHits(const LayoutDesc* layout, const BackendDesc& backend, std::vector<float> t,
                      std::vector<int32_t> prim) {
    RayBenchCase c;
    c.layout = layout;
    c.backend = &backend;
    c.t = std::move(t);
    c.prim = std::move(prim);
    return c;
}

const LayoutDesc* octreeLayout(int nth) {
    for (const LayoutDesc& l : layouts())
        if (l.usesOctree && nth-- == 0) return &l;
    return nullptr;
}

TEST(RayBenchHits, AnotherPrimitiveAndAnotherTAreCountedApart) {
    const RayBenchCase a =
        withHits(octreeLayout(0), hostBackend(), {1.0f, 2.0f, INFINITY, 4.0f}, {0, 1, -1, 3});
    // Ray 0: the same; ray 1: another t; ray 2: a hit against a miss; ray 3: another primitive.
    const RayBenchCase b = withHits(octreeLayout(1), hostBackend(),
                                    {1.0f, std::nextafter(2.0f, 3.0f), 5.0f, 4.0f}, {0, 1, 7, 2});
    const HitAgreement h = compareHits(b, a, 4);
    EXPECT_EQ(h.otherPrim, 2u);
    EXPECT_EQ(h.otherT, 1u);
    EXPECT_NEAR(h.maxRelativeDt, (std::nextafter(2.0f, 3.0f) - 2.0f) / 2.0, 1e-12);
    EXPECT_FALSE(h.exact());
    EXPECT_TRUE(compareHits(a, a, 4).exact());
}

// Our layouts on the compared case's backend must agree exactly; Embree is only reported.
TEST(RayBenchHits, OnlyTheComparedBackendsLayoutsMustAgree) {
    RayBenchResult r;
    r.rays = 2;
    r.cases.push_back(withHits(octreeLayout(0), hostBackend(), {1.0f, 2.0f}, {0, 1}));
    r.cases.push_back(withHits(octreeLayout(1), hostBackend(), {1.0f, 2.0f}, {0, 1}));
    r.cases.push_back(withHits(nullptr, referenceBackend(), {1.5f, 2.0f}, {4, 1}));
    for (RayBenchCase& c : r.cases) c.agreement = compareHits(c, r.cases[0], r.rays);
    EXPECT_TRUE(disagreeingCases(r).empty()) << "Embree's other primitive is reported only";
    EXPECT_EQ(r.cases[2].agreement.otherPrim, 1u);

    r.cases[1].prim[1] = 5;  // one layout answers another primitive on one ray
    r.cases[1].agreement = compareHits(r.cases[1], r.cases[0], r.rays);
    const std::vector<const RayBenchCase*> bad = disagreeingCases(r);
    ASSERT_EQ(bad.size(), 1u);
    EXPECT_EQ(bad[0], &r.cases[1]);
}

}  // namespace
}  // namespace oct
