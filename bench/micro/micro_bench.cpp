// Micro-benchmarks of the inner operations the paper's traversal is made of: the ray-box slab
// test every visited node pays, the ray-triangle and ray-sphere tests every tested primitive
// pays, the Morton child key the hash octree computes per child, and the hash lookup
// h(k) = k mod m with its fixed-size bucket scan, next to the linear layout's 8p+1+i.
//
// Inputs are seeded random arrays (the same on every run), cycled so the loop does not
// measure a single cached case; results go through benchmark::DoNotOptimize.
//
//   build-bench/octrace_micro                       # all
//   build-bench/octrace_micro --benchmark_filter=Hash
#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/geometry/aabb.h"
#include "core/geometry/primitives.h"
#include "core/octree/built_scene.h"
#include "core/octree/layout_registry.h"
#include "core/octree/morton.h"
#include "core/octree/traversal.h"
#include "core/scene/grid_cloud.h"

namespace oct {
namespace {

constexpr size_t kInputs = 4096;  // a power of two: index with & (kInputs - 1)

float u01(std::mt19937_64& rng) { return float(rng() >> 40) * 0x1p-24f; }
Vec3 randomPoint(std::mt19937_64& rng, float lo, float hi) {
    return {lo + (hi - lo) * u01(rng), lo + (hi - lo) * u01(rng), lo + (hi - lo) * u01(rng)};
}

// A ray from a random point around [0,1]^3 aimed at `target` moved by up to +-jitter on each
// axis: with the jitter about the primitive's size, roughly half of the rays hit, so both
// branches of each test are exercised (the hit_rate counter reports it).
Ray rayTowards(std::mt19937_64& rng, Vec3 target, float jitter) {
    Vec3 org = randomPoint(rng, -2.0f, 3.0f);
    Vec3 to = target + randomPoint(rng, -jitter, jitter);
    return {org, normalize(to - org), 0.0f, INFINITY};
}

void BM_RayBox(benchmark::State& state) {
    std::mt19937_64 rng(1);
    std::vector<Aabb> boxes(kInputs);
    std::vector<RaySlabs> slabs(kInputs);
    for (size_t k = 0; k < kInputs; ++k) {
        Vec3 lo = randomPoint(rng, 0.0f, 0.8f);
        float size = 0.05f + 0.15f * u01(rng);
        boxes[k] = {lo, lo + makeVec3(size)};
        Ray r = rayTowards(rng, boxes[k].center(), size);
        slabs[k] = makeRaySlabs(r.org, r.dir);
    }
    size_t i = 0, hits = 0;
    for (auto _ : state) {
        float t0 = 0.0f, t1 = 0.0f;
        size_t k = i++ & (kInputs - 1);
        bool hit = intersectBox(slabs[k], boxes[k], 0.0f, INFINITY, t0, t1);
        hits += hit;
        benchmark::DoNotOptimize(hit);
        benchmark::DoNotOptimize(t0);
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
    state.counters["hit_rate"] = double(hits) / double(std::max<size_t>(i, 1));
}
BENCHMARK(BM_RayBox);

void BM_RayTriangle(benchmark::State& state) {
    std::mt19937_64 rng(2);
    std::vector<Triangle> tris(kInputs);
    std::vector<ShearedRay> rays(kInputs);
    for (size_t k = 0; k < kInputs; ++k) {
        Vec3 c = randomPoint(rng, 0.2f, 0.8f);
        tris[k] = {c + randomPoint(rng, -0.1f, 0.1f), c + randomPoint(rng, -0.1f, 0.1f),
                   c + randomPoint(rng, -0.1f, 0.1f)};
        Vec3 centroid = (tris[k].v0 + tris[k].v1 + tris[k].v2) * (1.0f / 3.0f);
        Ray r = rayTowards(rng, centroid, 0.03f);
        rays[k] = makeShearedRay(r.org, r.dir);
    }
    size_t i = 0, hits = 0;
    for (auto _ : state) {
        float t = 0.0f;
        size_t k = i++ & (kInputs - 1);
        bool hit = intersectTriangle(rays[k], tris[k], 0.0f, INFINITY, t);
        hits += hit;
        benchmark::DoNotOptimize(hit);
        benchmark::DoNotOptimize(t);
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
    state.counters["hit_rate"] = double(hits) / double(std::max<size_t>(i, 1));
}
BENCHMARK(BM_RayTriangle);

// makeShearedRay is paid once per ray (prepareRay), not per triangle: measured apart.
void BM_ShearRay(benchmark::State& state) {
    std::mt19937_64 rng(3);
    std::vector<Ray> rays(kInputs);
    for (Ray& r : rays) r = rayTowards(rng, randomPoint(rng, 0.0f, 1.0f), 0.0f);
    size_t i = 0;
    for (auto _ : state) {
        const Ray& r = rays[i++ & (kInputs - 1)];
        ShearedRay s = makeShearedRay(r.org, r.dir);
        benchmark::DoNotOptimize(s);
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_ShearRay);

void BM_RaySphere(benchmark::State& state) {
    std::mt19937_64 rng(4);
    std::vector<Sphere> spheres(kInputs);
    std::vector<Ray> rays(kInputs);
    for (size_t k = 0; k < kInputs; ++k) {
        spheres[k] = {randomPoint(rng, 0.2f, 0.8f), 0.02f + 0.1f * u01(rng)};
        rays[k] = rayTowards(rng, spheres[k].center, 1.2f * spheres[k].radius);
    }
    size_t i = 0, hits = 0;
    for (auto _ : state) {
        float t = 0.0f;
        size_t k = i++ & (kInputs - 1);
        const Ray& r = rays[k];
        bool hit = intersectSphere(r.org, r.dir, spheres[k], 0.0f, INFINITY, t);
        hits += hit;
        benchmark::DoNotOptimize(hit);
        benchmark::DoNotOptimize(t);
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
    state.counters["hit_rate"] = double(hits) / double(std::max<size_t>(i, 1));
}
BENCHMARK(BM_RaySphere);

// Random keys of depth 0..20 (so a child of depth <= 21 still fits in 64 bits).
std::vector<uint64_t> randomKeys(uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<uint64_t> keys(kInputs);
    for (uint64_t& k : keys) {
        int depth = int(rng() % 21);
        k = (uint64_t(1) << (3 * depth)) | (rng() & ((uint64_t(1) << (3 * depth)) - 1));
    }
    return keys;
}

void BM_MortonChildKey(benchmark::State& state) {
    std::vector<uint64_t> keys = randomKeys(8);
    size_t i = 0;
    for (auto _ : state) {
        size_t k = i++;
        uint64_t c = childKey(keys[k & (kInputs - 1)], int(k & 7));
        benchmark::DoNotOptimize(c);
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_MortonChildKey);

// The cell key of (x, y, z) at a depth: bit dilation, as the builder and tests use it.
void BM_MortonEncode(benchmark::State& state) {
    std::mt19937_64 rng(9);
    std::vector<uint32_t> xyz(3 * kInputs);
    for (uint32_t& v : xyz) v = uint32_t(rng() & 0x1fffff);
    size_t i = 0;
    for (auto _ : state) {
        size_t k = 3 * (i++ & (kInputs - 1));
        uint64_t key = encodeMorton(xyz[k], xyz[k + 1], xyz[k + 2], 21);
        benchmark::DoNotOptimize(key);
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_MortonEncode);

// A grid cloud's octree (one sphere per deepest leaf, as octrace bench builds it) in both
// layouts, and the children of its internal nodes as lookups.
struct LayoutFixture {
    Scene scene;
    Octree tree;
    HashOctree hash;
    LinearOctree linear;
    std::vector<uint64_t> presentKeys;  // children that exist in the tree
    std::vector<uint64_t> absentKeys;   // children of leaves: not stored
    std::vector<uint64_t> parents;      // linear positions of internal nodes

    explicit LayoutFixture(uint32_t n) : scene(makeGridCloud(n, 1)) {
        BuildParams p;
        p.maxDepth = kMaxOctreeDepth;  // clamped to the grid depth by the builder
        p.maxPrims = 1;
        tree = buildOctree(scene, p);
        hash = buildHash(tree);
        linear = buildLinear(tree);
        std::mt19937_64 rng(10);
        for (const OctreeNode& node : tree.nodes) {
            if (node.nodeType() == NodeType::Internal) {
                presentKeys.push_back(childKey(node.key, int(rng() & 7)));
                parents.push_back(linearIndexOfKey(node.key));
            } else if (node.depth < kMaxOctreeDepth) {
                absentKeys.push_back(childKey(node.key, int(rng() & 7)));
            }
        }
        std::shuffle(presentKeys.begin(), presentKeys.end(), rng);
        std::shuffle(absentKeys.begin(), absentKeys.end(), rng);
        std::shuffle(parents.begin(), parents.end(), rng);
    }
};

const LayoutFixture& fixture(uint32_t n) {
    static std::map<uint32_t, LayoutFixture> cache;
    auto it = cache.find(n);
    if (it == cache.end()) it = cache.emplace(n, LayoutFixture(n)).first;
    return it->second;
}

void BM_HashLookup(benchmark::State& state) {
    const LayoutFixture& f = fixture(uint32_t(state.range(0)));
    HashOctreeView v = hashView(f.hash, f.tree, primitivesView(f.scene));
    const std::vector<uint64_t>& keys = state.range(1) ? f.presentKeys : f.absentKeys;
    // The key index wraps with a compare, not `%`: a 64-bit division per lookup would be timed
    // with it (the layout's own k mod m is the cost being measured).
    size_t i = 0, calls = 0, found = 0;
    for (auto _ : state) {
        const OctreeNode* n = v.find(keys[i]);
        if (++i == keys.size()) i = 0;
        ++calls;
        found += n != nullptr;
        benchmark::DoNotOptimize(n);
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
    state.counters["found_rate"] = double(found) / double(std::max<size_t>(calls, 1));
    state.counters["buckets_m"] = double(f.hash.bucketCount);
    state.counters["max_bucket"] = double(f.hash.maxOccupancy);
    state.SetLabel(state.range(1) ? "present keys" : "absent keys");
}
BENCHMARK(BM_HashLookup)->ArgsProduct({{4000, 32000, 256000}, {1, 0}});

// The linear layout's child address for the same trees: 8p + 1 + i, then a load of the type.
void BM_LinearChild(benchmark::State& state) {
    const LayoutFixture& f = fixture(uint32_t(state.range(0)));
    LinearOctreeView v = linearView(f.linear, f.tree, primitivesView(f.scene));
    // The child's type is copied to a local before DoNotOptimize: on a const lvalue the asm
    // barrier may take a memory operand, and no load was timed at all. The parent index wraps
    // with a compare, as in BM_HashLookup.
    size_t i = 0, k = 0;
    NoObserver none;
    for (auto _ : state) {
        const OctreeNode* at = v.nodes.data + f.parents[i];
        const OctreeNode* c = v.child(at, at->key, int(k++ & 7), none);
        if (++i == f.parents.size()) i = 0;
        uint8_t type = c->type;
        benchmark::DoNotOptimize(type);
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_LinearChild)->Arg(4000)->Arg(32000)->Arg(256000);

// The node test per child, for every layout of the registry: a grid cloud's octree traced by
// random rays through the layout's own closestHit, the time divided by the children it tested
// (TraceCost::nodesVisited: a node-record layout's box test with its child lookup, the compact
// layout's share of its eight-lane test and its bounds test at pop). Primitive tests are timed
// too; prims_per_child says how much of the time they can be.
struct TraversalFixture {
    Scene scene;
    std::shared_ptr<const Octree> tree;
    std::vector<Ray> rays;
};

const TraversalFixture& traversalFixture(uint32_t n) {
    static std::map<uint32_t, TraversalFixture> cache;
    auto it = cache.find(n);
    if (it != cache.end()) return it->second;
    TraversalFixture f{makeGridCloud(n, 1), nullptr, {}};
    BuildParams p;
    p.maxDepth = kMaxOctreeDepth;  // clamped to the grid depth by the builder
    p.maxPrims = 1;
    f.tree = buildSharedOctree(f.scene, p);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = 0; i < 4096; ++i) {  // from a sphere around the [0,1]^3 domain, through it
        const Vec3 target = {u(rng), u(rng), u(rng)};
        const Vec3 from = {4.0f * u(rng) - 1.5f, 4.0f * u(rng) - 1.5f, -2.0f};
        f.rays.push_back({from, target - from, 0.0f, INFINITY});
    }
    return cache.emplace(n, std::move(f)).first->second;
}

void traversalPerChild(benchmark::State& state, const LayoutDesc* layout) {
    const TraversalFixture& f = traversalFixture(uint32_t(state.range(0)));
    LayoutOptions options;
    options.build = f.tree->params;
    const BuiltScene built = convertLayout(f.scene, f.tree, *layout, options);
    uint64_t children = 0, prims = 0;
    built.visit([&](const auto& view) {
        size_t i = 0;
        for (auto _ : state) {
            TraceCost cost = {0, 0};
            Hit h = closestHit(view, f.rays[i], cost);
            benchmark::DoNotOptimize(h);
            children += cost.nodesVisited;
            prims += cost.primsTested;
            if (++i == f.rays.size()) i = 0;
        }
    });
    state.SetItemsProcessed(int64_t(children));  // items/s: children tested per second
    state.counters["children_per_ray"] = double(children) / double(state.iterations());
    state.counters["prims_per_child"] = double(prims) / double(std::max<uint64_t>(children, 1));
    state.SetLabel(std::string(layout->name) + ": ns per child = 1e9 / items_per_second");
}

const bool kTraversalRegistered = [] {
    for (const LayoutDesc& l : layouts())
        if (l.usesOctree)
            benchmark::RegisterBenchmark((std::string("BM_TraversalPerChild/") + l.name).c_str(),
                                         traversalPerChild, &l)
                ->Arg(16000)
                ->Arg(256000);
    return true;
}();

}  // namespace
}  // namespace oct

BENCHMARK_MAIN();
