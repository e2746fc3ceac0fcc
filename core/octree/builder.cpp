#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#if defined(_OPENMP)
#include <omp.h>
#endif

#include "core/geometry/tri_box.h"
#include "core/octree/edge_bound.h"
#include "core/octree/morton.h"
#include "core/octree/octree.h"
#include "core/system/resources.h"

namespace oct {
namespace {

// The builder runs the overlap test in double and widens the box by a relative 1e-9, so the
// rounding of the test itself can only add a leaf (a counted false positive), never lose one:
// a lost leaf would lose hits. Inputs are floats, exactly representable in double.
constexpr double kOverlapPad = 1e-9;

// A node's primitive list while the tree is built: ascending indices, held in a ListArena.
struct PrimList {
    const uint32_t* data = nullptr;
    uint32_t count = 0;

    const uint32_t* begin() const { return data; }
    const uint32_t* end() const { return data + count; }
    bool empty() const { return count == 0; }
    uint32_t operator[](size_t i) const { return data[i]; }
};

struct PendingNode {
    uint64_t key;
    Aabb box;
    int depth;
    PrimList prims;  // primitives overlapping this node, ascending
};

// The lists one thread makes for one level: blocks that lists are appended to, a list never
// split between two blocks, so its address holds until the arena is recycled. A thread has two,
// by the parity of the level whose lists they hold: the lists of the level being split are read
// from one while its children's are written to the other, which held the level before it, now
// stored. Recycling keeps the blocks, so after the first levels the build neither allocates,
// frees nor first-touches a list; a vector per list did all three (docs/PERFORMANCE.md,
// "Kernel choices").
class ListArena {
public:
    PrimList append(const std::vector<uint32_t>& list) {
        if (list.empty()) return {};
        while (current_ < blocks_.size() &&
               blocks_[current_].capacity() - blocks_[current_].size() < list.size())
            ++current_;
        if (current_ == blocks_.size()) {
            // Blocks double up to kLargestBlock, so small scenes keep small arenas.
            const size_t grown = blocks_.empty() ? kFirstBlock : 2 * blocks_.back().capacity();
            blocks_.emplace_back();
            reserveHuge(blocks_.back(), std::max(list.size(), std::min(grown, kLargestBlock)));
        }
        std::vector<uint32_t>& block = blocks_[current_];
        const uint32_t* at = block.data() + block.size();
        block.insert(block.end(), list.begin(), list.end());  // within capacity: `at` holds
        return {at, static_cast<uint32_t>(list.size())};
    }
    // Drops every list made, keeping the blocks for the level after next.
    void recycle() {
        for (std::vector<uint32_t>& block : blocks_) block.clear();
        current_ = 0;
    }

private:
    static constexpr size_t kFirstBlock = size_t(1) << 12;
    static constexpr size_t kLargestBlock = size_t(1) << 20;  // 4 MiB
    std::vector<std::vector<uint32_t>> blocks_;
    size_t current_ = 0;
};

// The box the builder's triangle test sees: centre and half-size in double, the half-size
// widened by kOverlapPad (builderTriangleOverlaps). Made once per cell, not once per triangle.
struct PaddedBox {
    DVec3 c, h;
};

PaddedBox paddedBox(const Aabb& box) {
    // Centre and half-size in double: a float centre can be off by half an ulp, which moves the
    // box and loses a triangle lying exactly in a face (spider.obj lost 42 references so).
    DVec3 lo = toDouble(box.lo), hi = toDouble(box.hi);
    DVec3 c = {(lo.x + hi.x) * 0.5, (lo.y + hi.y) * 0.5, (lo.z + hi.z) * 0.5};
    DVec3 h = {(hi.x - lo.x) * 0.5, (hi.y - lo.y) * 0.5, (hi.z - lo.z) * 0.5};
    double pad = kOverlapPad * std::max({h.x, h.y, h.z});
    return {c, {h.x + pad, h.y + pad, h.z + pad}};
}

bool triangleOverlapsPadded(const Triangle& tri, const PaddedBox& b) {
    // A vertex in the closed box is a shared point: overlap, without the 13 axes. Most pairs a
    // split tests that are not rejected by the bounding boxes are of this kind (a triangle is
    // small against its cell). The difference to the centre is formed as triBoxOverlap forms it.
    for (const Vec3& v : {tri.v0, tri.v1, tri.v2})
        if (std::fabs(double(v.x) - b.c.x) <= b.h.x && std::fabs(double(v.y) - b.c.y) <= b.h.y &&
            std::fabs(double(v.z) - b.c.z) <= b.h.z)
            return true;
    return triBoxOverlap(b.c, b.h, toDouble(tri.v0), toDouble(tri.v1), toDouble(tri.v2));
}

// Axes 1-3 of triBoxOverlap alone, on the triangle's float bounds: min over the vertices of
// (v - c) is (min v) - c, as rounding is monotone, so this rejects exactly the pairs those axes
// reject, and a vertex in the box would have passed them. A miss here is a miss of the whole
// test; most of a parent's triangles miss most of its 8 children so.
bool boundsMiss(const Aabb& t, const PaddedBox& b) {
    return double(t.lo.x) - b.c.x > b.h.x || double(t.hi.x) - b.c.x < -b.h.x ||
           double(t.lo.y) - b.c.y > b.h.y || double(t.hi.y) - b.c.y < -b.h.y ||
           double(t.lo.z) - b.c.z > b.h.z || double(t.hi.z) - b.c.z < -b.h.z;
}

int threadsAvailable() {
#if defined(_OPENMP)
    return omp_get_max_threads();
#else
    return 1;  // the explain page's build (WebAssembly) has no OpenMP
#endif
}

// The children on the upper half of axis k (bit k of the child index set, as childBox reads it).
constexpr unsigned kUpperHalf[3] = {0xaau, 0xccu, 0xf0u};

// The primitives as the build reads them: the scene's spheres, or its triangles and their
// float bounds (for boundsMiss) in the build's order (BuildOrder).
struct BuildPrims {
    PrimKind kind;
    const Triangle* triangles;
    const Aabb* bounds;
    const Sphere* spheres;
};

// The build reads triangles in a spatial order, not the file's: sorted by the cell of the
// 32^3 grid over the root (depth 5, Morton order) that holds the centre of their bounds, the
// file's order kept within a cell. A node's list then names triangles that sit together in
// memory, where the file's order sent each test to a cache and TLB miss (docs/PERFORMANCE.md,
// "Kernel choices"). The lists hold build indices while the tree is made; the leaves' lists
// are put back into scene indices, ascending, at the end (toSceneIndices), so the tree is the
// one the file's order gives: which triangles a cell lists does not depend on the order they
// are tested in. The arrays are written once, so they sit on huge pages (allocateHuge): on
// 4 KiB pages their first touches cost more than the order saved.
// A scene of fewer than BuildParams::spatialOrderFrom triangles (16,384) is read in its file's
// order: its triangles and bounds fit in a core's cache either way, and the sort's fixed costs
// would be much of its build.
struct BuildOrder {
    HugeArray<uint32_t> sceneIndex;  // build index -> scene index; null: the scene's order
    HugeArray<Triangle> triangles;   // in build order; null: the scene's array
    HugeArray<Aabb> bounds;          // of the triangles in build order

    BuildPrims view(const Scene& scene) const {
        return {scene.kind, triangles ? triangles.get() : scene.triangles.data(), bounds.get(),
                scene.spheres.data()};
    }
};

constexpr int kOrderDepth = 5;

// The depth-5 Morton cell of the root holding a triangle's bounds centre (clamped: a scene
// with a user domain may reach past the root).
uint32_t orderCell(const Aabb& t, const Aabb& root) {
    uint32_t cell[3];
    for (int a = 0; a < 3; ++a) {
        const float centre = 0.5f * (t.lo[a] + t.hi[a]);
        const float unit = (centre - root.lo[a]) / (root.hi[a] - root.lo[a]);
        const float scaled = unit * float(1 << kOrderDepth);
        cell[a] = scaled > 0.0f ? uint32_t(std::min(scaled, float((1 << kOrderDepth) - 1))) : 0u;
    }
    return uint32_t(dilate3(cell[0]) | dilate3(cell[1]) << 1 | dilate3(cell[2]) << 2);
}

BuildOrder makeBuildOrder(const Scene& scene, const Aabb& root, uint32_t spatialFrom) {
    BuildOrder order;
    if (scene.kind != PrimKind::Triangles) return order;
    const int64_t n = int64_t(scene.triangles.size());
    // The build index of scene triangle i (its cell first); null: the scene's order.
    HugeArray<uint32_t> place;
    if (uint64_t(n) >= spatialFrom) {
        place = makeHugeArray<uint32_t>(size_t(n));
#pragma omp parallel for schedule(static) if (n > 4096)
        for (int64_t i = 0; i < n; ++i)
            place[size_t(i)] = orderCell(boundsOf(scene.triangles[size_t(i)]), root);
        // A counting sort: stable, so the file's order stays within a cell.
        std::vector<uint32_t> start(size_t(1) << (3 * kOrderDepth), 0);
        for (int64_t i = 0; i < n; ++i) ++start[place[size_t(i)]];
        uint32_t sum = 0;
        for (uint32_t& s : start) {
            const uint32_t count = s;
            s = sum;
            sum += count;
        }
        order.sceneIndex = makeHugeArray<uint32_t>(size_t(n));
        for (uint32_t i = 0; i < uint32_t(n); ++i) {
            place[i] = start[place[i]]++;
            order.sceneIndex[place[i]] = i;
        }
        order.triangles = makeHugeArray<Triangle>(size_t(n));
    }
    // Each triangle's bounds, and in the spatial order the triangle, written at its build index
    // (the scene index in the file's order), the scene read in its order: in the spatial order
    // a gather read it at random, a cache and TLB miss a triangle (twice the time on the bunny:
    // 4 KiB pages under a virtual machine's paging).
    order.bounds = makeHugeArray<Aabb>(size_t(n));
#pragma omp parallel for schedule(static) if (n > 4096)
    for (int64_t i = 0; i < n; ++i) {
        const Triangle& t = scene.triangles[size_t(i)];
        const size_t at = place ? place[size_t(i)] : size_t(i);
        if (place) order.triangles[at] = t;
        order.bounds[at] = boundsOf(t);
    }
    return order;
}

// The primitives of `prims` the builder lists in `box`, ascending as given, into `out`.
template <class List>
void overlapping(const BuildPrims& scene, const List& prims, const Aabb& box,
                 std::vector<uint32_t>& out) {
    out.clear();
    if (scene.kind != PrimKind::Triangles) {
        for (uint32_t p : prims)
            if (builderSphereOverlaps(scene.spheres[p], box)) out.push_back(p);
        return;
    }
    const PaddedBox b = paddedBox(box);
    for (uint32_t p : prims)
        if (!boundsMiss(scene.bounds[p], b) && triangleOverlapsPadded(scene.triangles[p], b))
            out.push_back(p);
}

// What one thread of the build keeps from node to node: the 8 lists being gathered (copied into
// an arena once at their size: a list grown in place reallocates some log2(size) times), and its
// two arenas. They live as long as the build.
struct ThreadLists {
    std::array<std::vector<uint32_t>, 8> found;
    ListArena arenas[2];

    ListArena& arenaFor(int depth) { return arenas[depth & 1]; }
};

// The leaves' lists from build indices to the scene's, each ascending again.
void toSceneIndices(const BuildOrder& order, Octree& tree) {
    if (!order.sceneIndex) return;
    const int64_t count = int64_t(tree.nodes.size());
#pragma omp parallel for schedule(dynamic, 1024) if (count > 4096)
    for (int64_t n = 0; n < count; ++n) {
        const OctreeNode& node = tree.nodes[size_t(n)];
        if (node.nodeType() != NodeType::Leaf) continue;
        uint32_t* list = tree.primIndices.data() + node.primOffset;
        for (uint32_t i = 0; i < node.primCount; ++i) list[i] = order.sceneIndex[list[i]];
        std::sort(list, list + node.primCount);
    }
}

int threadIndex() {
#if defined(_OPENMP)
    return omp_get_thread_num();
#else
    return 0;
#endif
}

// Child i of a split node as the next level holds it: key, box and depth (its list comes from
// listChildren or `overlapping`).
void placeChild(const PendingNode& p, int i, PendingNode& kid) {
    kid.key = childKey(p.key, i);
    kid.box = childBox(p.box, i);
    kid.depth = p.depth + 1;
}

// The 8 children's lists in one pass over the parent's primitives. Per axis, which halves the
// triangle's bounds can reach, by boundsMiss's comparisons with the widest pad of the children
// on that half (so no child is passed over that its own test would accept); then each child so
// reached decides by its own boundsMiss and full test. The lists are those of `overlapping`,
// child by child; a triangle small against the cell reaches one child instead of being tested
// against all 8.
void listChildren(const BuildPrims& scene, const PendingNode& p, PendingNode* kids,
                  ThreadLists& work) {
    ListArena& arena = work.arenaFor(p.depth + 1);
    Aabb box[8];
    for (int i = 0; i < 8; ++i) box[i] = childBox(p.box, i);
    if (scene.kind != PrimKind::Triangles) {
        for (int i = 0; i < 8; ++i) {
            overlapping(scene, p.prims, box[i], work.found[0]);
            kids[i].prims = arena.append(work.found[0]);
        }
        return;
    }
    PaddedBox pb[8];
    for (int i = 0; i < 8; ++i) pb[i] = paddedBox(box[i]);
    // Half `side` of axis k: its centre (the same for the 4 children there) and widest half-size.
    double c[3][2], h[3][2];
    for (int k = 0; k < 3; ++k)
        for (int side = 0; side < 2; ++side) {
            c[k][side] = k == 0 ? pb[side].c.x : (k == 1 ? pb[side << 1].c.y : pb[side << 2].c.z);
            h[k][side] = 0.0;
            for (int i = 0; i < 8; ++i) {
                if (((i >> k) & 1) != side) continue;
                const double hk = k == 0 ? pb[i].h.x : (k == 1 ? pb[i].h.y : pb[i].h.z);
                h[k][side] = std::max(h[k][side], hk);
            }
        }
    std::array<std::vector<uint32_t>, 8>& found = work.found;
    for (std::vector<uint32_t>& f : found) f.clear();
    for (uint32_t prim : p.prims) {
        const Aabb& t = scene.bounds[prim];
        const double lo[3] = {t.lo.x, t.lo.y, t.lo.z}, hi[3] = {t.hi.x, t.hi.y, t.hi.z};
        unsigned reach = 0xffu;  // bit i: child i may overlap
        for (int k = 0; k < 3; ++k)
            for (int side = 0; side < 2; ++side)
                if (lo[k] - c[k][side] > h[k][side] || hi[k] - c[k][side] < -h[k][side])
                    reach &= side ? ~kUpperHalf[k] : kUpperHalf[k];
        for (; reach != 0; reach &= reach - 1) {
            const int i = __builtin_ctz(reach);
            if (!boundsMiss(t, pb[i]) && triangleOverlapsPadded(scene.triangles[prim], pb[i]))
                found[i].push_back(prim);
        }
    }
    for (int i = 0; i < 8; ++i) kids[i].prims = arena.append(found[i]);
}

bool sameTriangle(const Triangle& a, const Triangle& b) {
    return sortedVertices(a) == sortedVertices(b);
}

// Beyond the paper: no split, at any depth, can separate the node's primitives when they are
// all the same primitive (identical points, copies of one face) or all spheres containing the
// whole node: every sub-cell overlaps all of them or none. Splitting them anyway only
// multiplies nodes and references (9 identical points built 1.34 M nodes; 1,000 took 4.4 GB and
// 38 s before the reference cap refused them), so such a node stays a leaf. The traversal then
// tests the same primitives the split leaves would have listed; no other node changes.
bool inseparable(const BuildPrims& scene, const PrimList& prims, const Aabb& box) {
    if (scene.kind == PrimKind::Triangles) {
        const Triangle& first = scene.triangles[prims[0]];
        for (uint32_t p : prims)
            if (!sameTriangle(scene.triangles[p], first)) return false;
        return true;
    }
    const Sphere& first = scene.spheres[prims[0]];
    bool same = true, allContain = true;
    for (uint32_t p : prims) {
        const Sphere& s = scene.spheres[p];
        same = same && s.center.x == first.center.x && s.center.y == first.center.y &&
               s.center.z == first.center.z && s.radius == first.radius;
        // The farthest corner of the box within the radius: the sphere contains the box.
        double d2 = 0.0;
        for (int a = 0; a < 3; ++a) {
            double e = std::max(std::fabs(double(box.lo[a]) - s.center[a]),
                                std::fabs(double(box.hi[a]) - s.center[a]));
            d2 += e * e;
        }
        allContain = allContain && d2 <= double(s.radius) * double(s.radius);
        if (!same && !allContain) return false;
    }
    return true;
}

OctreeNode makeNode(const PendingNode& p, NodeType type) {
    OctreeNode n{};
    n.key = p.key;
    n.box = p.box;
    n.type = static_cast<uint8_t>(type);
    n.depth = static_cast<uint8_t>(p.depth);
    return n;
}

// What one more node of the next level costs while that level is built, for the memory check:
// its pending record (PendingNode, in the next level's array, made once at its size, into which
// its parent's split writes it).
constexpr uint64_t kBuildBytesPerNode = sizeof(PendingNode);
// A reference in a child's list: its entry in an arena, whose blocks double (so up to twice
// the entries), the thread's gathering buffer aside.
constexpr uint64_t kBuildBytesPerReference = 2 * sizeof(uint32_t);

// The new block a vector allocates to hold `needed` elements (it doubles), the old one still
// held while the elements move: 0 when its capacity suffices.
template <class T>
uint64_t growthBytes(const std::vector<T>& v, uint64_t needed) {
    if (needed <= v.capacity()) return 0;
    return std::max<uint64_t>(needed, 2 * uint64_t(v.capacity())) * sizeof(T);
}

// Grows v's room to what push_back's doubling would give (growthBytes' estimate, which the
// memory check counted), the new room advised onto huge pages before anything is copied there:
// on this project's virtual machines a first touch of each 4 KiB page costs some 18 us, and
// the tree's arrays and each level's records are written once, front to back.
template <class T>
void reserveGrowth(std::vector<T>& v, uint64_t needed) {
    if (needed <= v.capacity()) return;
    std::vector<T> grown;
    reserveHuge(grown, std::max<uint64_t>(needed, 2 * uint64_t(v.capacity())));
    grown.insert(grown.end(), std::make_move_iterator(v.begin()), std::make_move_iterator(v.end()));
    v.swap(grown);
}

// The next level's name in messages: "octree of 'quad.obj' at depth 17 (8388608 more nodes".
std::string levelText(const Scene& scene, int depth, uint64_t nodes) {
    return "octree of '" + scene.name + "' at depth " + std::to_string(depth) + " (" +
           std::to_string(nodes) + " more nodes";
}

// "octree of 'quad.obj' needs more than N nodes (the node budget)" + where + the options that
// shrink the tree: the node budget's refusal, level by level or counted before building.
OctreeError nodeBudgetRefusal(const Scene& scene, const BuildParams& params,
                              const std::string& where) {
    return OctreeError("octree of '" + scene.name + "' needs more than " +
                       std::to_string(params.maxNodes) + " nodes (the node budget)" + where +
                       ": lower --max-depth, raise --max-prims, or raise --node-budget");
}

// Refuses the next level when the tree would pass the node budget with it, or when storing
// this level (`storeBytes`) and making the next level's nodes need more memory than `left`;
// returns the bytes left for the next level's references.
uint64_t checkNextLevel(const Scene& scene, const BuildParams& params, uint64_t nodes,
                        uint64_t nextNodes, int nextDepth, uint64_t storeBytes,
                        const MemoryLimit& left) {
    if (nextDepth > params.storableDepth)
        throw OctreeError(levelText(scene, nextDepth, nextNodes) + "): " + params.depthLimit);
    if (nodes + nextNodes > params.storableNodes)
        throw OctreeError(levelText(scene, nextDepth, nextNodes) + ", " +
                          std::to_string(nodes + nextNodes) + " with it): " + params.nodeLimit);
    if (nodes + nextNodes > params.maxNodes)
        throw nodeBudgetRefusal(scene, params,
                                " at depth " + std::to_string(nextDepth) + ", " +
                                    std::to_string(nodes + nextNodes) + " with it");
    const uint64_t bytes = storeBytes + nextNodes * kBuildBytesPerNode;
    checkMemory<OctreeError>(bytes, levelText(scene, nextDepth, nextNodes) + ")",
                             "lower --max-depth or raise --max-prims", left);
    return left.bytes - bytes;
}

std::string pointText(Vec3 p) {
    char s[96];
    std::snprintf(s, sizeof s, "(%g, %g, %g)", double(p.x), double(p.y), double(p.z));
    return s;
}

// Before building: an edge that more than maxPrims triangles share is split along down to the
// deepest level the build may make (edge_bound.h). Where the cells along it alone pass what the
// layouts can store or the node budget, the build is refused at once, with the same reason the
// level-by-level check would give after building most of the tree (27-33 s for one quad).
void refuseSharedEdgesPastLimits(const Scene& scene, const Aabb& root, const BuildParams& params,
                                 int effectiveMaxDepth) {
    const int splitDepth = std::min(effectiveMaxDepth, params.storableDepth);
    const uint64_t limit = std::min(params.maxNodes, params.storableNodes);
    const std::optional<SharedEdgeBound> found =
        sharedEdgePastLimit(scene, root, params.maxPrims, splitDepth, limit);
    if (!found) return;
    const std::string why =
        "the " + std::to_string(found->edge.triangles) + " triangles sharing the edge " +
        pointText(found->edge.a) + "-" + pointText(found->edge.b) + " (more than --max-prims " +
        std::to_string(params.maxPrims) + ") split every cell along it down to depth " +
        std::to_string(splitDepth) + ", " + std::to_string(found->nodes) +
        " nodes or more, counted before building";
    if (params.storableNodes < params.maxNodes)
        throw OctreeError("octree of '" + scene.name + "': " + why + ": " + params.nodeLimit);
    throw nodeBudgetRefusal(scene, params, ": " + why);
}

void checkParams(const Scene& scene, const BuildParams& params) {
    if (params.maxDepth < 0 || params.maxDepth > kMaxOctreeDepth)
        throw OctreeError("--max-depth " + std::to_string(params.maxDepth) + " is outside [0, " +
                          std::to_string(kMaxOctreeDepth) +
                          "]: a 64-bit Morton key holds 21 levels below the root");
    if (params.maxPrims == 0)
        throw OctreeError("--max-prims 0 would split every node: use 1 or more");
    if (scene.primitiveCount() == 0)
        throw OctreeError("scene '" + scene.name + "' has no primitives to build an octree over");
}

}  // namespace

bool builderTriangleOverlaps(const Triangle& tri, const Aabb& box) {
    return triangleOverlapsPadded(tri, paddedBox(box));
}

std::array<std::array<float, 3>, 3> sortedVertices(const Triangle& t) {
    std::array<std::array<float, 3>, 3> v = {
        {{t.v0.x, t.v0.y, t.v0.z}, {t.v1.x, t.v1.y, t.v1.z}, {t.v2.x, t.v2.y, t.v2.z}}};
    std::sort(v.begin(), v.end());
    return v;
}

double sphereCentreBoxDistanceSq(const Sphere& s, const Aabb& box) {
    double d2 = 0.0;
    for (int a = 0; a < 3; ++a) {
        double c = s.center[a], lo = box.lo[a], hi = box.hi[a];
        double e = c < lo ? lo - c : (c > hi ? c - hi : 0.0);
        d2 += e * e;
    }
    return d2;
}

bool builderSphereOverlaps(const Sphere& s, const Aabb& box) {
    double d2 = sphereCentreBoxDistanceSq(s, box);
    double r = double(s.radius) * (1.0 + kOverlapPad);
    return d2 <= r * r;
}

Aabb rootCube(const Scene& scene) {
    if (scene.domain) return *scene.domain;
    Aabb b = scene.bounds();
    Vec3 c = b.center();
    Vec3 e = b.extent();
    float half = 0.5f * std::max({e.x, e.y, e.z});
    // Pad relative to the size, and by an absolute amount for a flat or point-sized scene.
    half = half * (1.0f + 1e-4f) +
           1e-6f * (1.0f + std::max({std::fabs(c.x), std::fabs(c.y), std::fabs(c.z)}));
    return {c - makeVec3(half), c + makeVec3(half)};
}

Octree buildOctree(const Scene& scene, const BuildParams& params) {
    checkParams(scene, params);
    auto start = std::chrono::steady_clock::now();

    Octree tree;
    tree.kind = scene.kind;
    tree.primitiveCount = scene.primitiveCount();
    tree.params = params;
    tree.root = rootCube(scene);
    // A grid cloud's spheres fit one per cell of depth gridDepth (grid_cloud.h); splitting
    // deeper would cut spheres in two, so the grid depth bounds the build.
    tree.effectiveMaxDepth =
        scene.gridDepth >= 0 ? std::min(params.maxDepth, scene.gridDepth) : params.maxDepth;

    refuseSharedEdgesPastLimits(scene, tree.root, params, tree.effectiveMaxDepth);

    const BuildOrder order = makeBuildOrder(scene, tree.root, params.spatialOrderFrom);
    const BuildPrims prims = order.view(scene);
    std::vector<ThreadLists> work(static_cast<size_t>(threadsAvailable()));
    // Breadth-first over one level at a time, so the 8 children of each node are adjacent
    // and levels are contiguous. Two levels' records, swapped from level to level so that their
    // pages are written once.
    std::vector<PendingNode> level(1), next;
    level[0] = {kRootKey, tree.root, 0, {}};
    {
        std::vector<uint32_t> all(tree.primitiveCount);
        for (uint32_t i = 0; i < tree.primitiveCount; ++i) all[i] = i;
        overlapping(prims, all, tree.root, work[0].found[0]);
        level[0].prims = work[0].arenaFor(0).append(work[0].found[0]);
    }

    while (!level.empty()) {
        // The arenas this level's children are listed in held the level above, now stored.
        const int nextDepth = level[0].depth + 1;
        for (ThreadLists& w : work) w.arenaFor(nextDepth).recycle();
        // Phase 1, in parallel (OpenMP, dynamic: costs differ by orders of magnitude): which
        // nodes split, then every child's list: one (node, octant) pair per iteration while the
        // level is small, so the first levels (1 and 8 nodes holding every primitive) use every
        // thread too, then a node's 8 lists per iteration (listChildren). Each list
        // reads only the scene and its parent's list, so the tree does not depend on the thread
        // count. The reference cap is checked on a shared running total, as the serial build
        // did child by child: the build is refused iff the level's total passes the cap.
        const int64_t count = int64_t(level.size());
        std::vector<uint8_t> splits(level.size(), 0);
#pragma omp parallel for schedule(dynamic, 16) if (count > 64)
        for (int64_t n = 0; n < count; ++n) {
            const PendingNode& p = level[size_t(n)];
            splits[size_t(n)] = p.prims.count > params.maxPrims &&
                                p.depth < tree.effectiveMaxDepth &&
                                !inseparable(prims, p.prims, p.box);
        }
        // The next level's nodes against the node budget and the memory left, before any of
        // its lists is made; then its references against what memory remains, as they grow.
        // The j-th split node, level[splitNodes[j]], has its children at next[8j .. 8j + 8):
        // phase 1 writes their records there, their lists in the arena of the thread that made
        // them.
        uint64_t leafRefs = 0;
        std::vector<uint32_t> splitNodes;
        for (size_t n = 0; n < level.size(); ++n) {
            if (splits[n])
                splitNodes.push_back(static_cast<uint32_t>(n));
            else
                leafRefs += level[n].prims.count;
        }
        const uint64_t splitCount = splitNodes.size();
        const uint64_t stored = tree.nodes.size() + level.size();
        const uint64_t storeBytes =
            growthBytes(tree.nodes, stored) + growthBytes(tree.firstChild, stored) +
            growthBytes(tree.primIndices, tree.primIndices.size() + leafRefs);
        const MemoryLimit left = splitCount > 0 ? memoryLimit() : MemoryLimit{};
        const uint64_t bytesLeft = splitCount == 0
                                       ? 0
                                       : checkNextLevel(scene, params, stored, 8 * splitCount,
                                                        nextDepth, storeBytes, left);
        const uint64_t refsFit = bytesLeft / kBuildBytesPerReference;
        // Its size is known: no growth copy (the check counted its records).
        next.clear();
        reserveGrowth(next, 8 * splitCount);
        next.resize(8 * splitCount);
        const uint64_t cap = params.maxReferences, storedRefs = tree.primIndices.size();
        uint64_t pendingRefs = 0;
        bool overCap = false, overMemory = false;
        // Fewer nodes than two a thread (the root, on a few cores): one job per (node, octant),
        // so every thread has work; else one per node, whose 8 lists share one pass. Only split
        // nodes are jobs: a level's leaves (all 80k of the bunny's last, 3 ms) would each cost
        // a dynamic schedule's hand-out.
        const bool perOctant = count < 2 * threadsAvailable();
        const int64_t jobs = int64_t(perOctant ? 8 * splitCount : splitCount);
#pragma omp parallel for schedule(dynamic, 1)
        for (int64_t job = 0; job < jobs; ++job) {
            const size_t j = size_t(perOctant ? job / 8 : job);
            bool over;
#pragma omp atomic read
            over = overCap;
            if (over) continue;
            const PendingNode& p = level[splitNodes[j]];
            uint64_t made = 0;
            PendingNode* kids = &next[8 * j];
            ThreadLists& mine = work[size_t(threadIndex())];
            if (perOctant) {
                const int i = int(job % 8);
                placeChild(p, i, kids[i]);
                overlapping(prims, p.prims, kids[i].box, mine.found[0]);
                kids[i].prims = mine.arenaFor(nextDepth).append(mine.found[0]);
                made = kids[i].prims.count;
            } else {
                for (int i = 0; i < 8; ++i) placeChild(p, i, kids[i]);
                listChildren(prims, p, kids, mine);
                for (int i = 0; i < 8; ++i) made += kids[i].prims.count;
            }
            uint64_t total;
#pragma omp atomic capture
            total = pendingRefs += made;
            // Large primitives replicate into most nodes: refuse before memory runs out.
            if (total + storedRefs > cap || total > refsFit) {
                if (total > refsFit) {
#pragma omp atomic write
                    overMemory = true;
                }
#pragma omp atomic write
                overCap = true;
            }
        }
        if (overMemory && pendingRefs + storedRefs <= cap)
            throw OctreeError(memoryShortfall(
                (left.bytes - bytesLeft) + pendingRefs * kBuildBytesPerReference,
                levelText(scene, nextDepth, 8 * splitCount) + ", " + std::to_string(pendingRefs) +
                    " more primitive references so far)",
                "lower --max-depth or raise --max-prims", left));
        if (overCap)
            throw OctreeError("octree of '" + scene.name + "' needs more than " +
                              std::to_string(params.maxReferences) + " primitive references (" +
                              std::to_string(params.maxReferences * 4 >> 20) +
                              " MiB): lower --max-depth or raise --max-prims");

        // Phase 2, in order: records and leaf lists, breadth first (phase 1 placed the next
        // level's records).
        reserveGrowth(tree.nodes, stored);
        reserveGrowth(tree.firstChild, stored);
        reserveGrowth(tree.primIndices, tree.primIndices.size() + leafRefs);
        for (size_t n = 0; n < level.size(); ++n) {
            const PendingNode& p = level[n];
            if (splits[n]) {
                tree.nodes.push_back(makeNode(p, NodeType::Internal));
                tree.firstChild.push_back(0);  // patched below, once the level's size is known
            } else {
                NodeType type = p.prims.empty() ? NodeType::EmptyLeaf : NodeType::Leaf;
                OctreeNode nd = makeNode(p, type);
                if (tree.primIndices.size() + p.prims.count > 0xffffffffull)
                    throw OctreeError("octree of '" + scene.name +
                                      "' needs more than 2^32 primitive references: lower "
                                      "--max-depth or raise --max-prims");
                nd.primOffset = static_cast<uint32_t>(tree.primIndices.size());
                nd.primCount = p.prims.count;
                tree.primIndices.insert(tree.primIndices.end(), p.prims.begin(), p.prims.end());
                tree.nodes.push_back(nd);
                tree.firstChild.push_back(Octree::kNoChild);
            }
            tree.depth = std::max(tree.depth, p.depth);
        }
        // Children of this level's internal nodes follow the level, in the order pushed.
        size_t levelStart = tree.nodes.size() - level.size();
        uint32_t childPos = static_cast<uint32_t>(tree.nodes.size());
        for (size_t i = levelStart; i < tree.nodes.size(); ++i) {
            if (tree.nodes[i].nodeType() != NodeType::Internal) continue;
            tree.firstChild[i] = childPos;
            childPos += 8;
        }
        level.swap(next);
    }
    toSceneIndices(order, tree);
    tree.buildSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return tree;
}

}  // namespace oct
