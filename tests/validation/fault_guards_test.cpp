// The faults scripts/mutation-check found that validate did not catch, each fed to validate as a
// deliberately broken layout or view (docs/VALIDATION.md, "Mutation testing"): every test
// first shows that the check as it was lets the fault through (or would hang), then that the
// strengthened check fails it.
#include <gtest/gtest.h>

#include <cmath>

#include "core/octree/built_scene.h"
#include "tests/validation/fixtures.h"
#include "validation/report/report.h"

namespace oct {
namespace {

using octtest::cpuTracer;
using octtest::meshPath;

// A hash octree that lost one leaf (its slot removed from its bucket, as a probe that stops
// early would lose it): a tiny frame and no ray set never reach it, the structural check does.
TEST(FaultGuards, HashLeafNoRayReachesFailsTheStructureCheck) {
    Scene scene = loadScene(meshPath("teapot.obj"));
    Octree tree = buildOctree(scene, BuildParams{});
    HashOctree hash = buildHash(tree);
    // The last non-empty leaf in breadth-first order: deep, small, off the 4x4 frame's rays.
    uint32_t leaf = 0;
    for (uint32_t k = 0; k < tree.nodes.size(); ++k)
        if (tree.nodes[k].nodeType() == NodeType::Leaf && tree.nodes[k].primCount > 0) leaf = k;
    const uint64_t key = tree.nodes[leaf].key, b = key % hash.bucketCount;
    OctreeNode* bucket = hash.slots.data() + b * hash.bucketSlots;
    uint32_t s = 0;
    while (bucket[s].key != key) ++s;
    for (; s + 1 < hash.bucketSlots; ++s) bucket[s] = bucket[s + 1];  // close the gap
    bucket[hash.bucketSlots - 1] = OctreeNode{};

    const PrimitivesView prims = primitivesView(scene);
    const HashOctreeView view = hashView(hash, tree, prims);
    TracerUnderTest bad = cpuTracer("hash-lost-leaf", view, prims);
    ValidateOptions o = octtest::smallOptions(4, 0);
    o.replication = false;
    o.lightInside = false;
    // Without the structural check the rays pass: the lost leaf is not on their way.
    ASSERT_TRUE(validateScene(scene, {bad}, &tree, o).passes());
    bad.lookup = [view](uint64_t k) { return lookupNode(view, k); };
    ValidationReport rep = validateScene(scene, {bad}, &tree, o);
    EXPECT_FALSE(rep.passes());
    ASSERT_TRUE(rep.runs[0].structure.has_value());
    EXPECT_EQ(rep.runs[0].structure->missing, 1u);
    ASSERT_FALSE(rep.runs[0].structure->errors.empty());
    EXPECT_NE(rep.runs[0].structure->errors[0].find("key " + std::to_string(key)),
              std::string::npos)
        << rep.runs[0].structure->errors[0];
    EXPECT_NE(humanSummary(rep).find("structure FAIL"), std::string::npos);
    EXPECT_EQ(toJson(rep)["runs"][0]["structure"]["missing"], 1u);
}

// Every layout's own view finds every canonical node: the check passes on sound layouts.
TEST(FaultGuards, SoundLayoutsPassTheStructureCheck) {
    for (const char* mesh : {"teapot.obj", "cornell_box.obj"}) {
        Scene scene = loadScene(meshPath(mesh));
        octtest::CpuTracers t = octtest::cpuTracers(scene);
        for (const TracerUnderTest& tr : t.tracers) {
            if (!tr.lookup) continue;
            StructureReport r = checkLayoutStructure(*t.canonical, tr.lookup);
            EXPECT_TRUE(r.passes()) << mesh << " " << tr.layout << ": " << r.failures();
            EXPECT_EQ(r.nodes, t.canonical->nodes.size());
        }
    }
}

// Records 1..8 overwritten by the root's (key 1, the root box, internal): a faulty conversion.
// The walk cannot cycle (a linear child lies after its parent), so its work stays within the
// array; the rays still find the right hits through the loose copies, and the structural
// check is what fails.
TEST(FaultGuards, CorruptLinearRecordsCannotCycleAndFailTheStructureCheck) {
    Scene scene = loadScene(meshPath("teapot.obj"));
    Octree tree = buildOctree(scene, BuildParams{});
    LinearOctree lin = buildLinear(tree);
    ASSERT_EQ(lin.nodes[0].nodeType(), NodeType::Internal);
    for (int i = 1; i <= 8; ++i) lin.nodes[size_t(i)] = lin.nodes[0];
    const PrimitivesView prims = primitivesView(scene);
    const LinearOctreeView view = linearView(lin, tree, prims);
    const Vec3 c = scene.bounds().center();
    Ray r = {{c.x, c.y, c.z - 10.0f}, {0, 0, 1}, 0.0f, INFINITY};
    TraceCost cost = {0, 0};
    closestHit(view, r, cost);
    EXPECT_LE(cost.nodesVisited, lin.nodes.size());
    ValidateOptions o = octtest::smallOptions(16, 300);
    o.replication = false;
    TracerUnderTest t = cpuTracer("corrupt", view, prims);
    t.lookup = [view](uint64_t k) { return lookupNode(view, k); };
    ValidationReport rep = validateScene(scene, {t}, &tree, o);
    EXPECT_FALSE(rep.passes());
    ASSERT_TRUE(rep.runs[0].structure.has_value());
    EXPECT_GE(rep.runs[0].structure->missing, 8u);
}

// An array shorter than its internal nodes need (a wrong size or index arithmetic): children
// past its end are absent, never read (the sanitizer suite sees any read past the vector).
TEST(FaultGuards, LinearChildrenPastTheArrayAreAbsentNotRead) {
    Scene scene = loadScene(meshPath("teapot.obj"));
    Octree tree = buildOctree(scene, BuildParams{});
    LinearOctree lin = buildLinear(tree);
    lin.nodes.resize(9);
    lin.nodes.shrink_to_fit();
    const PrimitivesView prims = primitivesView(scene);
    LinearOctreeView view = linearView(lin, tree, prims);
    ASSERT_EQ(view.nodes.count, 9u);
    const Vec3 c = scene.bounds().center();
    Ray r = {{c.x, c.y, c.z - 10.0f}, {0, 0, 1}, 0.0f, INFINITY};
    TraceCost cost = {0, 0};
    EXPECT_EQ(closestHit(view, r, cost).prim, -1);
    EXPECT_LE(cost.nodesVisited, 9u);
}

// A leaf list pointing past the index array: the traversal refuses to read it.
TEST(FaultGuards, LeafListPastTheArrayIsAFaultNotARead) {
    Scene scene = loadScene(meshPath("teapot.obj"));
    Octree tree = buildOctree(scene, BuildParams{});
    LinearOctree lin = buildLinear(tree);
    for (OctreeNode& n : lin.nodes)
        if (n.nodeType() == NodeType::Leaf) n.primOffset = uint32_t(tree.primIndices.size());
    const PrimitivesView prims = primitivesView(scene);
    const LinearOctreeView view = linearView(lin, tree, prims);
    const Vec3 c = scene.bounds().center();
    Ray r = {{c.x, c.y, c.z - 10.0f}, {0, 0, 1}, 0.0f, INFINITY};
    TraceCost cost = {0, 0};
    EXPECT_EQ(closestHit(view, r, cost).prim, kTraversalFault);
}

// An any-hit query that ignores the shadow ray's tmax: with the default light outside the scene
// nothing lies beyond any shadow ray's end, so it passes; seen and lit from inside it fails.
struct TmaxIgnoringAccel {
    LinearOctreeView v;
};
template <class Obs>
Hit closestHit(const TmaxIgnoringAccel& a, const Ray& r, TraceCost& cost, Obs& obs) {
    return closestHit(a.v, r, cost, obs);
}
Hit closestHit(const TmaxIgnoringAccel& a, const Ray& r, TraceCost& cost) {
    return closestHit(a.v, r, cost);
}
template <class Obs>
bool anyHit(const TmaxIgnoringAccel& a, const Ray& r, TraceCost& cost, Obs& obs) {
    Ray beyond = r;
    beyond.tmax = INFINITY;  // the fault
    return anyHit(a.v, beyond, cost, obs);
}

TEST(FaultGuards, AnyHitIgnoringTmaxFailsWithTheLightInside) {
    Scene scene = loadScene(meshPath("cornell_box.obj"));
    Octree tree = buildOctree(scene, BuildParams{});
    LinearOctree lin = buildLinear(tree);
    const PrimitivesView prims = primitivesView(scene);
    const TmaxIgnoringAccel accel{linearView(lin, tree, prims)};
    TracerUnderTest bad = cpuTracer("anyhit-beyond-tmax", accel, prims);
    ValidateOptions o = octtest::smallOptions(32, 0);
    o.replication = false;
    o.lightInside = false;
    ASSERT_TRUE(validateScene(scene, {bad}, &tree, o).passes()) << "the old check caught it";
    o.lightInside = true;
    ValidationReport rep = validateScene(scene, {bad}, &tree, o);
    EXPECT_FALSE(rep.passes());
    ASSERT_TRUE(rep.runs[0].lightInside.has_value());
    EXPECT_GT(rep.runs[0].lightInside->shadow.wrong, 0u);
    EXPECT_EQ(rep.runs[0].film.shadow.wrong, 0u);
    // A sound layout passes the same check.
    octtest::CpuTracers sound = octtest::cpuTracers(scene, {"linear"});
    EXPECT_TRUE(validateScene(scene, sound.tracers, sound.canonical, o).passes());
}

}  // namespace
}  // namespace oct
