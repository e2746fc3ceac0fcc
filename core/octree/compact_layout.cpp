#include "core/octree/compact_layout.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/system/resources.h"

namespace oct {
namespace {

// What the compact layout's view points into: its records and bounds, and the canonical tree
// whose leaf index list it shares.
struct CompactArrays {
    std::shared_ptr<const Octree> tree;
    CompactOctree compact;
};

bool stored(const OctreeNode& n) {
    return n.nodeType() == NodeType::Internal ||
           (n.nodeType() == NodeType::Leaf && n.primCount > 0);
}

// --- bounds of what a cell holds (double precision) ---------------------------------------------

using P3 = std::array<double, 3>;

struct Box3 {
    P3 lo = {INFINITY, INFINITY, INFINITY};
    P3 hi = {-INFINITY, -INFINITY, -INFINITY};
    bool empty() const { return lo[0] > hi[0]; }
    void grow(const P3& p) {
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], p[a]);
            hi[a] = std::max(hi[a], p[a]);
        }
    }
    void grow(const Box3& b) {
        if (b.empty()) return;
        grow(b.lo);
        grow(b.hi);
    }
};

// The cell widened by a relative 1e-7 of its edge: clipping against it cannot lose a point of
// the closed cell to rounding (the builder's overlap test pads by 1e-9; this is wider).
Box3 paddedCell(const Aabb& cell) {
    Box3 b;
    for (int a = 0; a < 3; ++a) {
        const double pad = 1e-7 * (double(cell.hi[a]) - double(cell.lo[a])) +
                           1e-12 * std::max(std::fabs(double(cell.lo[a])), 1.0);
        b.lo[a] = double(cell.lo[a]) - pad;
        b.hi[a] = double(cell.hi[a]) + pad;
    }
    return b;
}

// Sutherland-Hodgman: the triangle clipped to the box, as the bounds of the clipped polygon.
// A triangle inside the box is its own bounds. Each of the six planes adds at most one vertex:
// at most 9. Deep leaves are small against their triangles (the bunny: 54 of 301k references
// lie inside their cell, most cross two or three planes), so this runs for nearly every
// reference: the two polygons are swapped, not copied, and each vertex's side of a plane is
// found once.
Box3 clippedTriangle(const Triangle& t, const Box3& box) {
    P3 polys[2][9];  // not zeroed: a vertex is written before it is read
    P3* poly = polys[0];
    P3* next = polys[1];
    poly[0] = P3{t.v0.x, t.v0.y, t.v0.z};
    poly[1] = P3{t.v1.x, t.v1.y, t.v1.z};
    poly[2] = P3{t.v2.x, t.v2.y, t.v2.z};
    int count = 3;
    Box3 own;
    for (int i = 0; i < 3; ++i) own.grow(poly[i]);
    bool within = true;
    for (int a = 0; a < 3; ++a) within = within && own.lo[a] >= box.lo[a] && own.hi[a] <= box.hi[a];
    if (within) return own;
    for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
            const double plane = side ? box.hi[a] : box.lo[a];
            bool in[9];
            int inside = 0;
            for (int i = 0; i < count; ++i) {
                in[i] = side ? poly[i][a] <= plane : poly[i][a] >= plane;
                inside += in[i];
            }
            // A plane with every vertex on its inner side gives back the same polygon, vertex for
            // vertex: skip it (a replicated triangle crosses one to three of its cell's six).
            if (inside == count) continue;
            if (inside == 0) return {};
            int n = 0;
            for (int i = 0, j = count - 1; i < count; j = i++) {  // j: the vertex before i
                const P3& cur = poly[i];
                const P3& prev = poly[j];
                if (in[i] != in[j]) {
                    const double s = (plane - prev[a]) / (cur[a] - prev[a]);
                    P3& x = next[n++];
                    for (int k = 0; k < 3; ++k) x[k] = prev[k] + s * (cur[k] - prev[k]);
                    x[a] = plane;
                }
                if (in[i]) next[n++] = cur;
            }
            count = n;
            std::swap(poly, next);
        }
    Box3 b;
    for (int i = 0; i < count; ++i) b.grow(poly[i]);
    return b;
}

Box3 clippedSphere(const Sphere& s, const Box3& box) {
    Box3 b;
    for (int a = 0; a < 3; ++a) {
        b.lo[a] = std::max(double(s.center[a]) - double(s.radius), box.lo[a]);
        b.hi[a] = std::min(double(s.center[a]) + double(s.radius), box.hi[a]);
        if (b.lo[a] > b.hi[a]) return {};
    }
    return b;
}

// What a leaf holds within its cell. When rounding leaves nothing (a primitive the builder
// listed only by its tolerance), the whole cell: bounds may only ever be too large.
Box3 leafGeometry(const Scene& scene, const Octree& tree, const OctreeNode& n) {
    const Box3 cell = paddedCell(n.box);
    Box3 b;
    bool lost = false;
    const uint32_t* list = tree.primIndices.data() + n.primOffset;
    // The list names triangles scattered over the scene's array (the file's order): ask for all
    // of them before the first is clipped, so their misses overlap instead of queueing.
    if (scene.kind == PrimKind::Triangles)
        for (uint32_t k = 0; k < n.primCount; ++k) __builtin_prefetch(&scene.triangles[list[k]]);
    for (uint32_t k = 0; k < n.primCount; ++k) {
        const uint32_t p = list[k];
        const Box3 c = scene.kind == PrimKind::Triangles ? clippedTriangle(scene.triangles[p], cell)
                                                         : clippedSphere(scene.spheres[p], cell);
        lost = lost || c.empty();
        b.grow(c);
    }
    return lost ? cell : b;
}

// The largest q whose plane cellLo + q * step lies at or below `g`, the smallest whose plane
// cellHi - (255 - q) * step lies at or above `g`, each checked with and without a fused
// multiply-add (the certified CUDA build has none, the fast one may contract): the kernel's
// dequantize() is conservative however it is compiled.
uint8_t quantLo(float lo, float hi, double g) {
    const float step = (hi - lo) * (1.0f / 255.0f);
    auto fits = [&](int q) {
        return double(lo + float(q) * step) <= g && double(std::fmaf(float(q), step, lo)) <= g;
    };
    if (!(step > 0.0f)) return 0;
    // Start from the real-valued answer and step down until both forms fit (a step or two).
    int q = int(std::floor((g - double(lo)) / double(step))) + 1;
    for (q = std::min(q, 255); q > 0; --q)
        if (fits(q)) return uint8_t(q);
    return 0;  // the cell's own plane, exact
}
uint8_t quantHi(float lo, float hi, double g) {
    const float step = (hi - lo) * (1.0f / 255.0f);
    auto fits = [&](int q) {
        return double(hi - float(255 - q) * step) >= g &&
               double(std::fmaf(-float(255 - q), step, hi)) >= g;
    };
    if (!(step > 0.0f)) return 255;
    int q = 255 - int(std::floor((double(hi) - g) / double(step))) - 1;
    for (q = std::max(q, 0); q < 255; ++q)
        if (fits(q)) return uint8_t(q);
    return 255;
}

QuantBounds quantise(const Box3& g, const Aabb& cell) {
    QuantBounds q{};
    for (int a = 0; a < 3; ++a) {
        q.lo[a] = quantLo(cell.lo[a], cell.hi[a], g.lo[a]);
        q.hi[a] = quantHi(cell.lo[a], cell.hi[a], g.hi[a]);
        if (q.lo[a] > q.hi[a]) q.lo[a] = q.hi[a];  // a flat slab: keep a valid box
    }
    return q;
}

// Bounds of every canonical node: the leaves in parallel, then the internal nodes children
// before parents (the tree is breadth first, so a backwards pass sees children first).
std::vector<Box3> nodeGeometry(const Scene& scene, const Octree& tree) {
    std::vector<Box3> g;
    reserveHuge(g, tree.nodes.size());  // 48 bytes a node, touched once
    g.resize(tree.nodes.size());
    const int64_t n = int64_t(tree.nodes.size());
#pragma omp parallel for schedule(dynamic, 256)
    for (int64_t i = 0; i < n; ++i) {
        const OctreeNode& node = tree.nodes[size_t(i)];
        if (node.nodeType() == NodeType::Leaf && node.primCount > 0)
            g[size_t(i)] = leafGeometry(scene, tree, node);
    }
    for (size_t i = tree.nodes.size(); i-- > 0;)
        if (tree.nodes[i].nodeType() == NodeType::Internal)
            for (int c = 0; c < 8; ++c) g[i].grow(g[tree.firstChild[i] + c]);
    return g;
}

}  // namespace

CompactOctree buildCompact(const Octree& tree, const Scene* scene) {
    CompactOctree c;
    c.rootBox = tree.root;
    if (tree.nodes.empty() || !stored(tree.nodes[0])) return c;  // nothing to hit
    c.rootIsLeaf = tree.nodes[0].nodeType() == NodeType::Leaf;
    std::vector<Box3> geometry;
    if (scene) geometry = nodeGeometry(*scene, tree);
    // Breadth first: a queue of canonical node indices in the order their records are placed;
    // an internal node's stored children are appended together, so they are adjacent.
    std::vector<uint32_t> order = {0};
    order.reserve(tree.nodes.size());
    c.nodes.reserve(tree.nodes.size());
    for (size_t at = 0; at < order.size(); ++at) {
        const OctreeNode& n = tree.nodes[order[at]];
        CompactNode rec{};
        if (n.nodeType() == NodeType::Leaf) {
            rec.a = n.primOffset;
            rec.b = n.primCount;
        } else {
            const uint32_t first = tree.firstChild[order[at]];
            uint32_t mask = 0, leaves = 0;
            rec.a = uint32_t(order.size());
            for (int i = 0; i < 8; ++i) {
                const OctreeNode& ch = tree.nodes[first + i];
                if (!stored(ch)) continue;
                mask |= 1u << i;
                if (ch.nodeType() == NodeType::Leaf) leaves |= 1u << i;
                order.push_back(first + i);
            }
            rec.b = mask | leaves << 8;
        }
        c.nodes.push_back(rec);
    }
    if (!scene) return c;
    // Each record's bounds from its canonical node's, independent of one another.
    c.bounds.resize(order.size());
    const int64_t records = int64_t(order.size());
#pragma omp parallel for schedule(static)
    for (int64_t at = 0; at < records; ++at) {
        const uint32_t i = order[size_t(at)];
        c.bounds[size_t(at)] = quantise(geometry[i], tree.nodes[i].box);
    }
    return c;
}

CompactOctreeView compactView(const CompactOctree& c, const Octree& tree, PrimitivesView prims) {
    CompactOctreeView v;
    v.nodes = spanOf(c.nodes);
    v.primIndices = spanOf(tree.primIndices);
    v.bounds = spanOf(c.bounds);
    v.prims = prims;
    v.rootBox = c.rootBox;
    v.rootIsLeaf = c.rootIsLeaf;
    return v;
}

NodeLookup lookupNode(const CompactOctreeView& v, uint64_t key) {
    NodeLookup out;
    if (v.nodes.count == 0) return out;
    uint32_t index = 0;
    bool leaf = v.rootIsLeaf != 0;
    Aabb box = v.rootBox;
    for (int d = keyDepth(key) - 1; d >= 0; --d) {
        if (leaf) return out;
        const CompactNode n = v.nodes.data[index];
        const int octant = int((key >> (3 * d)) & 7u);
        if (!((n.childMask() >> octant) & 1u)) return out;
        const uint32_t next = compactChildIndex(n, octant);
        if (next <= index || next >= v.nodes.count) {
            out.broken = true;
            return out;
        }
        index = next;
        leaf = (n.leafMask() >> octant) & 1u;
        box = childBox(box, octant);
    }
    out.found = true;
    out.box = box;
    out.type = leaf ? NodeType::Leaf : NodeType::Internal;
    if (leaf) {
        const CompactNode n = v.nodes.data[index];
        if (uint64_t(n.primOffset()) + n.primCount() > v.primIndices.count) {
            out.broken = true;
            return out;
        }
        out.list = v.primIndices.data + n.primOffset();
        out.count = n.primCount();
    }
    return out;
}

LayoutStorage CompactLayout::convert(const Scene& scene, const std::shared_ptr<const Octree>& tree,
                                     const LayoutOptions&) {
    if (tree->nodes.size() > 0xffffffffull)
        throw OctreeError("the compact layout addresses at most 2^32 nodes; this octree has " +
                          std::to_string(tree->nodes.size()) + ": lower --max-depth");
    auto arrays = std::make_shared<CompactArrays>();
    arrays->tree = tree;
    arrays->compact = buildCompact(*tree, &scene);
    // The view first: it points into *arrays, which the storage then takes over.
    const auto view = compactView(arrays->compact, *tree, primitivesView(scene));
    return makeLayoutStorage(view, std::move(arrays));
}

LayoutReport CompactLayout::report(const Scene& scene, const Octree& tree, const LayoutOptions& o) {
    auto start = std::chrono::steady_clock::now();
    LayoutStorage s = convert(scene, std::shared_ptr<const Octree>(&tree, [](const Octree*) {}), o);
    LayoutReport r;
    r.convertSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const CompactOctreeView& v = s.as<CompactOctreeView>();
    const uint64_t records = v.nodes.count;
    const uint64_t perNode = sizeof(CompactNode) + sizeof(QuantBounds);
    r.bytes = s.bytes;
    r.facts = {countFact("nodes", records),
               countFact("node_bytes", v.nodes.bytes() + v.bounds.bytes()),
               countFact("bytes_per_node", perNode), countFact("bytes", r.bytes),
               realFact("build_seconds", r.convertSeconds)};
    char line[160];
    std::snprintf(line, sizeof line,
                  "%llu nodes of %llu bytes (empty leaves not stored), %.2f MiB, built in %.3f s",
                  (unsigned long long)records, (unsigned long long)perNode,
                  double(r.bytes) / 1048576.0, r.convertSeconds);
    r.summary = line;
    return r;
}

}  // namespace oct
