// The double truth's accelerated queries (policy/double_tracer.h, through policy/box_bvh.h)
// against its brute force over every primitive: the same closest hit, the same list of hits,
// the same touchiness near a segment and the same nearest primitive, bit for bit, on every
// committed mesh, a grid cloud and a mesh far from the origin, for seeded rays of every kind
// the checks meet (from outside, from inside, axis-parallel, aimed exactly at vertices and edge
// points, finite segments ending on a surface).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "core/scene/grid_cloud.h"
#include "core/scene/load_scene.h"
#include "tests/paths.h"
#include "tests/seeded.h"
#include "validation/policy/double_tracer.h"

namespace oct {
namespace {

using octtest::committedMeshes;
using octtest::meshPath;

using octtest::u01;

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// A point of the scene: a vertex (or sphere centre), a point on an edge, or inside the box.
Vec3 scenePoint(const Scene& s, std::mt19937_64& rng) {
    const uint32_t i = uint32_t(rng() % s.primitiveCount());
    const int kind = int(rng() % 3);
    if (s.kind == PrimKind::Spheres) {
        const Sphere& sp = s.spheres[i];
        return kind == 0 ? sp.center : sp.center + Vec3{sp.radius, 0.0f, 0.0f};
    }
    const Triangle& t = s.triangles[i];
    if (kind == 0) return t.v0;
    if (kind == 1) return t.v0 + (t.v1 - t.v0) * float(u01(rng));
    const Aabb b = s.bounds();
    return b.lo + b.extent() * Vec3{float(u01(rng)), float(u01(rng)), float(u01(rng))};
}

std::vector<Ray> truthRays(const Scene& s, int n, uint64_t seed) {
    std::mt19937_64 rng(seed);
    const Aabb b = s.bounds();
    const Vec3 c = b.center();
    const float r = length(b.extent());
    std::vector<Ray> rays;
    for (int i = 0; i < n; ++i) {
        const Vec3 target = scenePoint(s, rng);
        Vec3 o;
        switch (i % 4) {
            case 0:  // from a shell around the scene
                o = c + normalize(Vec3{float(u01(rng) - 0.5), float(u01(rng) - 0.5),
                                       float(u01(rng) - 0.5)}) *
                            (1.5f * r);
                break;
            case 1:  // from inside the box
                o = b.lo + b.extent() * Vec3{float(u01(rng)), float(u01(rng)), float(u01(rng))};
                break;
            default:
                o = c + Vec3{float(u01(rng) - 0.5), float(u01(rng) - 0.5), 2.0f} * r;
        }
        Vec3 d = target - o;
        if (i % 8 == 2) d = {0.0f, 0.0f, -1.0f};  // axis-parallel through the box
        if (!(length(d) > 0.0f)) continue;
        Ray ray{o, d, 0.0f, INFINITY};
        if (i % 5 == 0) ray.tmax = 1.0f;   // a segment ending exactly at the target
        if (i % 7 == 0) ray.tmin = 0.25f;  // starting part-way
        rays.push_back(ray);
    }
    return rays;
}

void expectSameAnswers(const Scene& scene, int rays, uint64_t seed) {
    const double extent = sceneExtent(scene);
    const DoubleTracer truth(scene, {2e-6 * extent, 1e-3});
    size_t checked = 0, hits = 0;
    for (const Ray& ray : truthRays(scene, rays, seed)) {
        const DoubleRay r = toDoubleRay(ray);
        const Hit a = truth.closest(r), b = truth.closestBrute(r);
        ASSERT_EQ(a.prim, b.prim) << scene.name;
        ASSERT_TRUE(sameBits(a.t, b.t)) << scene.name;
        const auto all = truth.allHitsBrute(r);
        ASSERT_EQ(truth.allHits(r), all) << scene.name;
        // One at a time, in the same order, and stopping where the caller says.
        std::vector<std::pair<double, uint32_t>> inOrder, firstTwo;
        truth.hitsInOrder(r, [&](double t, uint32_t p) { return inOrder.push_back({t, p}), true; });
        ASSERT_EQ(inOrder, all) << scene.name;
        truth.hitsInOrder(r, [&](double t, uint32_t p) {
            firstTwo.push_back({t, p});
            return firstTwo.size() < 2;
        });
        ASSERT_EQ(firstTwo.size(), std::min<size_t>(all.size(), 2)) << scene.name;
        ASSERT_EQ(truth.touchinessNear(r), truth.touchinessNearBrute(r)) << scene.name;
        // A touch distance beyond the BVH's growth (far rays' float error bound).
        ASSERT_EQ(truth.touchinessNear(r, 3e-4 * extent),
                  truth.touchinessNearBrute(r, 3e-4 * extent))
            << scene.name;
        if (a.prim >= 0) {
            // Points on the surface and a little off it: the nearest primitive and its distance.
            for (double off : {0.0, 1e-4 * extent, 0.05 * extent}) {
                const double t = double(a.t);
                const DVec3 p = r.org + r.dir * t + DVec3{off, -off, 0.5 * off};
                double da, db;
                const int32_t na = truth.nearestTo(p, da), nb = truth.nearestToBrute(p, db);
                ASSERT_EQ(na, nb) << scene.name;
                ASSERT_TRUE(sameBits(da, db)) << scene.name;
            }
            ++hits;
        }
        ++checked;
    }
    EXPECT_GT(checked, size_t(rays) / 2);
    EXPECT_GT(hits, checked / 10) << scene.name << ": the rays should hit";
}

TEST(DoubleTruth, AcceleratedEqualsBruteForceOnEveryCommittedMesh) {
    for (const std::string& m : committedMeshes())
        expectSameAnswers(loadScene(meshPath(m)), 1500, 3);
}

TEST(DoubleTruth, AcceleratedEqualsBruteForceOnAGridCloud) {
    expectSameAnswers(loadScene("grid:4000:2"), 2000, 5);
}

// The teapot moved to UTM-like coordinates (x = 5e5, y = 4e6): coordinates carry 25 bits of
// offset, where a filter that is not conservative shows first.
TEST(DoubleTruth, AcceleratedEqualsBruteForceFarFromTheOrigin) {
    Scene s = loadScene(octtest::kTeapot);
    for (Triangle& t : s.triangles)
        for (Vec3* v : {&t.v0, &t.v1, &t.v2}) *v = *v + Vec3{5e5f, 4e6f, 0.0f};
    s.name = "teapot at (5e5, 4e6)";
    expectSameAnswers(s, 1500, 7);
}

// The distance from a point to a sliver is the point's, not the rounding of a barycentric
// formula: on slivers:2000 (in z = 0, vertices on a 2^-24 grid, altitudes down to 8.5e-10),
// an edge's midpoint (exact in double) lies on the triangle, the centroid within rounding of
// it, and either lifted by 1e-9 lies 1e-9 away. Ericson's closest-point formula put a point
// of a shared edge 2.2e-5 off one of its triangles, and certify called a right hit off the
// surface.
TEST(DoubleTruth, DistanceToASliverIsNotItsRoundingError) {
    const Scene scene = loadScene("slivers:2000");
    const DoubleTracer truth(scene, {2e-6, 1e-3});
    double worst = 0.0;
    uint32_t worstPrim = 0;
    for (uint32_t k = 0; k < scene.primitiveCount(); ++k) {
        const Triangle& t = scene.triangles[k];
        const DVec3 v[3] = {toDouble(t.v0), toDouble(t.v1), toDouble(t.v2)};
        std::vector<DVec3> on = {(v[0] + v[1]) * 0.5, (v[1] + v[2]) * 0.5, (v[2] + v[0]) * 0.5,
                                 (v[0] + v[1] + v[2]) * (1.0 / 3.0)};
        for (const DVec3& p : on)
            for (double lift : {0.0, 1e-9}) {
                const double err = std::fabs(truth.distanceTo(k, p + DVec3{0.0, 0.0, lift}) - lift);
                if (err > worst) worst = err, worstPrim = k;
            }
    }
    EXPECT_LE(worst, 1e-15) << "triangle #" << worstPrim;
}

}  // namespace
}  // namespace oct
