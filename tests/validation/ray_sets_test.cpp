// The standard ray sets (validation/rays/ray_sets.h): validate's seeded sets, and every set of
// `octrace rays`: reproducible to the byte (a pinned checksum), well formed, and the edges and
// vertices rays sealed at their targets.
#include "validation/rays/ray_sets.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/octree/octree.h"
#include "core/scene/mesh_topology.h"
#include "cpu_ref/embree_tracer.h"
#include "tests/validation/fixtures.h"
#include "validation/policy/double_tracer.h"

namespace oct {
namespace {

uint64_t rowsOf(const RaySet& r, const char* name) {
    const RaySetRange* s = r.find(name);
    return s ? s->count : 0;
}

TEST(RaySets, SplitReproducibleAndWellFormed) {
    Scene scene = loadScene(octtest::meshPath("teapot.obj"));
    RaySet a = makeValidationRays(scene, 3001, 42);
    RaySet b = makeValidationRays(scene, 3001, 42);
    RaySet c = makeValidationRays(scene, 3001, 43);
    ASSERT_EQ(a.count(), 3001u);
    ASSERT_EQ(a.rays.size(), 8u * 3001u);
    EXPECT_EQ(a.rays, b.rays);
    EXPECT_NE(a.rays, c.rays);
    EXPECT_EQ(rowsOf(a, "around"), 1001u);
    EXPECT_EQ(rowsOf(a, "inside"), 1000u);
    EXPECT_EQ(rowsOf(a, "axis"), 1000u);

    Aabb root = rootCube(scene);
    Aabb bounds = scene.bounds();
    int onPlane = 0, finiteTmax = 0;
    for (const RaySetRange& s : a.sets)
        for (uint64_t i = s.begin; i < s.begin + s.count; ++i) {
            const Ray r = a.ray(i);
            ASSERT_TRUE(isFinite(r.org));
            EXPECT_NEAR(length(r.dir), 1.0f, 1e-6f);
            EXPECT_EQ(r.tmin, 0.0f);
            finiteTmax += std::isfinite(r.tmax);
            if (s.name == "around") {
                EXPECT_FALSE(bounds.contains(r.org));
            }
            if (s.name == "inside") {
                EXPECT_TRUE(root.contains(r.org));
            }
            if (s.name != "axis") continue;
            EXPECT_TRUE(root.contains(r.org));
            const Vec3 o = r.org, d = r.dir;
            EXPECT_EQ((d.x != 0) + (d.y != 0) + (d.z != 0), 1);
            // On a node boundary plane of depth <= 3: (o - lo) / edge * 8 is an integer (the
            // float midpoints of a cube are exact here).
            for (int ax = 0; ax < 3; ++ax) {
                if (d[ax] != 0) continue;
                double f =
                    (double(o[ax]) - root.lo[ax]) / (double(root.hi[ax]) - root.lo[ax]) * 8.0;
                if (std::fabs(f - std::round(f)) < 1e-5) {
                    ++onPlane;
                    break;
                }
            }
        }
    EXPECT_GE(onPlane, 450);     // every other axis ray
    EXPECT_GT(finiteTmax, 150);  // a quarter of the inside rays
    EXPECT_LT(finiteTmax, 350);
}

TEST(RaySets, ZeroRaysIsEmpty) {
    Scene scene = loadScene(octtest::meshPath("cube_binary.ply"));
    EXPECT_EQ(makeValidationRays(scene, 0, 1).count(), 0u);
}

RaySetSpec seededSpec(uint64_t count, uint64_t seed) {
    RaySetSpec spec;
    for (const char* n : {"around", "inside", "axis", "edges", "vertices", "grazing", "tmin-tmax"})
        spec.sets.push_back(findRaySet(n));
    spec.count = count;
    spec.seed = seed;
    return spec;
}

// Same seed, same bytes, on every machine: the seeded sets use raw mt19937_64 output and IEEE
// arithmetic only, so this checksum of the teapot's rays is the same everywhere. A change here
// changes every published ray file: only on purpose, with the docs (docs/CERTIFY.md). Last
// changed (from 3c3a6479d86b4435) when an edges or vertices target became sealed only where the
// double truth hits one of its own triangles at its t on the stored ray: 135 of 2000 teapot
// targets were hidden behind another part of the teapot and are drawn again, which changes the
// edges and vertices rows from the first such one on; around, inside, axis, grazing and
// tmin-tmax are byte for byte the same (and so are the cube's and sphere_with_hole's sets).
TEST(RaySets, SeededSetsHaveAPinnedChecksum) {
    Scene scene = loadScene(octtest::meshPath("teapot.obj"));
    RaySet r = makeRaySet(scene, seededSpec(700, 5));
    ASSERT_EQ(r.count(), 700u);
    EXPECT_EQ(hex64(fnv1a64(r.rays.data(), r.rays.size() * sizeof(float))), "5ca4e2075201275a");
    RaySet again = makeRaySet(scene, seededSpec(700, 5));
    EXPECT_EQ(r.rays, again.rays);
}

// Each seeded set draws from its own stream: a set's rows do not depend on the sets beside it
// (only on its share of the count).
TEST(RaySets, EachSetHasItsOwnStream) {
    Scene scene = loadScene(octtest::meshPath("teapot.obj"));
    RaySetSpec both = seededSpec(200, 3);
    both.sets = {findRaySet("around"), findRaySet("edges")};
    RaySetSpec alone = both;
    alone.sets = {findRaySet("edges")};
    alone.count = 100;
    RaySet a = makeRaySet(scene, both), b = makeRaySet(scene, alone);
    const RaySetRange* e = a.find("edges");
    ASSERT_TRUE(e);
    ASSERT_EQ(e->count, 100u);
    EXPECT_TRUE(std::equal(b.rays.begin(), b.rays.end(), a.rays.begin() + 8 * e->begin));
}

// Every edges and vertices ray is sealed: the double-precision truth (watertight) hits the
// mesh at or before the target, within 1e-6 of the extent.
TEST(RaySets, EdgeAndVertexTargetsAreHitByTheTruth) {
    for (const char* mesh : {"cube_binary.ply", "teapot.obj", "sphere_with_hole.stl"}) {
        SCOPED_TRACE(mesh);
        Scene scene = loadScene(octtest::meshPath(mesh));
        RaySetSpec spec = seededSpec(400, 11);
        spec.sets = {findRaySet("edges"), findRaySet("vertices")};
        RaySet r = makeRaySet(scene, spec);
        ASSERT_EQ(r.targets.size(), 400u);
        MeshTopology topo = meshTopology(scene);
        DoubleTracer truth(scene, {0.0, 0.0});
        const double tol = 1e-6 * sceneExtent(scene);
        for (const RayTarget& t : r.targets) {
            const Ray ray = r.ray(t.row);
            Hit h = truth.closest(toDoubleRay(ray));
            ASSERT_GE(h.prim, 0) << "row " << t.row;
            EXPECT_LE(double(h.t), t.t + tol) << "row " << t.row;
            // The target's vertices are the welded vertices named.
            EXPECT_EQ(topo.vertices[t.a].x, t.pa.x);
            if (!t.vertex()) {
                EXPECT_TRUE(topo.findEdge(t.a, t.b));
            }
        }
    }
}

TEST(RaySets, CameraShadowAndTriangleOnlySets) {
    Scene scene = loadScene(octtest::meshPath("cube_binary.ply"));
    RaySetSpec spec;
    spec.sets = {findRaySet("camera"), findRaySet("shadow")};
    spec.camera.width = 20;
    spec.camera.height = 10;
    EXPECT_THROW(makeRaySet(scene, spec), std::invalid_argument);  // shadow needs a reference
    EmbreeTracer embree(scene);
    RaySet r = makeRaySet(scene, spec, [&](RayBatchView b) { traceRaysCpu(embree.accel(), b); });
    ASSERT_EQ(rowsOf(r, "camera"), 200u);
    ASSERT_TRUE(r.frame);
    EXPECT_GT(rowsOf(r, "shadow"), 0u);
    const Ray p = r.ray(3 * 20 + 7);
    const Ray q = primaryRay(r.frame->camera, 7, 3, 20, 10);
    EXPECT_EQ(p.dir.x, q.dir.x);
    EXPECT_EQ(p.dir.y, q.dir.y);
    const Ray s = r.ray(r.find("shadow")->begin);
    EXPECT_TRUE(std::isfinite(s.tmax));  // a finite segment towards the light

    Scene cloud = makeGridCloud(100, 1);
    RaySetSpec edges;
    edges.sets = {findRaySet("edges")};
    EXPECT_THROW(makeRaySet(cloud, edges), std::invalid_argument);
    edges.sets = {findRaySet("around"), findRaySet("around")};
    EXPECT_THROW(makeRaySet(scene, edges), std::invalid_argument);
}

}  // namespace
}  // namespace oct
