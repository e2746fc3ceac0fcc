// Ray queries (core/octree/traversal.h) and the ray/box, ray/triangle and ray/sphere routines
// beneath them. The octree layouts are compared with exhaustive tracing, which tests every
// primitive: with the same intersection code and the tie rule (equal t: lower id), a correct
// traversal returns bit-identical hits. The primitive routines are compared with double-precision
// references written here.
#include "core/octree/traversal.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/octree/built_scene.h"
#include "core/scene/grid_cloud.h"
#include "core/scene/load_scene.h"
#include "tests/seeded.h"

namespace oct {
namespace {

using octtest::u01;
float sym(std::mt19937_64& rng) { return float(2.0 * u01(rng) - 1.0); }

Vec3 randomUnit(std::mt19937_64& rng) {
    for (;;) {
        Vec3 v = {sym(rng), sym(rng), sym(rng)};
        float l2 = dot(v, v);
        if (l2 > 1e-4f && l2 <= 1.0f) return v * (1.0f / std::sqrt(l2));
    }
}

Vec3 randomIn(std::mt19937_64& rng, const Aabb& b) {
    Vec3 p;
    for (int a = 0; a < 3; ++a) p[a] = b.lo[a] + float(u01(rng)) * (b.hi[a] - b.lo[a]);
    return p;
}

std::string describe(const Ray& r) {
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "ray org (%.9g, %.9g, %.9g) dir (%.9g, %.9g, %.9g) t [%.9g, %.9g]", r.org.x,
                  r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax);
    return buf;
}

// --- the ray sets ---------------------------------------------------------------------------

// Rays of every kind the test plan names, for a scene whose octree root is `root` and whose
// internal node centres (split planes) are `planes`.
std::vector<Ray> makeRays(const Aabb& root, const std::vector<Vec3>& planes, int perKind,
                          uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<Ray> rays;
    const Vec3 c = root.center();
    const float diag = length(root.extent());
    // 1. From outside the root, aimed at random points inside it; half with unnormalised
    //    directions (the traversal must not assume unit length).
    for (int i = 0; i < perKind; ++i) {
        Vec3 org = c + randomUnit(rng) * (diag * float(0.8 + 2.0 * u01(rng)));
        Vec3 dir = randomIn(rng, root) - org;
        if (i % 2) dir = normalize(dir);
        rays.push_back({org, dir, 0.0f, INFINITY});
    }
    // 2. From inside the root, random directions.
    for (int i = 0; i < perKind; ++i)
        rays.push_back({randomIn(rng, root), randomUnit(rng), 0.0f, INFINITY});
    // 3. Axis-parallel: direction exactly +-x, +-y or +-z; origins inside, outside, and on the
    //    split planes of internal nodes (one or both of the other coordinates on a centre plane,
    //    so the ray runs along a face shared by two or four children).
    for (int i = 0; i < perKind; ++i) {
        int axis = static_cast<int>(rng() % 3);
        float sign = (rng() & 1) ? 1.0f : -1.0f;
        Vec3 dir = {0.0f, 0.0f, 0.0f};
        dir[axis] = sign;
        Vec3 org = randomIn(rng, root);
        int placement = static_cast<int>(rng() % 4);
        if (placement >= 1 && !planes.empty()) {
            // planes[0] is the root's centre: a quarter of these rays lie on its planes.
            Vec3 pc = (rng() % 4 == 0) ? planes[0] : planes[rng() % planes.size()];
            int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
            if (placement == 1 || placement == 3) org[a1] = pc[a1];
            if (placement == 2 || placement == 3) org[a2] = pc[a2];
        }
        if (rng() & 1)
            org[axis] = sign > 0 ? root.lo[axis] - 0.1f * diag : root.hi[axis] + 0.1f * diag;
        rays.push_back({org, dir, 0.0f, INFINITY});
    }
    // 4. Rays from outside pointing away from or past the root (mostly misses).
    for (int i = 0; i < perKind / 4; ++i) {
        Vec3 org = c + randomUnit(rng) * (1.5f * diag);
        rays.push_back({org, randomUnit(rng), 0.0f, INFINITY});
    }
    return rays;
}

// Windowed copies: the same rays with [tmin, tmax] cut around where the exhaustive hit lies (or
// anywhere for misses), including windows starting exactly at the hit or ending just past it.
std::vector<Ray> makeWindows(const std::vector<Ray>& rays, const std::vector<Hit>& hits,
                             float scale, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<Ray> out;
    for (size_t i = 0; i < rays.size(); ++i) {
        Ray r = rays[i];
        float len = length(r.dir);
        float t = hits[i].prim >= 0 ? hits[i].t : float(u01(rng)) * scale / len;
        switch (rng() % 5) {
            case 0:  // window before the hit: the nearest surface is excluded
                r.tmin = t * float(0.1 * u01(rng));
                r.tmax = t * float(0.5 + 0.5 * u01(rng));
                break;
            case 1:  // window starting past the hit: only farther surfaces count
                r.tmin = t * float(1.0 + 1e-3 + 0.5 * u01(rng));
                r.tmax = INFINITY;
                break;
            case 2:  // window ending exactly at the hit, or one float past it
                r.tmin = 0.0f;
                r.tmax = (rng() & 1) ? t : std::nextafter(t, INFINITY);
                break;
            case 3:  // window starting exactly at the hit
                r.tmin = t;
                r.tmax = t * 2.0f + 1.0f;
                break;
            default:  // a random window
                r.tmin = float(u01(rng)) * scale / len;
                r.tmax = r.tmin + float(u01(rng)) * scale / len;
        }
        out.push_back(r);
    }
    return out;
}

std::vector<Vec3> splitPlanes(const Octree& t, size_t maxCount) {
    std::vector<Vec3> planes;
    for (const OctreeNode& n : t.nodes)
        if (n.nodeType() == NodeType::Internal && planes.size() < maxCount)
            planes.push_back(n.box.center());
    return planes;
}

// --- layouts against exhaustive -------------------------------------------------------------

// Rays with their exhaustive answers, computed once and shared by every layout.
struct RaySet {
    std::vector<Ray> rays;
    std::vector<Hit> hits;  // exhaustive closestHit
};

RaySet traceExhaustive(const ExhaustiveView& ex, std::vector<Ray> rays, const char* name) {
    RaySet set;
    size_t anyMismatches = 0;
    for (const Ray& r : rays) {
        TraceCost cost = {0, 0};
        Hit h = closestHit(ex, r, cost);
        // Exhaustive anyHit against exhaustive closestHit: the hit lies within [tmin, tmax].
        bool want = h.prim >= 0 && h.t >= r.tmin && h.t <= r.tmax;
        if (anyHit(ex, r, cost) != want && ++anyMismatches <= 5)
            ADD_FAILURE() << name
                          << ": exhaustive anyHit disagrees with closestHit: " << describe(r);
        set.hits.push_back(h);
    }
    EXPECT_EQ(anyMismatches, 0u) << name;
    set.rays = std::move(rays);
    return set;
}

template <class View>
size_t compareWithExhaustive(const View& view, const RaySet& set, const char* layout) {
    size_t mismatches = 0, anyMismatches = 0;
    for (size_t i = 0; i < set.rays.size(); ++i) {
        const Ray& r = set.rays[i];
        TraceCost cost = {0, 0};
        Hit got = closestHit(view, r, cost);
        const Hit& want = set.hits[i];
        bool same =
            got.prim == want.prim && (got.t == want.t || (std::isinf(got.t) && std::isinf(want.t)));
        if (!same && ++mismatches <= 5)
            ADD_FAILURE() << layout << ": " << describe(r) << ": got t " << got.t << " prim "
                          << got.prim << ", exhaustive t " << want.t << " prim " << want.prim;
        bool wantAny = want.prim >= 0 && want.t >= r.tmin && want.t <= r.tmax;
        bool any = anyHit(view, r, cost);
        if (any != wantAny && ++anyMismatches <= 5)
            ADD_FAILURE() << layout << " anyHit " << any << ", exhaustive closest hit says "
                          << wantAny << ": " << describe(r);
    }
    EXPECT_EQ(mismatches, 0u) << layout;
    EXPECT_EQ(anyMismatches, 0u) << layout;
    return set.rays.size();
}

struct BuildConfig {
    int maxDepth;
    uint32_t maxPrims;
};

// Every octree layout of the registry over one canonical octree, against exhaustive tracing
// (the linear layout only while its complete array stays small). Returns the queries made.
size_t compareLayouts(const Scene& scene, const std::shared_ptr<const Octree>& tree,
                      const std::vector<const RaySet*>& sets) {
    size_t queries = 0;
    LayoutOptions lo;
    lo.linearBudget = 256ull << 20;
    for (const LayoutDesc& layout : layouts()) {
        if (!layout.usesOctree) continue;
        if (std::string(layout.name) == "linear" && tree->depth > 6) continue;
        BuiltScene b = convertLayout(scene, tree, layout, lo);
        b.visit([&](const auto& view) {
            for (const RaySet* set : sets)
                queries += compareWithExhaustive(view, *set, layout.name);
        });
    }
    return queries;
}

// Builds each configuration, converts it to every octree layout and compares each with
// exhaustive tracing on the rays and their windowed copies.
void checkScene(const Scene& scene, const std::vector<BuildConfig>& configs, int perKind,
                uint64_t seed) {
    const PrimitivesView prims = primitivesView(scene);
    const ExhaustiveView ex = exhaustiveView(prims);
    // The rays depend only on the root box (the same for every configuration) and on split
    // planes, taken from the last configuration.
    Octree first = buildOctree(scene, {configs.back().maxDepth, configs.back().maxPrims});
    RaySet plain =
        traceExhaustive(ex, makeRays(first.root, splitPlanes(first, 4096), perKind, seed), "rays");
    RaySet windows = traceExhaustive(
        ex, makeWindows(plain.rays, plain.hits, length(first.root.extent()), seed + 1),
        "windowed rays");
    size_t queries = 0;
    for (const BuildConfig& c : configs) {
        SCOPED_TRACE("maxDepth " + std::to_string(c.maxDepth) + " maxPrims " +
                     std::to_string(c.maxPrims));
        auto t = std::make_shared<const Octree>(buildOctree(scene, {c.maxDepth, c.maxPrims}));
        queries += compareLayouts(scene, t, {&plain, &windows});
        // The hash layout with two slots a bucket as well: few slots make m grow steeply with
        // the node count (B = 2 on a 160k-node tree needs 21M buckets), so only on small trees.
        if (t->nodes.size() <= 20000) {
            HashOctree h = buildHash(*t, {2u});
            HashOctreeView hv = hashView(h, *t, prims);
            queries += compareWithExhaustive(hv, plain, "hash B=2");
            queries += compareWithExhaustive(hv, windows, "hash B=2 windowed");
        }
    }
    size_t primary = 0;
    for (const Hit& h : plain.hits) primary += h.prim >= 0;
    std::printf("[traversal] %s: %zu rays (%zu hit) + as many windowed, %zu layout queries\n",
                scene.name.c_str(), plain.rays.size(), primary, queries);
    // The rays must exercise both outcomes.
    EXPECT_GT(primary, plain.rays.size() / 8);
    EXPECT_LT(primary, plain.rays.size() * 19 / 20);
}

Scene loadMesh(const std::string& relPath) {
    return loadScene(std::string(OCT_SOURCE_DIR) + "/" + relPath);
}

const std::vector<BuildConfig> kMeshConfigs = {{7, 8}, {4, 1}, {6, 2}, {8, 2}};

TEST(TraversalVsExhaustive, Teapot) {
    checkScene(loadMesh("meshes/teapot.obj"), kMeshConfigs, 600, 1);
}
TEST(TraversalVsExhaustive, Spider) {
    checkScene(loadMesh("meshes/spider.obj"), kMeshConfigs, 600, 2);
}
TEST(TraversalVsExhaustive, Wuson) {
    checkScene(loadMesh("meshes/wuson.obj"), kMeshConfigs, 600, 3);
}

TEST(TraversalVsExhaustive, GridCloud) {
    checkScene(makeGridCloud(2000, 7), {{21, 1}, {2, 8}, {3, 1}}, 600, 4);
}

// Spheres of random radii that straddle node boundaries (unlike the grid cloud's, which each
// sit inside one cell).
TEST(TraversalVsExhaustive, RandomSpheres) {
    std::mt19937_64 rng(6);
    Scene s;
    s.name = "random spheres";
    s.kind = PrimKind::Spheres;
    for (int i = 0; i < 1000; ++i)
        s.spheres.push_back({{float(4.0 * u01(rng)), float(2.0 * u01(rng)), float(3.0 * u01(rng))},
                             float(std::pow(10.0, -2.3 + 1.5 * u01(rng)))});
    checkScene(s, {{6, 2}, {3, 8}}, 400, 7);
}

// Equal distances on different primitives must resolve to the lower id whatever order the
// leaves are visited in. Many small triangles (low ids) lie on one big triangle (the highest
// id) in the plane z = 1/2, and rays along (dx, dy, -1) from z = 5/2 hit both at exactly t = 2
// (every coordinate is dyadic, so the watertight test computes t without rounding). An oblique
// ray often meets the big triangle in a leaf it crosses before the leaf holding the hit point,
// so only the tie rule brings back the small triangle's id there.
TEST(TraversalVsExhaustive, TiesAcrossLeavesGoToLowerId) {
    Scene s;
    s.name = "coplanar ties";
    s.kind = PrimKind::Triangles;
    const float z = 0.5f, d = 1.0f / 64.0f;
    std::vector<Vec3> centres;
    for (int i = -24; i <= 24; i += 3)
        for (int j = -24; j <= 24; j += 3) centres.push_back({i / 8.0f, j / 8.0f, z});
    for (Vec3 c : centres)
        s.triangles.push_back({{c.x - d, c.y - d, z}, {c.x + d, c.y - d, z}, {c.x, c.y + d, z}});
    // Bounds in z, away from every ray.
    s.triangles.push_back({{7, 7, 3}, {7.5f, 7, 3}, {7, 7.5f, 3}});
    s.triangles.push_back({{7, 7, -2}, {7.5f, 7, -2}, {7, 7.5f, -2}});
    const int32_t big = static_cast<int32_t>(s.triangles.size());
    s.triangles.push_back({{-8, -8, z}, {8, -8, z}, {0, 8, z}});

    std::mt19937_64 rng(8);
    std::vector<Ray> rays;
    for (int i = 0; i < 4000; ++i) {
        Vec3 c = centres[rng() % centres.size()];
        // A point of the small triangle: offsets in 1/256 steps inside its half-size box.
        Vec3 p = {c.x + float(int(rng() % 5) - 2) / 256.0f,
                  c.y + float(int(rng() % 3) - 2) / 256.0f, z};
        Vec3 dir = {float(int(rng() % 3) - 1), float(int(rng() % 3) - 1), -1.0f};
        rays.push_back({p - dir * 2.0f, dir, 0.0f, INFINITY});
    }
    const PrimitivesView prims = primitivesView(s);
    RaySet set = traceExhaustive(exhaustiveView(prims), rays, "coplanar ties");
    size_t ties = 0;
    for (const Hit& h : set.hits) {
        ASSERT_EQ(h.t, 2.0f);
        ties += h.prim < big;
    }
    EXPECT_GT(ties, set.hits.size() * 9 / 10);  // the small triangle wins the tie
    for (BuildConfig c : {BuildConfig{6, 1}, BuildConfig{8, 2}, BuildConfig{4, 1}}) {
        SCOPED_TRACE("maxDepth " + std::to_string(c.maxDepth));
        compareLayouts(s, std::make_shared<const Octree>(buildOctree(s, {c.maxDepth, c.maxPrims})),
                       {&set});
    }
}

TEST(TraversalVsExhaustive, BunnyIfFetched) {
    const std::string path = std::string(OCT_SOURCE_DIR) + "/meshes/cache/bunny.obj";
    if (!std::ifstream(path).good()) GTEST_SKIP() << path << " not fetched";
    checkScene(loadScene(path), {{7, 8}}, 60, 5);
}

// The traversal keeps one entry a level (traversal.h, compact_octree.h), sized for the deepest
// tree the builder allows: a tree whose leaves reach depth kMaxOctreeDepth must be walked to the
// bottom with every level in use. Tiny triangles at distances 2^-k (k = 1 .. 22) from a point
// off every split plane stay together in a cell until its size is about their distance, so with
// one primitive a leaf the cells around the point are split down to the deepest level; one
// floor triangle gives the rays something to hit (two sharing an edge would split every cell
// along it to the bottom).
TEST(TraversalVsExhaustive, TreeDownToTheDeepestLevel) {
    Scene s;
    s.name = "staircase to depth 21";
    s.kind = PrimKind::Triangles;
    s.triangles.push_back({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}});
    s.triangles.push_back({{0, 0, 1}, {0.01f, 0, 1}, {0, 0.01f, 1}});
    const Vec3 c = {0.3f, 0.35f, 0.4f};
    constexpr int kSteps = 22;
    for (int k = 1; k <= kSteps; ++k) {
        const float d = std::ldexp(1.0f, -k), e = d / 4;
        const Vec3 p = c + Vec3{d, 0, 0};
        s.triangles.push_back({p, p + Vec3{e, 0, 0}, p + Vec3{0, e, e}});
    }
    Octree t = buildOctree(s, {kMaxOctreeDepth, 1});
    ASSERT_EQ(t.depth, kMaxOctreeDepth);
    checkScene(s, {{kMaxOctreeDepth, 1}, {kMaxOctreeDepth, 2}}, 400, 11);
    // And rays that go down the staircase: from above each step, straight at it.
    const PrimitivesView prims = primitivesView(s);
    RaySet steps;
    for (int k = 1; k <= kSteps; ++k) {
        const float d = std::ldexp(1.0f, -k), e = d / 4;
        steps.rays.push_back({c + Vec3{d + e / 4, e / 8, 2}, {0, 0, -1}, 0, INFINITY});
    }
    steps = traceExhaustive(exhaustiveView(prims), steps.rays, "down the staircase");
    auto tree = std::make_shared<const Octree>(std::move(t));
    compareLayouts(s, tree, {&steps});
}

// The order the node-record traversal visits hit children in (traversal.h, nearFirstOrder): the
// nearest first, ties to the higher octant, as a stable far-to-near sort popped from a stack
// would give. Both forms (the device's counting, the host's insertion) against that sort, for
// every hit mask and entry t drawn from few values (many ties).
TEST(TraversalOrder, BothFormsVisitNearestFirstTiesToTheHigherOctant) {
    std::mt19937_64 rng(12);
    for (uint32_t mask = 0; mask < 256; ++mask) {
        for (int trial = 0; trial < 40; ++trial) {
            float t[8];
            for (float& x : t) x = float(rng() % 4) * 0.5f - 0.25f;
            std::vector<std::pair<float, int>> hits;  // ascending octant, then a stable sort
            for (int i = 0; i < 8; ++i)
                if (mask >> i & 1u) hits.push_back({t[i], i});
            std::stable_sort(hits.begin(), hits.end(),
                             [](const auto& a, const auto& b) { return a.first > b.first; });
            uint32_t want = 0;  // popped from the back: nearest first, ties the higher octant
            for (size_t k = 0; k < hits.size(); ++k)
                want |= uint32_t(hits[hits.size() - 1 - k].second | 8) << (4 * k);
            ASSERT_EQ(nearFirstOrderByRank(t, mask), want) << "mask " << mask;
            ASSERT_EQ(nearFirstOrderBySort(t, mask), want) << "mask " << mask;
        }
    }
}

// Vec3's run-time component access (the triangle test's permutation) on temporaries and named
// vectors alike: the access once indexed past a member, which one compiler misread.
TEST(Vec3Components, ReadAndWriteByIndex) {
    const auto make = [](float a) { return Vec3{a, a + 1, a + 2}; };
    for (int i = 0; i < 3; ++i) EXPECT_EQ(make(10)[i], 10.0f + float(i));
    Vec3 v = {1, 2, 3};
    for (int i = 0; i < 3; ++i) v[i] = v[i] * 2;
    EXPECT_EQ(v.x, 2.0f);
    EXPECT_EQ(v.y, 4.0f);
    EXPECT_EQ(v.z, 6.0f);
}

// Regression: initialHit() starts the search with best = {tmax, -1}, and considerPrimitive()
// once accepted an equal t only for a lower primitive id than best.prim (-1), so closestHit()
// dropped a hit at exactly tmax that intersectTriangle() accepts and anyHit() reports.
TEST(TraversalVsExhaustive, HitExactlyAtTmax) {
    Scene s;
    s.kind = PrimKind::Triangles;
    s.triangles.push_back({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    const Ray r = {{0.25f, 0.25f, 2.0f}, {0.0f, 0.0f, -1.0f}, 0.0f, 2.0f};  // hit at t = 2
    TraceCost cost = {0, 0};
    const ExhaustiveView ex = exhaustiveView(primitivesView(s));
    EXPECT_TRUE(anyHit(ex, r, cost));
    Hit h = closestHit(ex, r, cost);
    EXPECT_EQ(h.prim, 0);
    EXPECT_EQ(h.t, 2.0f);
}

// --- ray/box slab test ----------------------------------------------------------------------

TEST(RayBox, ZeroDirectionComponents) {
    const Aabb box = {{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}};
    float t0, t1;
    // Along +x, inside the y and z slabs: enters at 1, leaves at (about) 2.
    RaySlabs r = makeRaySlabs({-1.0f, 0.5f, 0.5f}, {1.0f, 0.0f, 0.0f});
    ASSERT_TRUE(intersectBox(r, box, 0.0f, INFINITY, t0, t1));
    EXPECT_EQ(t0, 1.0f);
    EXPECT_GE(t1, 2.0f);
    EXPECT_LT(t1, 2.0f * 1.00001f);
    // Outside the y slab: never inside, whatever t.
    r = makeRaySlabs({-1.0f, 1.5f, 0.5f}, {1.0f, 0.0f, 0.0f});
    EXPECT_FALSE(intersectBox(r, box, 0.0f, INFINITY, t0, t1));
    r = makeRaySlabs({-1.0f, -1e-7f, 0.5f}, {1.0f, 0.0f, 0.0f});
    EXPECT_FALSE(intersectBox(r, box, 0.0f, INFINITY, t0, t1));
    // Exactly on the slab boundaries: touching counts (and no NaN from 0 * inf).
    for (float y : {0.0f, 1.0f}) {
        for (float z : {0.0f, 1.0f}) {
            r = makeRaySlabs({-1.0f, y, z}, {1.0f, 0.0f, 0.0f});
            ASSERT_TRUE(intersectBox(r, box, 0.0f, INFINITY, t0, t1)) << y << " " << z;
            EXPECT_EQ(t0, 1.0f);
            EXPECT_GE(t1, 2.0f);
        }
    }
    // Negative zero components give -inf reciprocals: same answers.
    r = makeRaySlabs({0.5f, 0.5f, 3.0f}, {-0.0f, -0.0f, -2.0f});
    ASSERT_TRUE(intersectBox(r, box, 0.0f, INFINITY, t0, t1));
    EXPECT_EQ(t0, 1.0f);
    EXPECT_GE(t1, 1.5f);
    r = makeRaySlabs({1.0f, 0.0f, 3.0f}, {-0.0f, 0.0f, -2.0f});
    ASSERT_TRUE(intersectBox(r, box, 0.0f, INFINITY, t0, t1));
    r = makeRaySlabs({1.0f + 1e-6f, 0.0f, 3.0f}, {-0.0f, 0.0f, -2.0f});
    EXPECT_FALSE(intersectBox(r, box, 0.0f, INFINITY, t0, t1));
    // The origin on a face plane, moving along it.
    r = makeRaySlabs({0.0f, 0.25f, -5.0f}, {0.0f, 0.0f, 1.0f});
    ASSERT_TRUE(intersectBox(r, box, 0.0f, INFINITY, t0, t1));
    EXPECT_EQ(t0, 5.0f);
    // Pointing away: the interval lies behind tmin.
    r = makeRaySlabs({-1.0f, 0.5f, 0.5f}, {-1.0f, 0.0f, 0.0f});
    EXPECT_FALSE(intersectBox(r, box, 0.0f, INFINITY, t0, t1));
    // tmax before the box.
    r = makeRaySlabs({-1.0f, 0.5f, 0.5f}, {1.0f, 0.0f, 0.0f});
    EXPECT_FALSE(intersectBox(r, box, 0.0f, 0.5f, t0, t1));
    EXPECT_TRUE(intersectBox(r, box, 0.0f, 1.0f, t0, t1));  // touching at tmax
}

TEST(RayBox, OriginInsideEntersAtTmin) {
    const Aabb box = {{-2.0f, -1.0f, 3.0f}, {2.0f, 1.0f, 4.0f}};
    std::mt19937_64 rng(17);
    for (int i = 0; i < 10000; ++i) {
        Vec3 org = randomIn(rng, box);
        Vec3 dir = randomUnit(rng);
        if (i % 3 == 0) dir[i % 9 / 3] = 0.0f;  // some zero components
        // Exit distance in double; tmin stays well before it.
        double exit = INFINITY;
        for (int a = 0; a < 3; ++a)
            if (dir[a] != 0.0f)
                exit = std::min(
                    exit, ((dir[a] > 0 ? double(box.hi[a]) : double(box.lo[a])) - org[a]) / dir[a]);
        float tmin = (i % 2) ? 0.0f : float(0.5 * exit * u01(rng));
        float t0, t1;
        ASSERT_TRUE(intersectBox(makeRaySlabs(org, dir), box, tmin, INFINITY, t0, t1));
        ASSERT_EQ(t0, tmin);
        ASSERT_GE(t1, tmin);
    }
}

// Random rays and boxes against the slab interval computed in double.
TEST(RayBox, AgreesWithDoubleSlabs) {
    std::mt19937_64 rng(18);
    size_t hits = 0;
    for (int i = 0; i < 100000; ++i) {
        Aabb box;
        for (int a = 0; a < 3; ++a) {
            float p = 4.0f * sym(rng), q = 4.0f * sym(rng);
            box.lo[a] = std::min(p, q);
            box.hi[a] = std::max(p, q);
        }
        Vec3 org = {8.0f * sym(rng), 8.0f * sym(rng), 8.0f * sym(rng)};
        // Half aimed near the box, half anywhere; a quarter with a zero component.
        Vec3 dir =
            (i % 2) ? randomUnit(rng)
                    : normalize(box.center() +
                                Vec3{sym(rng), sym(rng), sym(rng)} * (0.7f * length(box.extent())) -
                                org);
        if (i % 4 == 0) dir[static_cast<int>(rng() % 3)] = 0.0f;
        double lo = 0.0, hi = INFINITY;
        bool inside = true;
        for (int a = 0; a < 3; ++a) {
            if (dir[a] == 0.0f) {
                inside = inside && org[a] >= box.lo[a] && org[a] <= box.hi[a];
                continue;
            }
            double ta = (double(box.lo[a]) - org[a]) / dir[a];
            double tb = (double(box.hi[a]) - org[a]) / dir[a];
            lo = std::max(lo, std::min(ta, tb));
            hi = std::min(hi, std::max(ta, tb));
        }
        bool want = inside && lo <= hi;
        float t0, t1;
        bool got = intersectBox(makeRaySlabs(org, dir), box, 0.0f, INFINITY, t0, t1);
        const double tol = 1e-5 * (1.0 + std::fabs(lo) + (std::isinf(hi) ? 0.0 : std::fabs(hi)));
        if (inside && std::fabs(hi - lo) <= tol) continue;  // grazing: either answer
        ASSERT_EQ(got, want) << i;
        if (got) {
            ++hits;
            ASSERT_NEAR(t0, lo, tol) << i;
            ASSERT_GE(double(t1), hi * (1.0 - 1e-6) - 1e-6) << i;  // never short of the exit
            ASSERT_NEAR(t1, hi, tol) << i;
        }
    }
    EXPECT_GT(hits, 5000u);
}

// --- ray/triangle ---------------------------------------------------------------------------

bool hitTri(Vec3 org, Vec3 dir, const Triangle& tri, float& t, float tmin = 0.0f,
            float tmax = INFINITY) {
    return intersectTriangle(makeShearedRay(org, dir), tri, tmin, tmax, t);
}

TEST(RayTriangle, BasicHitsAndMisses) {
    const Triangle tri = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    float t;
    ASSERT_TRUE(hitTri({0.25f, 0.25f, 2.0f}, {0, 0, -1}, tri, t));
    EXPECT_EQ(t, 2.0f);
    ASSERT_TRUE(hitTri({0.25f, 0.25f, -2.0f}, {0, 0, 2}, tri, t));  // back face, scaled dir
    EXPECT_EQ(t, 1.0f);
    EXPECT_FALSE(hitTri({0.75f, 0.75f, 2.0f}, {0, 0, -1}, tri, t));  // beside it
    EXPECT_FALSE(hitTri({0.25f, 0.25f, 2.0f}, {0, 0, 1}, tri, t));   // behind the origin
    EXPECT_FALSE(hitTri({0.25f, 0.25f, 2.0f}, {0, 0, -1}, tri, t, 0.0f, 1.5f));  // past tmax
    EXPECT_TRUE(hitTri({0.25f, 0.25f, 2.0f}, {0, 0, -1}, tri, t, 0.0f, 2.0f));   // at tmax
    EXPECT_TRUE(hitTri({0.25f, 0.25f, 2.0f}, {0, 0, -1}, tri, t, 2.0f, 3.0f));   // at tmin
    EXPECT_FALSE(hitTri({0.25f, 0.25f, 2.0f}, {0, 0, -1}, tri, t, 2.5f, 3.0f));
    EXPECT_FALSE(hitTri({-1.0f, 0.25f, 0.0f}, {1, 0, 0}, tri, t));  // ray in its plane
    // Vertices and edges of a lone triangle count as hits.
    EXPECT_TRUE(hitTri({0, 0, 1}, {0, 0, -1}, tri, t));
    EXPECT_TRUE(hitTri({0.5f, 0, 1}, {0, 0, -1}, tri, t));
    EXPECT_TRUE(hitTri({0.5f, 0.5f, 1}, {0, 0, -1}, tri, t));
}

// Two triangles sharing the edge (a, b), folded by a random small angle, and rays through
// random points of that edge from random directions on either side: the watertight test must
// report at least one hit (no crack), at a distance agreeing with the double computation.
TEST(RayTriangle, SharedEdgeIsWatertight) {
    std::mt19937_64 rng(19);
    size_t both = 0;
    for (int i = 0; i < 100000; ++i) {
        float s = std::pow(10.0f, float(-2.0 + 4.0 * u01(rng)));
        Vec3 off = {100.0f * s * sym(rng), 100.0f * s * sym(rng), 100.0f * s * sym(rng)};
        Vec3 a = off + randomUnit(rng) * s, b = off + randomUnit(rng) * s;
        Vec3 e = b - a;
        Vec3 n = normalize(cross(e, randomUnit(rng)));  // a normal of the hinge
        Vec3 side = normalize(cross(n, e));             // in-plane, away from the edge
        Vec3 m = a + e * 0.5f;
        Vec3 c1 = m + side * s + n * (0.3f * s * sym(rng));
        Vec3 c2 = m - side * s + n * (0.3f * s * sym(rng));
        Triangle t1 = {a, b, c1}, t2 = {b, a, c2};  // consistent winding across the edge
        if (i % 2) t2 = {c2, a, b};
        // A point on the edge up to rounding, away from its ends (a ray passing just beyond an
        // end vertex may rightly miss both).
        Vec3 p = a + e * float(0.01 + 0.98 * u01(rng));
        // Direction within 60 degrees of the normal, from either side.
        Vec3 d = normalize(n + randomUnit(rng) * 0.5f);
        if (rng() & 1) d = -d;
        float dist = s * float(0.5 + 10.0 * u01(rng));
        Vec3 org = p - d * dist;
        float ta, tb;
        bool ha = hitTri(org, d, t1, ta), hb = hitTri(org, d, t2, tb);
        ASSERT_TRUE(ha || hb) << i << ": crack at the shared edge, "
                              << describe({org, d, 0, INFINITY});
        both += ha && hb;
        float th = ha ? ta : tb;
        ASSERT_NEAR(th, dist, 1e-3 * dist + 1e-5 * length(off)) << i;
    }
    std::printf("[traversal] shared edge: %zu of 100000 rays hit both triangles\n", both);
}

// A fan of triangles around a shared vertex: a ray straight through the vertex hits one.
TEST(RayTriangle, SharedVertexIsWatertight) {
    std::mt19937_64 rng(20);
    for (int i = 0; i < 20000; ++i) {
        Vec3 v = {10.0f * sym(rng), 10.0f * sym(rng), 10.0f * sym(rng)};
        Vec3 n = randomUnit(rng);
        Vec3 u = normalize(cross(n, randomUnit(rng))), w = cross(n, u);
        // At least 4 rim points with bounded jitter keep every fan angle below 180 degrees, so
        // the fan surrounds the vertex.
        const int k = 4 + static_cast<int>(rng() % 6);
        std::vector<Vec3> rim;
        for (int j = 0; j < k; ++j) {
            float ang = 2.0f * 3.14159265f * (float(j) + 0.2f * sym(rng)) / float(k);
            rim.push_back(v + (u * std::cos(ang) + w * std::sin(ang)) + n * (0.2f * sym(rng)));
        }
        Vec3 d = normalize(n + randomUnit(rng) * 0.4f);
        Vec3 org = v - d * 3.0f;
        bool any = false;
        for (int j = 0; j < k; ++j) {
            float t;
            any = any || hitTri(org, d, {v, rim[j], rim[(j + 1) % k]}, t);
        }
        ASSERT_TRUE(any) << i << ": ray through a fan's vertex missed every triangle";
    }
}

// Random rays against random triangles: hit or miss and the distance as in a double-precision
// barycentric computation, away from the edges (where rounding may decide either way).
TEST(RayTriangle, AgreesWithDoubleReference) {
    std::mt19937_64 rng(21);
    size_t hits = 0, compared = 0;
    for (int i = 0; i < 100000; ++i) {
        Triangle tri = {{sym(rng), sym(rng), sym(rng)},
                        {sym(rng), sym(rng), sym(rng)},
                        {sym(rng), sym(rng), sym(rng)}};
        Vec3 org = randomUnit(rng) * 3.0f;
        Vec3 dir = normalize(Vec3{0.7f * sym(rng), 0.7f * sym(rng), 0.7f * sym(rng)} - org);
        // Double Moller-Trumbore with exact barycentrics.
        auto D = [](Vec3 v) { return std::array<double, 3>{v.x, v.y, v.z}; };
        auto sub = [](std::array<double, 3> x, std::array<double, 3> y) {
            return std::array<double, 3>{x[0] - y[0], x[1] - y[1], x[2] - y[2]};
        };
        auto crs = [](std::array<double, 3> x, std::array<double, 3> y) {
            return std::array<double, 3>{x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2],
                                         x[0] * y[1] - x[1] * y[0]};
        };
        auto dt = [](std::array<double, 3> x, std::array<double, 3> y) {
            return x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
        };
        auto e1 = sub(D(tri.v1), D(tri.v0)), e2 = sub(D(tri.v2), D(tri.v0));
        auto pv = crs(D(dir), e2);
        double det = dt(e1, pv);
        if (std::fabs(det) < 1e-3) continue;  // grazing
        auto tv = sub(D(org), D(tri.v0));
        double bu = dt(tv, pv) / det;
        auto qv = crs(tv, e1);
        double bv = dt(D(dir), qv) / det;
        double tt = dt(e2, qv) / det;
        double margin = std::min({bu, bv, 1.0 - bu - bv});
        if (std::fabs(margin) < 1e-4 || std::fabs(tt) < 1e-4) continue;  // near an edge
        bool want = margin > 0.0 && tt > 0.0;
        float t;
        bool got = hitTri(org, dir, tri, t);
        ++compared;
        ASSERT_EQ(got, want) << i;
        if (got) {
            ++hits;
            ASSERT_NEAR(t, tt, 1e-5 * (1.0 + tt)) << i;
        }
    }
    EXPECT_GT(compared, 80000u);
    EXPECT_GT(hits, 10000u);
}

// --- ray/sphere -----------------------------------------------------------------------------

bool hitSphere(Vec3 org, Vec3 dir, Sphere s, float& t, float tmin = 0.0f, float tmax = INFINITY) {
    return intersectSphere(org, dir, s, tmin, tmax, t);
}

TEST(RaySphere, HandMade) {
    const Sphere s = {{0, 0, 0}, 1.0f};
    float t;
    ASSERT_TRUE(hitSphere({0, 0, -5}, {0, 0, 1}, s, t));  // from outside: near side
    EXPECT_EQ(t, 4.0f);
    ASSERT_TRUE(hitSphere({0, 0, -5}, {0, 0, 2}, s, t));  // unnormalised direction
    EXPECT_EQ(t, 2.0f);
    ASSERT_TRUE(hitSphere({0, 0, 0}, {1, 0, 0}, s, t));  // from the centre: far side
    EXPECT_EQ(t, 1.0f);
    ASSERT_TRUE(hitSphere({0, 0.5f, 0}, {0, 1, 0}, s, t));  // from inside, off centre
    EXPECT_EQ(t, 0.5f);
    ASSERT_TRUE(hitSphere({0, 0.5f, 0}, {0, -1, 0}, s, t));
    EXPECT_EQ(t, 1.5f);
    EXPECT_FALSE(hitSphere({0, 0, 5}, {0, 0, 1}, s, t));               // sphere behind the origin
    EXPECT_FALSE(hitSphere({0, 0, -5}, {0, 0, 1}, s, t, 0.0f, 3.9f));  // beyond tmax
    ASSERT_TRUE(hitSphere({0, 0, -5}, {0, 0, 1}, s, t, 4.5f, 10.0f));  // near root cut off
    EXPECT_EQ(t, 6.0f);
    // Tangent-ish: passing just inside the rim hits near t = 5, just outside misses.
    ASSERT_TRUE(hitSphere({0, 1.0f - 1e-4f, -5}, {0, 0, 1}, s, t));
    EXPECT_NEAR(t, 5.0f, 0.02f);
    EXPECT_FALSE(hitSphere({0, 1.0f + 1e-4f, -5}, {0, 0, 1}, s, t));
    // Far away and small: the closest-approach form keeps the discriminant accurate.
    const Sphere tiny = {{0, 0, 1000.0f}, 1e-3f};
    ASSERT_TRUE(hitSphere({5e-4f, 0, 0}, {0, 0, 1}, tiny, t));
    EXPECT_NEAR(t, 1000.0f - 8.66e-4f, 1e-3f);
    EXPECT_FALSE(hitSphere({1.1e-3f, 0, 0}, {0, 0, 1}, tiny, t));
}

TEST(RaySphere, AgreesWithDoubleReference) {
    std::mt19937_64 rng(22);
    size_t hits = 0, compared = 0;
    for (int i = 0; i < 100000; ++i) {
        Sphere s = {{5.0f * sym(rng), 5.0f * sym(rng), 5.0f * sym(rng)},
                    float(0.05 + 2.0 * u01(rng))};
        Vec3 org = {10.0f * sym(rng), 10.0f * sym(rng), 10.0f * sym(rng)};
        Vec3 dir = normalize(s.center + randomUnit(rng) * (2.0f * s.radius) - org);
        if (i % 3 == 0) dir = dir * float(0.1 + 5.0 * u01(rng));
        double f[3], d[3];
        for (int a = 0; a < 3; ++a) {
            f[a] = double(org[a]) - s.center[a];
            d[a] = dir[a];
        }
        double A = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        double B = f[0] * d[0] + f[1] * d[1] + f[2] * d[2];
        double C = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] - double(s.radius) * s.radius;
        double disc = B * B - A * C;
        double r2 = double(s.radius) * s.radius;
        if (std::fabs(disc) < 1e-4 * A * r2) continue;  // tangent: either answer
        double want = -1.0;
        if (disc > 0.0) {
            double sq = std::sqrt(disc);
            double t0 = (-B - sq) / A, t1 = (-B + sq) / A;
            if (std::fabs(t0) < 1e-4 || std::fabs(t1) < 1e-4) continue;  // at the origin
            want = t0 > 0.0 ? t0 : (t1 > 0.0 ? t1 : -1.0);
        }
        float t;
        bool got = hitSphere(org, dir, s, t);
        ++compared;
        ASSERT_EQ(got, want > 0.0) << i;
        if (got) {
            ++hits;
            ASSERT_NEAR(t, want, 1e-5 * (1.0 + want)) << i;
        }
    }
    EXPECT_GT(compared, 90000u);
    EXPECT_GT(hits, 10000u);
}

}  // namespace
}  // namespace oct
