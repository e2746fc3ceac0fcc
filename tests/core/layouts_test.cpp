// The canonical octree (core/octree/builder.cpp) and its linear and hash layouts
// (core/octree/linear_layout.cpp, hash_layout.cpp), checked against invariants computed
// independently of the code under test: Morton ancestry, volumes, a double-precision brute-force
// triangle/box test (brute_sat.h), a breadth-first walk for linear positions, and trial-division
// primes.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <set>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "core/octree/built_scene.h"
#include "core/octree/morton.h"
#include "core/scene/grid_cloud.h"
#include "tests/core/brute_sat.h"
#include "tests/seeded.h"

namespace oct {
namespace {

glm::dvec3 d3(Vec3 v) { return {double(v.x), double(v.y), double(v.z)}; }

using octtest::u01;

// A triangle soup in a non-cubic box: triangles of sizes from 1e-3 to 0.5 of the box, some
// axis-parallel, some slivers.
Scene randomSoup(uint32_t n, uint64_t seed) {
    std::mt19937_64 rng(seed);
    Scene s;
    s.name = "soup:" + std::to_string(n) + ":" + std::to_string(seed);
    s.kind = PrimKind::Triangles;
    const double lo[3] = {-3.0, 1.0, 0.0}, size[3] = {8.0, 1.0, 4.0};
    for (uint32_t i = 0; i < n; ++i) {
        double c[3];
        for (int a = 0; a < 3; ++a) c[a] = lo[a] + size[a] * u01(rng);
        double r = std::pow(10.0, -3.0 + 2.7 * u01(rng));
        double v[3][3];
        for (auto& vi : v)
            for (int a = 0; a < 3; ++a) vi[a] = c[a] + r * (2.0 * u01(rng) - 1.0);
        int kind = static_cast<int>(rng() % 6);
        if (kind == 0) {  // axis-parallel: all three in a plane of constant coordinate
            int axis = static_cast<int>(rng() % 3);
            v[1][axis] = v[2][axis] = v[0][axis];
        } else if (kind == 1) {  // sliver
            double t = u01(rng);
            for (int a = 0; a < 3; ++a) v[2][a] = v[0][a] + t * (v[1][a] - v[0][a]) + 1e-5 * r;
        }
        Triangle t;
        t.v0 = {float(v[0][0]), float(v[0][1]), float(v[0][2])};
        t.v1 = {float(v[1][0]), float(v[1][1]), float(v[1][2])};
        t.v2 = {float(v[2][0]), float(v[2][1]), float(v[2][2])};
        s.triangles.push_back(t);
        s.sourceFace.push_back(i);
    }
    return s;
}

struct BuildConfig {
    int maxDepth;
    uint32_t maxPrims;
    operator BuildParams() const { return {maxDepth, maxPrims}; }
};

bool isLeafType(NodeType t) { return t == NodeType::Leaf || t == NodeType::EmptyLeaf; }

double volume(const Aabb& b) {
    return (double(b.hi.x) - b.lo.x) * (double(b.hi.y) - b.lo.y) * (double(b.hi.z) - b.lo.z);
}

bool sameBox(const Aabb& a, const Aabb& b) {
    return a.lo.x == b.lo.x && a.lo.y == b.lo.y && a.lo.z == b.lo.z && a.hi.x == b.hi.x &&
           a.hi.y == b.hi.y && a.hi.z == b.hi.z;
}

bool sameRecord(const OctreeNode& a, const OctreeNode& b) {
    return a.key == b.key && a.primOffset == b.primOffset && a.primCount == b.primCount &&
           sameBox(a.box, b.box) && a.type == b.type && a.depth == b.depth;
}

// A leaf's primitives no split could separate (builder.cpp): all the same primitive (the same
// vertices in any order; the same centre and radius), or all spheres containing the leaf's box.
bool inseparableLeaf(const Scene& s, const Octree& t, const OctreeNode& n) {
    auto sortedVertices = [](const Triangle& tri) {
        std::vector<std::array<float, 3>> v = {{tri.v0.x, tri.v0.y, tri.v0.z},
                                               {tri.v1.x, tri.v1.y, tri.v1.z},
                                               {tri.v2.x, tri.v2.y, tri.v2.z}};
        std::sort(v.begin(), v.end());
        return v;
    };
    bool same = true, contain = true;
    const uint32_t first = t.primIndices[n.primOffset];
    for (uint32_t k = 0; k < n.primCount; ++k) {
        const uint32_t p = t.primIndices[n.primOffset + k];
        if (s.kind == PrimKind::Triangles) {
            same = same && sortedVertices(s.triangles[p]) == sortedVertices(s.triangles[first]);
            contain = false;
            continue;
        }
        const Sphere& a = s.spheres[p];
        const Sphere& b = s.spheres[first];
        same = same && a.center.x == b.center.x && a.center.y == b.center.y &&
               a.center.z == b.center.z && a.radius == b.radius;
        for (int cx = 0; cx < 2; ++cx)
            for (int cy = 0; cy < 2; ++cy)
                for (int cz = 0; cz < 2; ++cz) {
                    double dx = double(cx ? n.box.hi.x : n.box.lo.x) - a.center.x;
                    double dy = double(cy ? n.box.hi.y : n.box.lo.y) - a.center.y;
                    double dz = double(cz ? n.box.hi.z : n.box.lo.z) - a.center.z;
                    contain = contain &&
                              dx * dx + dy * dy + dz * dz <= double(a.radius) * double(a.radius);
                }
    }
    return same || contain;
}

// Structure of the canonical tree: (a) and (d) of the test plan.
void checkStructure(const Octree& t, const Scene& s) {
    SCOPED_TRACE("structure");
    ASSERT_FALSE(t.nodes.empty());
    ASSERT_EQ(t.nodes.size(), t.firstChild.size());
    ASSERT_EQ(t.nodes[0].key, kRootKey);
    ASSERT_TRUE(sameBox(t.nodes[0].box, t.root));
    ASSERT_EQ(t.nodes[0].depth, 0);

    std::vector<int> parentCount(t.nodes.size(), 0);
    size_t internal = 0, leaves = 0, empty = 0;
    int maxDepth = 0;
    std::set<uint64_t> allKeys, leafKeys;
    uint64_t refs = 0;
    std::vector<std::pair<uint32_t, uint32_t>> lists;  // (offset, count) of leaves
    for (size_t i = 0; i < t.nodes.size(); ++i) {
        const OctreeNode& n = t.nodes[i];
        ASSERT_TRUE(allKeys.insert(n.key).second) << "duplicate key " << n.key;
        ASSERT_EQ(int(n.depth), keyDepth(n.key));
        ASSERT_LE(int(n.depth), t.effectiveMaxDepth);
        if (i > 0) {
            ASSERT_GE(n.depth, t.nodes[i - 1].depth) << "not breadth first at " << i;
        }
        maxDepth = std::max(maxDepth, int(n.depth));
        NodeType type = n.nodeType();
        if (type == NodeType::Internal) {
            ++internal;
            ASSERT_EQ(n.primCount, 0u);
            ASSERT_LT(int(n.depth), t.effectiveMaxDepth);
            uint32_t fc = t.firstChild[i];
            ASSERT_NE(fc, Octree::kNoChild);
            ASSERT_LE(uint64_t(fc) + 8, t.nodes.size());
            ASSERT_GT(fc, i);
            for (int c = 0; c < 8; ++c) {
                const OctreeNode& ch = t.nodes[fc + c];
                ++parentCount[fc + c];
                ASSERT_EQ(ch.key, childKey(n.key, c));
                ASSERT_EQ(ch.depth, n.depth + 1);
                ASSERT_TRUE(sameBox(ch.box, childBox(n.box, c))) << "node " << fc + c;
            }
        } else {
            ASSERT_TRUE(isLeafType(type)) << "node " << i << " has type " << int(n.type);
            ASSERT_EQ(t.firstChild[i], Octree::kNoChild);
            leafKeys.insert(n.key);
            if (type == NodeType::Leaf) {
                ++leaves;
                ASSERT_GT(n.primCount, 0u);
            } else {
                ++empty;
                ASSERT_EQ(n.primCount, 0u);
            }
            // A leaf too full to be one must be at the depth limit, or hold primitives that no
            // split could separate.
            if (n.primCount > t.params.maxPrims && int(n.depth) != t.effectiveMaxDepth) {
                ASSERT_TRUE(inseparableLeaf(s, t, n)) << "leaf " << i << " of " << n.primCount;
            }
            ASSERT_LE(uint64_t(n.primOffset) + n.primCount, t.primIndices.size());
            for (uint32_t k = 1; k < n.primCount; ++k)
                ASSERT_LT(t.primIndices[n.primOffset + k - 1], t.primIndices[n.primOffset + k])
                    << "leaf " << i << " list not ascending";
            for (uint32_t k = 0; k < n.primCount; ++k)
                ASSERT_LT(t.primIndices[n.primOffset + k], t.primitiveCount);
            refs += n.primCount;
            if (n.primCount) lists.push_back({n.primOffset, n.primCount});
        }
    }
    ASSERT_EQ(internal + leaves + empty, t.nodes.size());
    ASSERT_EQ(t.nodes.size(), 8 * internal + 1);  // a full octree
    ASSERT_EQ(maxDepth, t.depth);
    ASSERT_EQ(refs, t.primIndices.size());
    ASSERT_EQ(t.referenceCount(), refs);
    // Leaf lists partition the index array.
    std::sort(lists.begin(), lists.end());
    uint64_t expectOffset = 0;
    for (auto& l : lists) {
        ASSERT_EQ(l.first, expectOffset);
        expectOffset += l.second;
    }
    // Every node but the root is the child of exactly one internal node.
    ASSERT_EQ(parentCount[0], 0);
    for (size_t i = 1; i < t.nodes.size(); ++i) ASSERT_EQ(parentCount[i], 1) << "node " << i;

    // Leaves tile the root: no leaf is an ancestor of another (disjoint interiors), every
    // ancestor of a leaf is a node of the tree, and the volumes add up.
    double leafVolume = 0.0;
    for (const OctreeNode& n : t.nodes) {
        if (!isLeafType(n.nodeType())) continue;
        leafVolume += volume(n.box);
        for (uint64_t k = parentKey(n.key); k >= kRootKey; k = parentKey(k)) {
            ASSERT_EQ(leafKeys.count(k), 0u) << "leaf " << n.key << " lies in leaf " << k;
            ASSERT_EQ(allKeys.count(k), 1u);
        }
    }
    EXPECT_NEAR(leafVolume, volume(t.root), 1e-9 * volume(t.root));
}

// (b): every leaf a triangle overlaps (exact double SAT) lists it, and every listed triangle
// overlaps its leaf up to the float-rounding band of brute_sat.h.
void checkTriangleReferences(const Scene& s, const Octree& t, size_t* checkedPairs) {
    SCOPED_TRACE("triangle references");
    size_t pairs = 0;
    for (const OctreeNode& n : t.nodes) {
        if (!isLeafType(n.nodeType())) continue;
        std::vector<uint32_t> listed(t.primIndices.begin() + n.primOffset,
                                     t.primIndices.begin() + n.primOffset + n.primCount);
        for (uint32_t p = 0; p < s.triangles.size(); ++p) {
            const Triangle& tri = s.triangles[p];
            octtest::SatResult r = octtest::bruteSat(d3(n.box.lo), d3(n.box.hi), d3(tri.v0),
                                                     d3(tri.v1), d3(tri.v2), 1e-6);
            bool inList = std::binary_search(listed.begin(), listed.end(), p);
            ++pairs;
            if (r.overlap) {
                ASSERT_TRUE(inList) << "triangle " << p << " overlaps leaf " << n.key
                                    << " but is not listed (gap " << r.maxScaledGap << ")";
            } else if (!r.borderline) {
                ASSERT_FALSE(inList) << "triangle " << p << " listed in leaf " << n.key
                                     << " it clearly misses (gap " << r.maxScaledGap << ")";
            }
        }
    }
    *checkedPairs = pairs;
}

TEST(Builder, RandomSoupInvariantsAndReferences) {
    struct Config {
        uint32_t tris;
        uint64_t seed;
        int maxDepth;
        uint32_t maxPrims;
    };
    const Config configs[] = {{300, 1, 8, 1}, {300, 2, 6, 2}, {200, 3, 10, 1}, {50, 4, 0, 1}};
    for (const Config& c : configs) {
        SCOPED_TRACE("soup seed " + std::to_string(c.seed));
        Scene s = randomSoup(c.tris, c.seed);
        Octree t = buildOctree(s, {c.maxDepth, c.maxPrims});
        EXPECT_EQ(t.primitiveCount, c.tris);
        EXPECT_EQ(t.effectiveMaxDepth, c.maxDepth);
        // The root is a cube containing every vertex.
        Vec3 e = t.root.extent();
        EXPECT_EQ(e.x, e.y);
        EXPECT_EQ(e.y, e.z);
        for (const Triangle& tri : s.triangles)
            for (Vec3 v : {tri.v0, tri.v1, tri.v2}) ASSERT_TRUE(t.root.contains(v));
        checkStructure(t, s);
        EXPECT_GE(t.depth, std::min(c.maxDepth, 5));  // deep enough to matter
        size_t pairs = 0;
        checkTriangleReferences(s, t, &pairs);
        EXPECT_GT(pairs, 0u);
    }
}

// A scene with BuildParams::spatialOrderFrom triangles or more is built reading them in a
// spatial order, and its leaves' lists are put back into the scene's indices: the tree is the
// one the file's order gives, node for node and list for list, and passes the same independent
// checks (lists ascending, every overlapping triangle listed and no clear miss, by brute force).
TEST(Builder, SpatialOrderBuildsTheFileOrdersTree) {
    struct Config {
        uint32_t tris;
        uint64_t seed;
        int maxDepth;
        uint32_t maxPrims;
        bool bruteForce;
    };
    const Config configs[] = {{300, 1, 8, 1, true}, {300, 2, 6, 2, true}, {5000, 5, 7, 4, false}};
    for (const Config& c : configs) {
        SCOPED_TRACE("soup seed " + std::to_string(c.seed));
        const Scene s = randomSoup(c.tris, c.seed);
        BuildParams spatial, fileOrder;
        spatial.maxDepth = fileOrder.maxDepth = c.maxDepth;
        spatial.maxPrims = fileOrder.maxPrims = c.maxPrims;
        spatial.spatialOrderFrom = 0;
        fileOrder.spatialOrderFrom = UINT32_MAX;
        const Octree a = buildOctree(s, spatial), b = buildOctree(s, fileOrder);
        checkStructure(a, s);
        if (c.bruteForce) {
            size_t pairs = 0;
            checkTriangleReferences(s, a, &pairs);
            EXPECT_GT(pairs, 0u);
        }
        ASSERT_EQ(a.nodes.size(), b.nodes.size());
        EXPECT_GE(a.depth, std::min(c.maxDepth, 5));  // deep enough to matter
        for (size_t i = 0; i < a.nodes.size(); ++i) {
            const OctreeNode &x = a.nodes[i], &y = b.nodes[i];
            ASSERT_EQ(x.key, y.key) << "node " << i;
            ASSERT_EQ(x.type, y.type) << "node " << i;
            ASSERT_EQ(x.primOffset, y.primOffset) << "node " << i;
            ASSERT_EQ(x.primCount, y.primCount) << "node " << i;
            ASSERT_TRUE(sameBox(x.box, y.box)) << "node " << i;
        }
        EXPECT_EQ(a.firstChild, b.firstChild);
        EXPECT_EQ(a.primIndices, b.primIndices);
    }
}

// Spheres of random radii straddling node boundaries: every leaf a sphere overlaps (closest
// point of the box within the radius, in double) lists it, and no leaf lists a sphere that
// clearly misses it.
TEST(Builder, RandomSpheresReferences) {
    std::mt19937_64 rng(12);
    Scene s;
    s.kind = PrimKind::Spheres;
    for (int i = 0; i < 300; ++i)
        s.spheres.push_back({{float(-1.0 + 3.0 * u01(rng)), float(2.0 * u01(rng)), float(u01(rng))},
                             float(std::pow(10.0, -3.0 + 2.3 * u01(rng)))});
    for (BuildConfig c : {BuildConfig{7, 1}, BuildConfig{5, 3}}) {
        Octree t = buildOctree(s, c);
        EXPECT_EQ(t.effectiveMaxDepth, c.maxDepth);
        checkStructure(t, s);
        for (const Sphere& sp : s.spheres)
            for (int a = 0; a < 3; ++a) {
                ASSERT_GE(sp.center[a] - sp.radius, t.root.lo[a]);
                ASSERT_LE(sp.center[a] + sp.radius, t.root.hi[a]);
            }
        for (const OctreeNode& n : t.nodes) {
            if (!isLeafType(n.nodeType())) continue;
            const uint32_t* list = t.primIndices.data() + n.primOffset;
            for (uint32_t p = 0; p < s.spheres.size(); ++p) {
                const Sphere& sp = s.spheres[p];
                double d2 = 0.0;
                for (int a = 0; a < 3; ++a) {
                    double c = sp.center[a];
                    double q = std::min(std::max(c, double(n.box.lo[a])), double(n.box.hi[a]));
                    d2 += (c - q) * (c - q);
                }
                double r2 = double(sp.radius) * sp.radius;
                bool inList = std::binary_search(list, list + n.primCount, p);
                if (d2 <= r2) {
                    ASSERT_TRUE(inList) << "sphere " << p << " overlaps leaf " << n.key;
                } else if (d2 > r2 * (1.0 + 1e-6)) {
                    ASSERT_FALSE(inList) << "sphere " << p << " listed in leaf " << n.key;
                }
            }
        }
    }
}

// Regression (see TriBox.BuilderCountsTouchingOnBoxWithInexactCentre): triangles lying exactly
// in an internal node's face plane were dropped from every leaf when the float centres of the
// two boxes sharing that face rounded away from it.
TEST(Builder, TrianglesLyingInNodeFacesAreReferenced) {
    std::mt19937_64 rng(3);
    size_t lost = 0;
    for (int trial = 0; trial < 50; ++trial) {
        Scene s;
        s.kind = PrimKind::Triangles;
        float o[3], size = float(0.5 + 3.0 * u01(rng));
        for (float& x : o) x = float(10.0 * u01(rng));
        // Two small triangles at opposite corners fix the scene's bounds.
        s.triangles.push_back(
            {{o[0], o[1], o[2]}, {o[0] + 0.01f, o[1], o[2]}, {o[0], o[1] + 0.01f, o[2]}});
        Vec3 f = {o[0] + size, o[1] + size, o[2] + size};
        s.triangles.push_back({f, f - Vec3{0.01f, 0, 0}, f - Vec3{0, 0.01f, 0}});
        // Triangles in the plane x = X of a node face at depth 1..3.
        Aabb b = rootCube(s);
        for (int d = 0; d < 1 + trial % 3; ++d) b = childBox(b, (d % 2) ? 0 : 7);
        Vec3 c = b.center();
        for (int k = 0; k < 10; ++k)
            s.triangles.push_back({{b.lo.x, c.y, c.z},
                                   {b.lo.x, c.y + 0.01f + 0.001f * k, c.z},
                                   {b.lo.x, c.y, c.z + 0.01f}});
        Octree t = buildOctree(s, {6, 1});
        std::vector<int> seen(s.triangles.size(), 0);
        for (const OctreeNode& n : t.nodes)
            for (uint32_t k = 0; k < n.primCount; ++k) ++seen[t.primIndices[n.primOffset + k]];
        for (int v : seen) lost += v == 0;
    }
    EXPECT_EQ(lost, 0u);
}

// (c): a grid cloud's spheres each lie in exactly one leaf, strictly inside its box.
TEST(Builder, GridCloudOneSpherePerLeaf) {
    for (uint32_t n : {1000u, 4096u, 5000u}) {
        SCOPED_TRACE("grid " + std::to_string(n));
        Scene s = makeGridCloud(n, 11);
        Octree t = buildOctree(s, {21, 1});
        int gridDepth = s.gridDepth;
        EXPECT_EQ(t.effectiveMaxDepth, gridDepth);  // clamped from 21
        EXPECT_EQ(t.depth, gridDepth);
        checkStructure(t, s);
        std::vector<int> refs(n, 0);
        std::vector<const OctreeNode*> leafOf(n, nullptr);
        for (const OctreeNode& node : t.nodes) {
            EXPECT_LE(node.primCount, 1u);
            for (uint32_t k = 0; k < node.primCount; ++k) {
                uint32_t p = t.primIndices[node.primOffset + k];
                ++refs[p];
                leafOf[p] = &node;
            }
        }
        std::unordered_map<uint64_t, const OctreeNode*> byKey;
        for (const OctreeNode& node : t.nodes) byKey[node.key] = &node;
        for (uint32_t p = 0; p < n; ++p) {
            ASSERT_EQ(refs[p], 1) << "sphere " << p;
            const Sphere& sp = s.spheres[p];
            const Aabb& b = leafOf[p]->box;
            for (int a = 0; a < 3; ++a) {
                ASSERT_GT(double(sp.center[a]) - sp.radius, double(b.lo[a])) << "sphere " << p;
                ASSERT_LT(double(sp.center[a]) + sp.radius, double(b.hi[a])) << "sphere " << p;
            }
            // Independently: the deepest grid cell holding the centre, found by Morton
            // encoding, is that leaf or lies below it.
            uint32_t cell[3];
            for (int a = 0; a < 3; ++a)
                cell[a] =
                    static_cast<uint32_t>(std::floor(double(sp.center[a]) * (1 << gridDepth)));
            uint64_t k = encodeMorton(cell[0], cell[1], cell[2], gridDepth);
            while (k > kRootKey && byKey.count(k) == 0) k = parentKey(k);
            ASSERT_EQ(k, leafOf[p]->key) << "sphere " << p;
        }
        // Every occupied leaf holds one sphere: as many Leaf nodes as spheres.
        size_t leafCount = 0;
        for (const OctreeNode& node : t.nodes) leafCount += node.nodeType() == NodeType::Leaf;
        EXPECT_EQ(leafCount, n);
    }
}

TEST(Builder, BadParametersThrow) {
    Scene s = randomSoup(10, 5);
    EXPECT_THROW(buildOctree(s, {22, 8}), OctreeError);
    EXPECT_THROW(buildOctree(s, {-1, 8}), OctreeError);
    EXPECT_THROW(buildOctree(s, {7, 0}), OctreeError);
    EXPECT_NO_THROW(buildOctree(s, {21, 8}));
    EXPECT_NO_THROW(buildOctree(s, {0, 1}));
    Scene empty;
    EXPECT_THROW(buildOctree(empty, {7, 8}), OctreeError);
    try {
        buildOctree(s, {22, 8});
    } catch (const OctreeError& e) {
        EXPECT_NE(std::string(e.what()).find("22"), std::string::npos) << e.what();
    }
}

// --- linear ---------------------------------------------------------------------------------

// (8^(d+1) - 1) / 7 in 128-bit arithmetic.
unsigned __int128 completeCount(int d) {
    unsigned __int128 p = 1;
    for (int i = 0; i <= d; ++i) p *= 8;
    return (p - 1) / 7;
}

TEST(Linear, NodeCountFormulaAndSaturation) {
    const uint64_t kMax = ~uint64_t(0);
    for (int d = 0; d <= 20; ++d) {
        ASSERT_EQ(linearNodeCount(d), uint64_t(completeCount(d))) << "depth " << d;
        unsigned __int128 bytes = completeCount(d) * sizeof(OctreeNode);
        uint64_t expect = bytes > kMax ? kMax : uint64_t(bytes);
        ASSERT_EQ(linearBytes(d), expect) << "depth " << d;
    }
    EXPECT_EQ(linearNodeCount(21), kMax);
    EXPECT_EQ(linearNodeCount(30), kMax);
    EXPECT_EQ(linearBytes(21), kMax);
    EXPECT_EQ(linearNodeCount(0), 1u);
    EXPECT_EQ(linearNodeCount(1), 9u);
    EXPECT_EQ(linearNodeCount(2), 73u);
}

// Linear positions by walking the canonical tree from the root with the 8p+1+i rule, not via
// linearIndexOfKey().
void checkLinear(const Octree& t, const LinearOctree& lin) {
    ASSERT_EQ(lin.nodes.size(), uint64_t(completeCount(t.depth)));
    ASSERT_EQ(lin.nodes.size(), linearNodeCount(t.depth));
    std::vector<uint64_t> pos(t.nodes.size(), ~uint64_t(0));
    pos[0] = 0;
    std::vector<bool> used(lin.nodes.size(), false);
    for (size_t i = 0; i < t.nodes.size(); ++i) {
        ASSERT_NE(pos[i], ~uint64_t(0));
        ASSERT_TRUE(sameRecord(lin.nodes[pos[i]], t.nodes[i])) << "node " << i;
        ASSERT_EQ(pos[i], linearIndexOfKey(t.nodes[i].key));
        used[pos[i]] = true;
        if (t.firstChild[i] != Octree::kNoChild)
            for (int c = 0; c < 8; ++c) pos[t.firstChild[i] + c] = 8 * pos[i] + 1 + c;
    }
    size_t invalid = 0;
    for (size_t p = 0; p < lin.nodes.size(); ++p)
        if (!used[p]) {
            ASSERT_EQ(lin.nodes[p].nodeType(), NodeType::Invalid) << "position " << p;
            ++invalid;
        }
    ASSERT_EQ(invalid + t.nodes.size(), lin.nodes.size());
}

TEST(Linear, NodesAtTheirCompleteTreePositions) {
    {
        Scene s = randomSoup(300, 21);
        Octree t = buildOctree(s, {5, 2});
        SCOPED_TRACE("soup");
        checkLinear(t, buildLinear(t));
    }
    {
        Scene s = makeGridCloud(1000, 3);
        Octree t = buildOctree(s, {21, 1});
        SCOPED_TRACE("grid");
        checkLinear(t, buildLinear(t));
    }
    {
        Scene s = randomSoup(5, 22);
        Octree t = buildOctree(s, {0, 1});  // the root alone
        LinearOctree lin = buildLinear(t);
        ASSERT_EQ(lin.nodes.size(), 1u);
        checkLinear(t, lin);
    }
}

TEST(Linear, BudgetRefusalNamesTheBytes) {
    Scene s = randomSoup(200, 23);
    Octree t = buildOctree(s, {4, 1});
    ASSERT_EQ(t.depth, 4);
    const uint64_t bytes = uint64_t(completeCount(4)) * sizeof(OctreeNode);
    EXPECT_NO_THROW(buildLinear(t, bytes));  // exactly at the budget
    try {
        buildLinear(t, bytes - 1);
        ADD_FAILURE() << "no refusal one byte under the budget";
    } catch (const OctreeError& e) {
        EXPECT_NE(std::string(e.what()).find(std::to_string(bytes)), std::string::npos) << e.what();
    }
    // A tree claiming depth 12 needs 3.8 TB: refusing it must come before any allocation (an
    // attempt would throw bad_alloc, reported differently, or exhaust memory).
    Octree deep = t;
    deep.depth = 12;
    const uint64_t deepBytes = uint64_t(completeCount(12)) * sizeof(OctreeNode);
    try {
        buildLinear(deep);
        ADD_FAILURE() << "no refusal of " << deepBytes << " bytes";
    } catch (const OctreeError& e) {
        std::string msg = e.what();
        EXPECT_NE(msg.find(std::to_string(deepBytes)), std::string::npos) << msg;
        EXPECT_NE(msg.find("budget"), std::string::npos) << msg;
    }
    // Within any budget but past the 2^32 records the traversal indexes (depth 11: 9.8 Gi):
    // refused for that, before any allocation.
    deep.depth = 11;
    try {
        buildLinear(deep, ~uint64_t(0) - 1);
        ADD_FAILURE() << "no refusal of a linear octree of depth 11";
    } catch (const OctreeError& e) {
        EXPECT_NE(std::string(e.what()).find("more than the 2^32"), std::string::npos) << e.what();
    }
    // Beyond 64 bits the figure saturates and is still refused.
    deep.depth = 21;
    EXPECT_THROW(buildLinear(deep, ~uint64_t(0) - 1), OctreeError);
}

// --- hash -----------------------------------------------------------------------------------

bool trialDivisionPrime(uint64_t n) {
    if (n < 2) return false;
    for (uint64_t d = 2; d * d <= n; ++d)
        if (n % d == 0) return false;
    return true;
}

void checkHash(const Octree& t, uint32_t B, uint64_t seed) {
    SCOPED_TRACE("B = " + std::to_string(B));
    HashOctree h = buildHash(t, {B});
    const uint64_t m = h.bucketCount;
    ASSERT_TRUE(trialDivisionPrime(m)) << m;
    ASSERT_GE(m * B, t.nodes.size());
    ASSERT_EQ(h.bucketSlots, B);
    ASSERT_EQ(h.slots.size(), m * B);
    // Bucket contents: at most B keys, each hashing to its bucket, used slots first.
    uint64_t stored = 0;
    uint32_t fullest = 0;
    for (uint64_t b = 0; b < m; ++b) {
        uint32_t used = 0;
        bool seenFree = false;
        for (uint32_t sl = 0; sl < B; ++sl) {
            const OctreeNode& n = h.slots[b * B + sl];
            if (n.key == 0) {
                seenFree = true;
                continue;
            }
            ASSERT_FALSE(seenFree) << "bucket " << b << " has a gap";
            ASSERT_EQ(n.key % m, b);
            ++used;
        }
        stored += used;
        fullest = std::max(fullest, used);
    }
    ASSERT_EQ(stored, t.nodes.size());
    ASSERT_LE(fullest, B);
    ASSERT_EQ(h.maxOccupancy, fullest);

    HashOctreeView v = hashView(h, t, PrimitivesView{});
    std::unordered_set<uint64_t> keys;
    for (const OctreeNode& n : t.nodes) {
        keys.insert(n.key);
        const OctreeNode* f = v.find(n.key);
        ASSERT_NE(f, nullptr) << "key " << n.key;
        ASSERT_TRUE(sameRecord(*f, n)) << "key " << n.key;
    }
    ASSERT_NE(v.root(), nullptr);
    ASSERT_EQ(v.root()->key, kRootKey);
    // Absent keys, valid-looking (leading 1, random digits, random depth up to 21).
    std::mt19937_64 rng(seed);
    int absent = 0;
    while (absent < 10000) {
        int depth = static_cast<int>(rng() % uint64_t(std::min(21, t.depth + 3) + 1));
        uint64_t k = kRootKey;
        for (int d = 0; d < depth; ++d) k = childKey(k, static_cast<int>(rng() & 7u));
        if (keys.count(k)) continue;
        ++absent;
        ASSERT_EQ(v.find(k), nullptr) << "absent key " << k;
    }
}

TEST(Hash, EveryNodeFoundAbsentKeysMissing) {
    Scene soup = randomSoup(300, 31);
    Octree ts = buildOctree(soup, {7, 1});
    Scene grid = makeGridCloud(5000, 9);
    Octree tg = buildOctree(grid, {21, 1});
    for (uint32_t B : {1u, 2u, 4u, 8u}) {
        checkHash(ts, B, 100 + B);
        checkHash(tg, B, 200 + B);
    }
    // Fewer slots per bucket need at least as many buckets.
    EXPECT_GE(buildHash(ts, {1}).bucketCount, buildHash(ts, {4}).bucketCount);
    EXPECT_THROW(buildHash(ts, {0}), OctreeError);
}

// A small B can need m far above the node count (B = 1 is a perfect hash); the growth of m stops
// at the budget with an error naming the sizes instead of allocating until memory runs out.
TEST(Hash, BudgetRefusalNamesTheSizes) {
    Scene soup = randomSoup(300, 31);
    Octree t = buildOctree(soup, {7, 1});
    for (uint32_t B : {1u, 2u, 4u}) {
        const HashOctree h = buildHash(t, {B});
        const uint64_t bytes = h.bucketCount * B * sizeof(OctreeNode);
        EXPECT_EQ(buildHash(t, {B, bytes}).bucketCount, h.bucketCount);  // exactly at the budget
        try {
            buildHash(t, {B, bytes - 1});
            ADD_FAILURE() << "B " << B << ": no refusal one byte under " << bytes;
        } catch (const OctreeError& e) {
            std::string msg = e.what();
            EXPECT_NE(msg.find("m = " + std::to_string(h.bucketCount)), std::string::npos) << msg;
            EXPECT_NE(msg.find("--hash-slots"), std::string::npos) << msg;
            EXPECT_NE(msg.find("budget"), std::string::npos) << msg;
        }
    }
}

TEST(Hash, SingleNodeTree) {
    Scene s = randomSoup(3, 41);
    Octree t = buildOctree(s, {0, 1});
    ASSERT_EQ(t.nodes.size(), 1u);
    for (uint32_t B : {1u, 2u}) checkHash(t, B, 300 + B);
}

}  // namespace
}  // namespace oct
