// The box-test contract (validation/exact/box_contract.h): the kernel's slab tests keep it on a
// real octree, and the faults a slip would make in them (the mutations of scripts/mutations.txt)
// break it, each seen by validate's check.
#include "validation/exact/box_contract.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/octree/compact_octree.h"
#include "fixtures.h"

namespace {

using oct::Aabb;
using oct::RaySlabs;

const oct::Octree& teapotTree() {
    static const oct::Octree tree =
        oct::buildOctree(oct::loadScene(octtest::meshPath("teapot.obj")), oct::BuildParams{});
    return tree;
}

// The kernel's slab test with one change each, as in scripts/mutations.txt.
enum class Fault { TouchingMisses, NoFarScale, NoTmin };

template <Fault F>
bool faultyBox(const RaySlabs& s, const Aabb& b, float tmin, float tmax) {
    float t0 = F == Fault::NoTmin ? -INFINITY : tmin, t1 = tmax;
    for (int a = 0; a < 3; ++a) {
        const float o = s.org[a], inv = s.inv[a];
        if (std::isinf(inv)) {
            if (!(o >= b.lo[a] && o <= b.hi[a])) return false;
            continue;
        }
        const float ta = (b.lo[a] - o) * inv, tb = (b.hi[a] - o) * inv;
        t0 = std::fmax(t0, std::fmin(ta, tb));
        t1 =
            std::fmin(t1, std::fmax(ta, tb) * (F == Fault::NoFarScale ? 1.0f : oct::kSlabFarScale));
    }
    return F == Fault::TouchingMisses ? t0 < t1 : t0 <= t1;
}

uint32_t kernelChildren(const RaySlabs& s, const Aabb& parent, float tmin, float tmax) {
    float enter[8], exit[8];
    return oct::compact_detail::childIntervals(s, parent, tmin, tmax, enter, exit);
}

template <Fault F>
uint32_t faultyChildren(const RaySlabs& s, const Aabb& parent, float tmin, float tmax) {
    uint32_t mask = 0;
    for (int i = 0; i < 8; ++i)
        mask |= uint32_t(faultyBox<F>(s, oct::childBox(parent, i), tmin, tmax)) << i;
    return mask;
}

bool kernelBox(const RaySlabs& s, const Aabb& b, float tmin, float tmax) {
    float t0, t1;
    return oct::intersectBox(s, b, tmin, tmax, t0, t1);
}

TEST(BoxContract, KernelTestsKeepItOnTheTeapotsOctree) {
    const oct::BoxContractReport r = oct::checkBoxContract(teapotTree(), 20000, 1);
    for (const std::string& e : r.errors) ADD_FAILURE() << e;
    EXPECT_TRUE(r.passes());
    EXPECT_EQ(r.rays, 20000u);
    EXPECT_GT(r.tests, r.rays);  // internal nodes add their eight children
    // The hard cases occur by construction: touching rays (t0 == t1 exactly) and misses.
    EXPECT_GT(r.touching, r.rays / 20);
    EXPECT_GT(r.meets, r.tests / 10);
    EXPECT_LT(r.meets, r.tests);
}

TEST(BoxContract, SameSeedSameCounts) {
    const oct::BoxContractReport a = oct::checkBoxContract(teapotTree(), 4000, 7);
    const oct::BoxContractReport b = oct::checkBoxContract(teapotTree(), 4000, 7);
    EXPECT_EQ(a.tests, b.tests);
    EXPECT_EQ(a.meets, b.meets);
    EXPECT_EQ(a.touching, b.touching);
}

TEST(BoxContract, TouchingNotCountedIsCulled) {
    const oct::BoxContractReport r = oct::checkBoxContract(
        teapotTree(), 20000, 1, {faultyBox<Fault::TouchingMisses>, kernelChildren});
    EXPECT_FALSE(r.passes());
    EXPECT_GT(r.culled, 0u);
    EXPECT_EQ(r.loose, 0u);
    ASSERT_FALSE(r.errors.empty());
    EXPECT_NE(r.errors[0].find("culled a touching ray: intersectBox"), std::string::npos)
        << r.errors[0];
}

TEST(BoxContract, FarDistanceNotScaledIsCulledWhenGrazing) {
    const oct::BoxContractReport box = oct::checkBoxContract(
        teapotTree(), 20000, 1, {faultyBox<Fault::NoFarScale>, kernelChildren});
    EXPECT_GT(box.culled, 20u);  // 89 with this seed
    EXPECT_EQ(box.loose, 0u);
    const oct::BoxContractReport children = oct::checkBoxContract(
        teapotTree(), 20000, 1, {kernelBox, faultyChildren<Fault::NoFarScale>});
    EXPECT_GT(children.culled, 10u);  // 62
    ASSERT_FALSE(children.errors.empty());
    EXPECT_NE(children.errors[0].find("childIntervals"), std::string::npos) << children.errors[0];
}

TEST(BoxContract, IntervalNotStartingAtTminIsLoose) {
    const oct::BoxContractReport r =
        oct::checkBoxContract(teapotTree(), 20000, 1, {faultyBox<Fault::NoTmin>, kernelChildren});
    EXPECT_GT(r.loose, 0u);
    ASSERT_FALSE(r.errors.empty());
    EXPECT_NE(r.errors[0].find("accepted a ray that misses the grown box"), std::string::npos)
        << r.errors[0];
}

TEST(BoxContract, ValidateRunsItAndFailsOnIt) {
    const oct::Scene scene = oct::loadScene(octtest::meshPath("teapot.obj"));
    octtest::CpuTracers t = octtest::cpuTracers(scene, {"linear"});
    oct::ValidateOptions o = octtest::smallOptions();
    o.boxContractRays = 2000;
    const oct::ValidationReport rep = oct::validateScene(scene, t.tracers, t.canonical, o);
    ASSERT_TRUE(rep.boxContract.has_value());
    EXPECT_EQ(rep.boxContract->rays, 2000u);
    EXPECT_TRUE(rep.passes());
    oct::ValidationReport broken = rep;
    broken.boxContract->culled = 1;
    EXPECT_FALSE(broken.passes());
}

}  // namespace
