// A leaf's triangle list tested four at a time (core/geometry/triangle_batch.h, the host's path
// without an observer) gives what testing one triangle at a time gives (the path every
// observer, CUDA and WebAssembly take): the same closest hit to the bit, the same primitive on
// ties, the same test count, the same stop for any-hit queries and the same fault for a list
// that leaves its arrays. Inputs are made to reach every lane verdict: integer grids whose
// edges and vertices rays cross exactly (edge functions exactly zero), triangles in the ray's
// plane, slivers, degenerate triangles, and hits exactly at tmax.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <vector>

#include "core/octree/leaf_list.h"

namespace oct {
namespace {

// Any observer other than NoObserver takes the one-at-a-time loop.
struct OneAtATime : NoObserver {};

struct LeafRun {
    LeafOutcome outcome;
    Hit best;
    uint32_t tested;
};

template <bool kAnyHit, class Obs>
LeafRun run(const std::vector<uint32_t>& list, uint32_t offset, uint32_t count,
            const std::vector<Triangle>& tris, const Ray& ray) {
    const ArraySpan<uint32_t> span{list.data(), list.size()};
    const PrimitivesView prims{tris.data(), nullptr, uint32_t(tris.size()), PrimKind::Triangles};
    const PreparedRay q = prepareRay(ray);
    Hit best = initialHit(ray);
    TraceCost cost{0, 0};
    Obs obs;
    const LeafOutcome out = testLeafList<kAnyHit>(span, offset, count, prims, q, best, cost, obs);
    return {out, best, cost.primsTested};
}

template <bool kAnyHit>
void expectSame(const std::vector<uint32_t>& list, uint32_t offset, uint32_t count,
                const std::vector<Triangle>& tris, const Ray& ray, const char* what) {
    const LeafRun batched = run<kAnyHit, NoObserver>(list, offset, count, tris, ray);
    const LeafRun single = run<kAnyHit, OneAtATime>(list, offset, count, tris, ray);
    ASSERT_EQ(int(batched.outcome), int(single.outcome)) << what;
    ASSERT_EQ(batched.best.prim, single.best.prim) << what;
    ASSERT_EQ(std::memcmp(&batched.best.t, &single.best.t, sizeof(float)), 0)
        << what << ": t " << batched.best.t << " against " << single.best.t;
    ASSERT_EQ(batched.tested, single.tested) << what;
}

Vec3 v3(float x, float y, float z) { return {x, y, z}; }

// A grid of unit squares on z = 0, two triangles each, sharing edges and vertices; a few
// stacked copies at other heights (hits at equal t across different primitives when a copy
// repeats), slivers, a degenerate triangle and one standing in the plane x = 0.5.
std::vector<Triangle> adversarialTriangles() {
    std::vector<Triangle> t;
    for (int z = 0; z < 3; ++z)
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                const float x = float(i), y = float(j), h = float(z) * 0.5f;
                t.push_back({v3(x, y, h), v3(x + 1, y, h), v3(x + 1, y + 1, h)});
                t.push_back({v3(x, y, h), v3(x + 1, y + 1, h), v3(x, y + 1, h)});
            }
    t.push_back(t[4]);  // a duplicate: a tie in t
    t.push_back({v3(0, 0, 0.25f), v3(3, 1e-4f, 0.25f), v3(3, 0, 0.25f)});  // a sliver
    t.push_back({v3(0, 0, 0.75f), v3(1, 1, 0.75f), v3(2, 2, 0.75f)});      // collinear
    t.push_back({v3(0.5f, 0, 0), v3(0.5f, 3, 0), v3(0.5f, 0, 1)});         // in the plane x = 0.5
    return t;
}

std::vector<Triangle> randomTriangles(std::mt19937& rng, int n) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), small(-0.2f, 0.2f);
    std::vector<Triangle> t;
    for (int i = 0; i < n; ++i) {
        const Vec3 c = v3(u(rng), u(rng), u(rng));
        t.push_back({c + v3(small(rng), small(rng), small(rng)),
                     c + v3(small(rng), small(rng), small(rng)),
                     c + v3(small(rng), small(rng), small(rng))});
    }
    return t;
}

std::vector<uint32_t> allIds(size_t n) {
    std::vector<uint32_t> ids(n);
    for (size_t i = 0; i < n; ++i) ids[i] = uint32_t(i);
    return ids;
}

TEST(LeafBatch, SameHitsAndCostsAsOneTriangleAtATimeOnEdgesVerticesAndTies) {
    const std::vector<Triangle> tris = adversarialTriangles();
    // Ascending ids, and descending: a later entry with a lower id at the same t (the
    // duplicate) must win the tie exactly as it does one at a time.
    const std::vector<uint32_t> ascending = allIds(tris.size());
    const std::vector<uint32_t> descending(ascending.rbegin(), ascending.rend());
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> cell(0, 12);
    int rays = 0;
    // Rays through grid points and half points (exactly on edges and vertices), straight down,
    // slanted along an axis, along a diagonal, and lying in the planes z = 0 and x = 0.5.
    const Vec3 dirs[] = {v3(0, 0, -1), v3(0, 0, 1),      v3(0.5f, 0, -1), v3(0.25f, 0.25f, -1),
                         v3(1, 0, 0),  v3(0, 1, 1e-30f), v3(0, 1, 0),     v3(1, 1, -0.125f)};
    for (int trial = 0; trial < 400; ++trial) {
        const Vec3 org =
            v3(float(cell(rng)) * 0.25f, float(cell(rng)) * 0.25f, trial % 3 == 0 ? 0.0f : 2.0f);
        for (const Vec3& d : dirs) {
            for (float tmax : {INFINITY, 2.0f, 1.5f, 1.0f}) {  // hits at exactly tmax included
                const Ray ray{org, d, 0.0f, tmax};
                // Every list length and offset: full batches, short last batches, one triangle.
                for (const std::vector<uint32_t>* list : {&ascending, &descending})
                    for (uint32_t count : {1u, 3u, 4u, 5u, uint32_t(list->size())}) {
                        const uint32_t offset =
                            uint32_t(trial) % uint32_t(list->size() - count + 1);
                        expectSame<false>(*list, offset, count, tris, ray, "closest");
                        expectSame<true>(*list, offset, count, tris, ray, "any");
                        ++rays;
                    }
            }
        }
    }
    EXPECT_GT(rays, 10000);
}

// Rays aimed at a point inside a random triangle, among copies of the first sixteen triangles
// under other ids: ties in t between two ids, met in either order, decided against the closest
// hit so far as one at a time decides them.
TEST(LeafBatch, SameHitsAsOneTriangleAtATimeOnSeededRandomTrianglesAndCopies) {
    std::mt19937 rng(20261206);
    std::vector<Triangle> tris = randomTriangles(rng, 48);
    for (int i = 0; i < 16; ++i) tris.push_back(tris[size_t(i)]);
    std::vector<uint32_t> list = allIds(tris.size());
    std::uniform_real_distribution<float> u(-1.5f, 1.5f), bary(0.0f, 1.0f);
    std::uniform_int_distribution<size_t> pick(0, tris.size() - 1);
    int hits = 0;
    for (int i = 0; i < 4000; ++i) {
        std::shuffle(list.begin(), list.end(), rng);
        const Triangle& aim = tris[pick(rng)];
        float a = bary(rng), b = bary(rng);
        if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
        const Vec3 target = aim.v0 + (aim.v1 - aim.v0) * a + (aim.v2 - aim.v0) * b;
        const Vec3 org = v3(u(rng), u(rng), u(rng));
        const Ray ray{org, target - org, 0.0f, INFINITY};
        expectSame<false>(list, 0, uint32_t(list.size()), tris, ray, "closest");
        expectSame<true>(list, 0, uint32_t(list.size()), tris, ray, "any");
        hits += run<false, NoObserver>(list, 0, uint32_t(list.size()), tris, ray).best.prim >= 0;
    }
    EXPECT_GT(hits, 3000);  // aimed rays hit (a few graze their triangle's edge and miss)
}

// A list that leaves the index array, or names a primitive past the scene, at each position:
// the entries before it are tested (an any-hit query may stop there, found), then the fault.
TEST(LeafBatch, AFaultyEntryStopsAtTheSameEntryAsOneAtATime) {
    const std::vector<Triangle> tris = adversarialTriangles();
    const Ray down{v3(0.3f, 0.6f, 2.0f), v3(0, 0, -1), 0.0f, INFINITY};
    for (uint32_t bad = 0; bad < 9; ++bad) {
        std::vector<uint32_t> list = allIds(9);
        list[bad] = uint32_t(tris.size()) + 5;  // no such primitive
        expectSame<false>(list, 0, 9, tris, down, "primitive past the scene");
        expectSame<true>(list, 0, 9, tris, down, "primitive past the scene, any hit");
        const std::vector<uint32_t> shortList(list.begin(), list.begin() + bad);
        expectSame<false>(shortList, 0, 9, tris, down, "list past the index array");
        expectSame<true>(shortList, 0, 9, tris, down, "list past the index array, any hit");
        EXPECT_EQ(int(run<false, NoObserver>(list, 0, 9, tris, down).outcome),
                  int(LeafOutcome::Fault));
    }
}

}  // namespace
}  // namespace oct
