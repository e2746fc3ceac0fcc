// The edges of the numeric range (core/geometry/numeric_range.h): scenes at the largest
// coordinates and the smallest extent octrace accepts, rays from the farthest origins with the
// shortest and longest directions it accepts, traced by the kernel (exhaustive and linear, the
// same code as CUDA) and by Embree, each rechecked against the double-precision truth
// (validation/policy/hit_check.h): no wrong answer, no hit at t = +inf. Outside the range, the
// kernel's primitive tests and Embree's adapter still never report a hit at t = +inf.
#include "core/geometry/numeric_range.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "backends/backend_list.h"
#include "core/geometry/primitives.h"
#include "core/octree/built_scene.h"
#include "core/render/frame.h"
#include "cpu_ref/embree_tracer.h"
#include "cpu_ref/render_cpu.h"
#include "validation/policy/film_compare.h"
#include "validation/policy/hit_check.h"

namespace oct {
namespace {

// Random triangles of a tenth of the box's side inside [centre - half, centre + half]^3, and
// one large one, so that most rays hit something.
Scene triangleScene(double centre, double half, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Scene s;
    s.name = "range";
    s.kind = PrimKind::Triangles;
    auto at = [&](double x, double y, double z) {
        return Vec3{float(centre + half * x), float(centre + half * y), float(centre + half * z)};
    };
    s.triangles.push_back({at(-1, -1, 0), at(1, -1, 0), at(-1, 1, 0)});
    for (int i = 0; i < 300; ++i) {
        double x = 0.9 * u(rng), y = 0.9 * u(rng), z = 0.9 * u(rng);
        s.triangles.push_back({at(x, y, z), at(x + 0.1 * u(rng), y + 0.1 * u(rng), z),
                               at(x, y + 0.1 * u(rng), z + 0.1 * u(rng))});
    }
    return s;
}

Scene sphereScene(double centre, double half, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.9, 0.9);
    Scene s;
    s.name = "range-spheres";
    s.kind = PrimKind::Spheres;
    for (int i = 0; i < 200; ++i)
        s.spheres.push_back({{float(centre + half * u(rng)), float(centre + half * u(rng)),
                              float(centre + half * u(rng))},
                             float(0.08 * half)});
    return s;
}

// Rays from the corners and face points of the origin box [-reach, reach]^3 (and from near the
// scene) towards random points of the scene's box, their directions scaled so that the
// largest component is the band's minimum, 1 or its maximum (times a non-power-of-two factor).
std::vector<Ray> raysAt(const Scene& s, double reach, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const Aabb b = s.bounds();
    const Vec3 c = b.center(), h = b.extent() * 0.5f;
    std::vector<Ray> rays;
    const double lengths[] = {kMinRayDirection * 1.3, 0.7, kMaxRayDirection * 0.9};
    for (int i = 0; i < 600; ++i) {
        double o[3];
        for (double& x : o) x = reach * u(rng);
        if (i % 3 == 0) o[i % 9 / 3] = (i % 2 ? reach : -reach);  // on a face of the box
        if (i % 5 == 0)
            for (int k = 0; k < 3; ++k) o[k] = c[k] + 3.0 * h[k] * u(rng);  // near the scene
        Vec3 org = {float(o[0]), float(o[1]), float(o[2])};
        Vec3 target = {float(c.x + h.x * u(rng)), float(c.y + h.y * u(rng)),
                       float(c.z + h.z * u(rng))};
        // In double: target - org can exceed float precision's comfort, not its range.
        double d[3] = {double(target.x) - org.x, double(target.y) - org.y,
                       double(target.z) - org.z};
        double m = std::max({std::fabs(d[0]), std::fabs(d[1]), std::fabs(d[2])});
        if (!(m > 0)) continue;
        double len = lengths[i % 3];
        Vec3 dir = {float(d[0] / m * len), float(d[1] / m * len), float(d[2] / m * len)};
        rays.push_back({org, dir, 0.0f, INFINITY});
    }
    return rays;
}

struct Tally {
    int hits = 0, wrong = 0, ambiguous = 0, infinite = 0;
};

void check(const HitClassifier& cls, const std::vector<Ray>& rays, const std::vector<Hit>& hits,
           const char* tracer, Tally& tally) {
    for (size_t i = 0; i < rays.size(); ++i) {
        const Hit h = hits[i];
        if (h.prim >= 0) ++tally.hits;
        if (h.prim >= 0 && !std::isfinite(h.t)) ++tally.infinite;
        Verdict v = cls.recheckClosest(rays[i], h);
        if (v.cls == HitClass::Wrong) {
            ++tally.wrong;
            ADD_FAILURE() << tracer << " ray " << i << " org (" << rays[i].org.x << ", "
                          << rays[i].org.y << ", " << rays[i].org.z << ") dir (" << rays[i].dir.x
                          << ", " << rays[i].dir.y << ", " << rays[i].dir.z << "): t " << h.t
                          << " prim " << h.prim << ", truth t " << v.truth.t << " prim "
                          << v.truth.prim;
        }
        // recheckClosest calls an answer equal to the truth "ambiguous, reference_off"; only
        // other reasons (a touchy configuration) count here.
        if (v.cls == HitClass::Ambiguous && (v.reasons & ~uint32_t(kReferenceOff)))
            ++tally.ambiguous;
    }
}

// Traces `rays` as `octrace trace` does (traceRayAt) with the exhaustive and linear layouts
// and with Embree; every answer is rechecked against the double truth.
void traceEveryWay(const Scene& scene, const std::vector<Ray>& rays) {
    std::vector<float> flat;
    for (const Ray& r : rays) {
        const float row[8] = {r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax};
        flat.insert(flat.end(), row, row + 8);
    }
    HitClassifier cls(scene, ValidationPolicy{});
    std::vector<float> t(rays.size());
    std::vector<int32_t> prim(rays.size());
    RayBatchView batch{flat.data(), t.data(), prim.data(), rays.size()};
    auto hits = [&] {
        std::vector<Hit> h(rays.size());
        for (size_t i = 0; i < h.size(); ++i) h[i] = {t[i], prim[i]};
        return h;
    };
    for (const char* name : {"exhaustive", "linear"}) {
        BuiltScene built = buildScene(scene, findLayout(name), LayoutOptions{});
        traceWith(hostBackend(), built, batch);
        Tally tally;
        check(cls, rays, hits(), name, tally);
        EXPECT_EQ(tally.infinite, 0) << name;
        EXPECT_GT(tally.hits, int(rays.size() / 4)) << name << ": the rays must meet the scene";
        EXPECT_LE(tally.ambiguous, int(rays.size() / 50)) << name;
    }
    EmbreeTracer embree(scene);
    traceRaysCpu(embree.accel(), batch);
    Tally tally;
    check(cls, rays, hits(), "embree", tally);
    EXPECT_EQ(tally.infinite, 0) << "embree";
    EXPECT_LE(tally.ambiguous, int(rays.size() / 50)) << "embree";
}

// The frame of `octrace render` with its default camera (eye at 5.75 x the bound for a scene
// at the bound) and with the eye at the farthest origin: no hit at +inf, and the layouts agree
// with Embree by docs/VALIDATION.md's per-pixel rule.
void renderEveryWay(const Scene& scene, std::optional<Vec3> eye) {
    CameraOptions opt;
    opt.width = opt.height = 64;
    opt.eye = eye;
    if (eye) opt.target = scene.bounds().center();
    FrameParams p = makeFrame(scene.bounds(), opt);
    EmbreeTracer embree(scene);
    Film truth(p.width, p.height);
    renderFrameCpu(p, embree.accel(), primitivesView(scene), truth.view());
    BuiltScene built = buildScene(scene, findLayout("linear"), LayoutOptions{});
    Film film;
    renderWith(hostBackend(), built, p, film);
    int hits = 0;
    for (size_t i = 0; i < film.pixelCount(); ++i) {
        if (film.prim[i] >= 0) ++hits;
        EXPECT_TRUE(film.prim[i] < 0 || std::isfinite(film.t[i])) << "pixel " << i;
        EXPECT_TRUE(truth.prim[i] < 0 || std::isfinite(truth.t[i])) << "embree pixel " << i;
    }
    EXPECT_GT(hits, 0);
    FilmComparison c = compareFilms(film, truth, sceneExtent(scene));
    EXPECT_EQ(c.distanceMismatch, 0u);
    EXPECT_LE(c.hitMissMismatch, film.pixelCount() / 200);
}

TEST(NumericRange, ScenesAtTheLargestCoordinatesTraceRightFromTheFarthestOrigins) {
    // A scene filling [-C, C]^3, and one in a corner of it, seen from the whole origin box.
    for (double centre : {0.0, kMaxCoordinate * 0.5}) {
        SCOPED_TRACE(centre);
        const double half = centre == 0.0 ? kMaxCoordinate : kMaxCoordinate * 0.5;
        Scene tris = triangleScene(centre, half, 7);
        traceEveryWay(tris, raysAt(tris, kMaxRayOrigin, 11));
        Scene spheres = sphereScene(centre, half * 0.9, 5);
        traceEveryWay(spheres, raysAt(spheres, kMaxRayOrigin, 13));
        renderEveryWay(tris, std::nullopt);
        const float o = float(kMaxRayOrigin);
        renderEveryWay(tris, Vec3{-o, o, -o});
    }
}

TEST(NumericRange, ScenesAtTheSmallestExtentTraceRight) {
    const double half = kMinSceneExtent * 0.5;
    for (double centre : {0.0, 3 * kMinSceneExtent}) {
        SCOPED_TRACE(centre);
        Scene tris = triangleScene(centre, half, 3);
        traceEveryWay(tris, raysAt(tris, 4 * kMinSceneExtent, 17));
        Scene spheres = sphereScene(centre, half * 0.9, 9);
        traceEveryWay(spheres, raysAt(spheres, 4 * kMinSceneExtent, 19));
        renderEveryWay(tris, std::nullopt);
    }
}

// The smallest triangle accepted (twice its area = kMinTriangleArea2) in a scene of extent 1 is
// hit, by every tracer, by rays of every direction length, at its distance to within 1e-10 of
// the extent (numeric_range.h: its t * det is a denormal, off by up to 2^-149 / det = 1.4e-17 in
// t). The validation policy calls any ray near so small a triangle touchy (edge tolerance 2e-6
// of the extent), so it is checked here directly rather than by the recheck.
TEST(NumericRange, TheSmallestTriangleIsHitAtItsDistance) {
    const float e = float(std::sqrt(kMinTriangleArea2));  // legs of length e: |cross| = e^2
    Scene s;
    s.name = "speck";
    s.kind = PrimKind::Triangles;
    s.triangles.push_back({{0, 0, 0}, {e, 0, 0}, {0, e, 0}});
    s.triangles.push_back({{1, 1, 1}, {1.5f, 1, 1}, {1, 1.5f, 1}});  // gives the scene extent 1
    // Rays from 1e-13 above it (tiny coordinates stay exact in float), straight down and at a
    // slope of 0.5, landing at (e/4, e/4, 0).
    const float above = 1e-13f;
    std::vector<float> rows;
    for (double len : {kMinRayDirection * 1.3, 1.0, kMaxRayDirection * 0.9})
        for (float slope : {0.0f, 0.5f}) {
            const float row[8] = {0.25f * e - slope * above,
                                  0.25f * e,
                                  above,
                                  float(slope * len),
                                  0,
                                  float(-len),
                                  0.0f,
                                  INFINITY};
            rows.insert(rows.end(), row, row + 8);
        }
    const size_t n = rows.size() / 8;
    std::vector<float> t(n);
    std::vector<int32_t> prim(n);
    RayBatchView batch{rows.data(), t.data(), prim.data(), n};
    auto expectHits = [&](const char* tracer) {
        for (size_t i = 0; i < n; ++i) {
            EXPECT_EQ(prim[i], 0) << tracer << " ray " << i;
            EXPECT_NEAR(double(t[i]) * std::fabs(double(rows[8 * i + 5])), double(above), 1e-10)
                << tracer << " ray " << i;
        }
    };
    for (const char* name : {"exhaustive", "linear"}) {
        BuiltScene built = buildScene(s, findLayout(name), LayoutOptions{});
        traceWith(hostBackend(), built, batch);
        expectHits(name);
    }
    EmbreeTracer embree(s);
    traceRaysCpu(embree.accel(), batch);
    expectHits("embree");
}

// --- outside the range: never a hit at +inf ---------------------------------------------------

// Before: a tetrahedron with vertices at 1e14 gave t = +inf with a valid primitive (the scaled
// distance t * det overflows float), on the CPU and in Embree.
TEST(NumericRange, KernelTestsNeverReportAHitAtInfinity) {
    const float s = 1e14f;
    Triangle tri = {{0, 0, 0}, {s, 0, 0}, {0, s, 0}};
    Vec3 org = {2.5e13f, 2.5e13f, -1e14f}, dir = {0, 0, 1};
    float t = 0;
    bool hit = intersectTriangle(makeShearedRay(org, dir), tri, 0.0f, INFINITY, t);
    EXPECT_TRUE(!hit || std::isfinite(t)) << "hit at t = " << t;

    // c = |f|^2 - r^2 overflows: the near root is +inf, the far one finite but past tmin.
    Sphere sp = {{0, 0, 3e19f}, 1e19f};
    hit = intersectSphere({0, 0, 0}, {0, 0, 1}, sp, 5e19f, INFINITY, t);
    EXPECT_TRUE(!hit || std::isfinite(t)) << "hit at t = " << t;
}

TEST(NumericRange, EmbreeAdapterNeverReportsAHitAtInfinity) {
    Scene s;
    s.name = "huge";
    s.kind = PrimKind::Triangles;
    const float e = 1e14f;
    s.triangles.push_back({{0, 0, 0}, {e, 0, 0}, {0, e, 0}});
    s.triangles.push_back({{0, 0, e}, {e, 0, 0}, {0, e, 0}});
    EmbreeTracer embree(s);
    TraceCost cost{0, 0};
    Hit h =
        closestHit(embree.accel(), Ray{{2.5e13f, 2.5e13f, -1e14f}, {0, 0, 1}, 0, INFINITY}, cost);
    EXPECT_TRUE(h.prim < 0 || std::isfinite(h.t)) << "hit " << h.prim << " at t = " << h.t;
}

}  // namespace
}  // namespace oct
