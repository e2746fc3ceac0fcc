// The slivers ray set (validation/rays/ray_sets.h) on the slivers scene (core/scene/slivers.h):
// every ray aimed inside the square, its target where it crosses the plane; the
// double-precision truth hits them all; octrace's layouts never miss one; a tracer that is not
// watertight fails certify's leak check. The set is refused on other scenes.
#include <gtest/gtest.h>

#include <cmath>

#include "core/scene/mesh_topology.h"
#include "core/scene/slivers.h"
#include "tests/validation/fixtures.h"
#include "validation/certify.h"
#include "validation/policy/double_tracer.h"
#include "validation/rays/ray_sets.h"
#include "validation/report/report.h"

namespace oct {
namespace {

RaySet sliversRays(const Scene& scene, uint64_t count, uint64_t seed) {
    RaySetSpec spec;
    spec.sets = {findRaySet("slivers")};
    spec.count = count;
    spec.seed = seed;
    return makeRaySet(scene, spec);
}

HitArrays layoutHits(const Scene& scene, const LayoutDesc& layout, const RaySet& rays) {
    const BuiltScene bs = buildScene(scene, layout, LayoutOptions{});
    HitArrays h;
    h.t.resize(rays.count());
    h.prim.resize(rays.count());
    traceWith(hostBackend(), bs, {rays.rays.data(), h.t.data(), h.prim.data(), rays.count()});
    return h;
}

// The textbook Moller-Trumbore test in float (examples/moller_trumbore.py): not watertight, and
// with its determinant epsilon (1e-7 there; 0: rounding alone) it drops thin triangles.
bool mollerTrumbore(const Ray& r, const Triangle& tri, float eps, float& t) {
    const Vec3 e1 = tri.v1 - tri.v0, e2 = tri.v2 - tri.v0;
    const Vec3 p = cross(r.dir, e2);
    const float det = dot(e1, p);
    if (!(std::fabs(det) > eps)) return false;
    const float inv = 1.0f / det;
    const Vec3 s = r.org - tri.v0;
    const float u = dot(s, p) * inv;
    if (u < 0.0f || u > 1.0f) return false;
    const Vec3 q = cross(s, e1);
    const float v = dot(r.dir, q) * inv;
    if (v < 0.0f || u + v > 1.0f) return false;
    t = dot(e2, q) * inv;
    return t > eps && t >= r.tmin && t <= r.tmax;
}

HitArrays mollerTrumboreHits(const Scene& scene, const RaySet& rays, float eps) {
    HitArrays h;
    h.t.assign(rays.count(), INFINITY);
    h.prim.assign(rays.count(), -1);
    for (uint64_t i = 0; i < rays.count(); ++i) {
        const Ray r = rays.ray(i);
        for (size_t k = 0; k < scene.triangles.size(); ++k) {
            float t;
            if (mollerTrumbore(r, scene.triangles[k], eps, t) && t < h.t[i]) {
                h.t[i] = t;
                h.prim[i] = int32_t(k);
            }
        }
    }
    return h;
}

// 64-bit FNV-1a of a vector's bytes.
template <typename T>
std::string checksum(const std::vector<T>& v) {
    return hex64(fnv1a64(v.data(), v.size() * sizeof(T)));
}

// Same seed, same bytes, everywhere: the scene (integer arithmetic) and its rays (raw
// mt19937_64 output, IEEE +, -, x, /, sqrt). A change here changes every published slivers
// ray file: only on purpose, with docs/CERTIFY.md.
TEST(SliversRays, TheSceneAndTheRaysHavePinnedChecksums) {
    const Scene scene = makeSlivers(2000, 1);
    EXPECT_EQ(checksum(scene.triangles), "ada2452756aa18bb");
    const RaySet r = sliversRays(scene, 1000, 5);
    EXPECT_EQ(checksum(r.rays), "e728099a6e37c0d2");
    EXPECT_EQ(sliversRays(scene, 1000, 5).rays, r.rays);
    EXPECT_NE(sliversRays(scene, 1000, 6).rays, r.rays);
}

TEST(SliversRays, EveryTargetLiesInsideTheSquare) {
    const Scene scene = makeSlivers(2000, 3);
    const RaySet r = sliversRays(scene, 4000, 2);
    ASSERT_EQ(r.count(), 4000u);
    ASSERT_EQ(r.targets.size(), 4000u);
    const MeshTopology topo = meshTopology(scene);
    const double margin = 1e-5 * sceneExtent(scene);
    int above = 0, grazingish = 0, kinds[3] = {0, 0, 0};
    for (uint64_t i = 0; i < r.count(); ++i) {
        const RayTarget& tg = r.targets[i];
        const Ray ray = r.ray(i);
        ASSERT_EQ(tg.row, i);
        EXPECT_EQ(ray.tmin, 0.0f);
        EXPECT_EQ(ray.tmax, INFINITY);
        EXPECT_NEAR(length(ray.dir), 1.0f, 1e-6f);
        // The target is where the stored ray meets z = 0, inside the square by the margin.
        ASSERT_GT(tg.t, 0.0);
        EXPECT_NEAR(double(ray.org.z) + tg.t * double(ray.dir.z), 0.0, 1e-15);
        const double x = ray.org.x + tg.t * double(ray.dir.x);
        const double y = ray.org.y + tg.t * double(ray.dir.y);
        EXPECT_TRUE(x >= margin && x <= 1 - margin && y >= margin && y <= 1 - margin) << i;
        const double cosine = std::fabs(ray.dir.z);
        EXPECT_GE(cosine, 0.0099) << i;
        above += ray.org.z > 0;
        grazingish += cosine < 0.05;
        // By row: two in four inside a triangle (naming its nearest edge), one on an interior
        // edge, one at an interior vertex, within a float rounding of the crossing.
        if (tg.vertex()) {
            EXPECT_EQ(i % 4, 3u);
            EXPECT_FALSE(vertexLink(topo, tg.a).empty());
            EXPECT_LT(std::hypot(x - tg.pa.x, y - tg.pa.y), 1e-6);
            ++kinds[2];
            continue;
        }
        const MeshEdge* e = topo.findEdge(tg.a, tg.b);
        ASSERT_TRUE(e) << i;
        EXPECT_LT(tg.a, tg.b);
        if (i % 4 == 2) {
            EXPECT_EQ(e->triangles, 2u);
            ++kinds[1];
        } else {
            ++kinds[0];
        }
    }
    EXPECT_EQ(kinds[0], 2000);
    EXPECT_EQ(kinds[1], 1000);
    EXPECT_EQ(kinds[2], 1000);
    EXPECT_GT(above, 1800);  // from both sides
    EXPECT_LT(above, 2200);
    EXPECT_GT(grazingish, 200);  // |cos| from 0.01: (sqrt(0.05) - 0.1) / 0.9 = 14 % below 0.05
}

TEST(SliversRays, TheTruthHitsEveryRayAtItsTarget) {
    const Scene scene = makeSlivers(4000, 9);
    const RaySet r = sliversRays(scene, 3000, 4);
    const DoubleTracer truth(scene, {0.0, 0.0});
    for (const RayTarget& tg : r.targets) {
        const Hit h = truth.closest(toDoubleRay(r.ray(tg.row)));
        ASSERT_GE(h.prim, 0) << "row " << tg.row;
        EXPECT_NEAR(double(h.t), tg.t, 1e-6 * tg.t) << "row " << tg.row;
    }
}

TEST(SliversRays, OnlyASliversSceneTakesTheSet) {
    const RaySetDesc& set = *findRaySet("slivers");
    const Scene teapot = loadScene(octtest::meshPath("teapot.obj"));
    const Scene cloud = makeGridCloud(100, 1);
    const Scene slivers = makeSlivers(200, 1);
    EXPECT_EQ(raySetMisfit(set, teapot), "needs a slivers:N scene");
    EXPECT_EQ(raySetMisfit(set, cloud), "needs a triangle mesh");
    EXPECT_EQ(raySetMisfit(set, slivers), "");
    try {
        sliversRays(teapot, 10, 1);
        ADD_FAILURE() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("needs a generated slivers:N scene"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_THROW(sliversRays(cloud, 10, 1), std::invalid_argument);
    // Every set fits a slivers scene (what --set all makes there); only slivers misfits others.
    RaySetSpec all;
    for (const RaySetDesc& k : standardRaySets()) {
        EXPECT_EQ(raySetMisfit(k, slivers), "") << k.name;
        EXPECT_EQ(raySetMisfit(k, teapot).empty(), &k != &set) << k.name;
        if (!k.needsReference) all.sets.push_back(&k);
    }
    all.count = 900;
    all.camera.width = all.camera.height = 8;
    const RaySet r = makeRaySet(slivers, all);
    EXPECT_EQ(r.find("slivers")->count, 112u);  // the last of 8 seeded sets: 900 / 8
}

// octrace's kernel is watertight on slivers: no ray through the square is missed, by any layout.
TEST(SliversCertify, EveryLayoutHitsEveryRay) {
    const Scene scene = makeSlivers(2000, 1);
    const RaySet rays = sliversRays(scene, 4000, 1);
    for (const LayoutDesc& layout : layouts()) {
        SCOPED_TRACE(layout.name);
        const HitArrays h = layoutHits(scene, layout, rays);
        uint64_t missed = 0;
        for (uint64_t i = 0; i < rays.count(); ++i)
            missed += !(h.prim[i] >= 0 && std::isfinite(h.t[i]));
        EXPECT_EQ(missed, 0u);
        const CertifyReport rep = certifyTracer(scene, rays, h, ValidationPolicy{});
        EXPECT_EQ(rep.result.leakChecked, rays.count());
        EXPECT_EQ(rep.result.all.wrong, 0u) << humanSummary(rep);
        EXPECT_EQ(rep.result.unsealed, 0u);
        for (const SetCertification& s : rep.result.sets)
            for (const LeakFinding& f : s.leakList) EXPECT_GE(f.got.prim, 0) << f.index;
    }
}

// Every layout's t is where the ray crosses the square's plane, to 1e-6 of the extent: the
// kernel recomputes an ill-conditioned t in double (core/geometry/primitives.h). In float
// alone these rows came back up to 5.6e-4 of the extent off (4e-2 in 20,000 rows): within the
// float error bound that the surface rule allows, so only this test holds the kernel to it.
TEST(SliversCertify, EveryLayoutsTIsAtTheTarget) {
    const Scene scene = makeSlivers(2000, 1);
    const RaySet rays = sliversRays(scene, 4000, 1);
    const double extent = sceneExtent(scene);
    for (const LayoutDesc& layout : layouts()) {
        SCOPED_TRACE(layout.name);
        const HitArrays h = layoutHits(scene, layout, rays);
        uint64_t off = 0;
        double worst = 0.0;
        for (const RayTarget& t : rays.targets) {
            const Ray r = rays.ray(t.row);
            const double dt = std::fabs(double(h.t[t.row]) - t.t) * double(length(r.dir)) / extent;
            worst = std::max(worst, dt);
            off += !(dt <= 1e-6);
        }
        EXPECT_EQ(off, 0u) << "worst |dt| / extent " << worst;
    }
}

// The whole leak check and the per-ray policy: every layout's t is at the target too (an
// ill-conditioned t is recomputed in double, core/geometry/primitives.h; before, 74 rows of
// slivers:2000 came back up to 4 % of the extent late).
TEST(SliversCertify, EveryLayoutPassesTheLeakCheck) {
    const Scene scene = makeSlivers(2000, 1);
    const RaySet rays = sliversRays(scene, 4000, 1);
    for (const LayoutDesc& layout : layouts()) {
        SCOPED_TRACE(layout.name);
        const CertifyReport rep =
            certifyTracer(scene, rays, layoutHits(scene, layout, rays), ValidationPolicy{});
        EXPECT_TRUE(rep.passes()) << humanSummary(rep);
        EXPECT_EQ(rep.result.leaks, 0u);
    }
}

// A tracer with cracks fails without any reference: Moller-Trumbore in float, with the
// textbook's determinant epsilon and without it.
TEST(SliversCertify, ACrackedTracerFails) {
    const Scene scene = makeSlivers(2000, 1);
    const RaySet rays = sliversRays(scene, 4000, 1);
    for (float eps : {1e-7f, 0.0f}) {
        SCOPED_TRACE(eps);
        const HitArrays h = mollerTrumboreHits(scene, rays, eps);
        uint64_t missed = 0;
        for (uint64_t i = 0; i < rays.count(); ++i) missed += h.prim[i] < 0;
        const CertifyReport rep = certifyTracer(scene, rays, h, ValidationPolicy{});
        EXPECT_FALSE(rep.passes());
        EXPECT_EQ(rep.result.unsealed, 0u);
        EXPECT_GE(rep.result.leaks, missed);  // every miss is a leak, and so is a late hit
        EXPECT_GT(missed, 10u) << humanSummary(rep);
        std::printf("Moller-Trumbore eps %g: %llu misses, %llu leaks of %llu\n", double(eps),
                    (unsigned long long)missed, (unsigned long long)rep.result.leaks,
                    (unsigned long long)rays.count());
    }
}

}  // namespace
}  // namespace oct
