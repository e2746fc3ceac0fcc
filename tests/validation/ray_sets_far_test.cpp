// The standard ray sets away from the origin and at the float grid's own spacing, as the loader
// accepts them (issue 21): every row `octrace rays` writes is one `octrace trace` accepts, and
// every edges / vertices target counted as sealed is hit by the double-precision truth on one
// of its own triangles at its t. The scenes are made here, written as OBJ files and loaded:
// a UTM-like terrain at x = 5e5, y = 4e6; the teapot scaled by 100 and moved there; 8 x 8
// heightfields whose vertices are 1 to 2 ulps apart at 1e6 .. 6.5e10.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "core/io/ray_file.h"
#include "core/scene/load_scene.h"
#include "core/scene/mesh_topology.h"
#include "cpu_ref/embree_tracer.h"
#include "cpu_ref/render_cpu.h"
#include "tests/cli_harness.h"
#include "tests/far_meshes.h"
#include "tests/paths.h"
#include "tests/validation/fixtures.h"
#include "validation/certify.h"
#include "validation/policy/double_tracer.h"
#include "validation/policy/film_compare.h"
#include "validation/rays/ray_sets.h"
#include "validation/report/report.h"

namespace oct {
namespace {

RaySetSpec seeded(uint64_t count, uint64_t seed, std::vector<const char*> names) {
    RaySetSpec spec;
    for (const char* n : names) spec.sets.push_back(findRaySet(n));
    spec.count = count;
    spec.seed = seed;
    return spec;
}

struct Far {
    const char* what;
    std::function<octtest::Mesh()> mesh;
};

std::vector<Far> farScenes() {
    std::vector<Far> out = {{"utm-terrain", octtest::utmTerrain},
                            {"teapot-x100-at-utm", octtest::farTeapot}};
    for (float base : {1e6f, 1e8f, 1e10f, 6.5e10f})
        out.push_back({base == 1e6f    ? "ulp-grid-1e6"
                       : base == 1e8f  ? "ulp-grid-1e8"
                       : base == 1e10f ? "ulp-grid-1e10"
                                       : "ulp-grid-6.5e10",
                       [base] { return octtest::ulpHeightfield(base, 5); }});
    return out;
}

// Each far scene, written as an OBJ file and loaded as a user's file is (nothing dropped).
void forEachFarScene(const std::function<void(const Scene&)>& body) {
    octtest::TempDir dir("ray_sets_far");
    for (const Far& f : farScenes()) {
        SCOPED_TRACE(f.what);
        const Scene scene =
            loadScene(octtest::writeObj(dir, std::string(f.what) + ".obj", f.mesh()));
        ASSERT_EQ(scene.report.totalDropped(), 0u);
        body(scene);
    }
}

// Every row of every seeded set is one `octrace trace` accepts (rayRowProblem, the reader's own
// rule): tmin-tmax rows of the ulp grids had NaN tmax or inf tmin (15 of these 2000 each).
TEST(RaySetsFar, EveryRowIsOneTraceAccepts) {
    forEachFarScene([](const Scene& scene) {
        const RaySet r = makeRaySet(scene, seeded(2000, 9,
                                                  {"around", "inside", "axis", "edges", "vertices",
                                                   "grazing", "tmin-tmax"}));
        uint64_t bad = 0;
        std::string first;
        for (uint64_t i = 0; i < r.count(); ++i) {
            const std::string why = rayRowProblem(&r.rays[8 * i]);
            if (why.empty()) continue;
            if (bad++ == 0) first = "row " + std::to_string(i) + ": " + why;
        }
        EXPECT_EQ(bad, 0u) << first;
    });
}

// A target counted as sealed is hit, in double on the stored float ray, on one of its own
// triangles (the edge's two, the vertex's fan) at its t, within the default t tolerance: at
// x = 5e5, y = 4e6 43 % of the terrain's edge rows tested nothing.
TEST(RaySetsFar, SealedTargetsAreHitByTheTruthOnTheirOwnTriangles) {
    forEachFarScene([](const Scene& scene) {
        const RaySet r = makeRaySet(scene, seeded(1000, 4, {"edges", "vertices"}));
        const MeshTopology topo = meshTopology(scene);
        DoubleTracer truth(scene, {0.0, 0.0});
        const double tol = kDefaultRelativeTolerance * sceneExtent(scene);
        uint64_t sealed = 0, missed = 0;
        std::string first;
        for (const RayTarget& t : r.targets) {
            // The target's own triangles: the edge's two, or every triangle around the vertex.
            std::vector<uint32_t> own;
            if (t.vertex()) {
                for (uint32_t k = topo.vertexStart[t.a]; k < topo.vertexStart[t.a + 1]; ++k)
                    own.push_back(topo.vertexTriangles[k]);
            } else {
                const MeshEdge* e = topo.findEdge(t.a, t.b);
                ASSERT_TRUE(e);
                own = {e->tri[0], e->tri[1]};
            }
            std::sort(own.begin(), own.end());
            EXPECT_EQ(t.triangles, own) << "row " << t.row;
            if (!t.sealed) continue;  // not counted as checked: certify skips it
            const Ray ray = r.ray(t.row);
            const Hit h = truth.closest(toDoubleRay(ray));
            const bool onOwn = h.prim >= 0 &&
                               std::find(own.begin(), own.end(), uint32_t(h.prim)) != own.end() &&
                               std::fabs(double(h.t) - t.t) <= tol / double(length(ray.dir));
            ++sealed;
            if (onOwn) continue;
            if (missed++ == 0)
                first = "row " + std::to_string(t.row) + ": truth #" + std::to_string(h.prim) +
                        " t " + std::to_string(h.t) + ", target t " + std::to_string(t.t);
        }
        EXPECT_EQ(missed, 0u) << missed << " of " << sealed << " sealed targets missed; " << first;
        // Checked on the stored ray, nearly every target can be sealed, the ulp grids' too.
        EXPECT_GE(sealed, 900u);
        if (sealed < r.targets.size()) {
            EXPECT_FALSE(r.notes.empty());
        }
    });
}

// octrace's own tracers (every layout, CPU) hit at or before every sealed target: on the grid
// whose vertices are 1 ulp apart it reported a leak at an edge the stored ray never meets.
TEST(RaySetsFar, OctracesOwnTracersDoNotLeakAtSealedTargets) {
    forEachFarScene([](const Scene& scene) {
        RaySet r = makeRaySet(scene, seeded(600, 8, {"edges", "vertices"}));
        const double tol = kDefaultRelativeTolerance * sceneExtent(scene);
        octtest::CpuTracers cpu = octtest::cpuTracers(scene);
        for (const TracerUnderTest& tracer : cpu.tracers) {
            SCOPED_TRACE(tracer.layout);
            std::vector<float> t(r.count());
            std::vector<int32_t> prim(r.count());
            tracer.trace({r.rays.data(), t.data(), prim.data(), r.count()});
            uint64_t leaks = 0;
            std::string first;
            for (const RayTarget& tg : r.targets) {
                if (!tg.sealed) continue;
                const Ray ray = r.ray(tg.row);
                if (prim[tg.row] >= 0 && double(t[tg.row]) <= tg.t + tol / double(length(ray.dir)))
                    continue;
                if (leaks++ == 0)
                    first = "row " + std::to_string(tg.row) + ": t " + std::to_string(t[tg.row]) +
                            " #" + std::to_string(prim[tg.row]) + ", target t " +
                            std::to_string(tg.t);
            }
            EXPECT_EQ(leaks, 0u) << first;
        }
    });
}

// certify finds no wrong ray and no leak in octrace's own tracers (every layout, CPU) on any far
// scene, in every standard set it takes: on the ulp grids at 1e6 and 1e8 the kernel reported 12
// "around" rays each hit at their origin, off the triangle (rays in the triangle's plane to
// within rounding). The ambiguous rate is not asserted: on a grid whose vertices are an ulp
// apart 4 % of the around rays touch something within rounding, and say so.
TEST(RaySetsFar, CertifyFindsNothingWrongInOctracesOwnTracers) {
    forEachFarScene([](const Scene& scene) {
        RaySetSpec spec = seeded(20000, 1, {});
        for (const RaySetDesc& k : standardRaySets())
            if (raySetsUnavailable(scene, {&k})[0].empty()) spec.sets.push_back(&k);
        spec.camera.width = spec.camera.height = 64;
        EmbreeTracer embree(scene);
        const RaySet rays =
            makeRaySet(scene, spec, [&](RayBatchView b) { traceRaysCpu(embree.accel(), b); });
        octtest::CpuTracers cpu = octtest::cpuTracers(scene);
        for (const TracerUnderTest& tracer : cpu.tracers) {
            SCOPED_TRACE(tracer.layout);
            HitArrays h;
            h.t.resize(rays.count());
            h.prim.resize(rays.count());
            tracer.trace({rays.rays.data(), h.t.data(), h.prim.data(), rays.count()});
            const CertifyReport rep = certifyTracer(scene, rays, h, ValidationPolicy{});
            EXPECT_EQ(rep.result.all.wrong, 0u) << humanSummary(rep);
            EXPECT_EQ(rep.result.leaks, 0u) << humanSummary(rep);
            EXPECT_EQ(rep.result.all.unverified, 0u) << humanSummary(rep);
        }
    });
}

}  // namespace
}  // namespace oct
