#include "core/octree/edge_bound.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/octree/octree.h"

namespace oct {
namespace {

// ---- Does the segment meet a closed box? -----------------------------------------------------
// Slab test (Kay & Kajiya 1986) of the segment a + t (b - a), t in [0, 1]. The box's floats
// come from the builder's childBox chain, so the grid is not exactly dyadic and a segment can
// pass exactly through a cell's corner or lie in its face (the quad's diagonal does both at
// every level): such touching cells are built (touching counts), and deciding them needs exact
// arithmetic. A fast double test settles the clear cases; the rest are decided in integers.

enum class Meets { Yes, No, Unsure };

struct EdgeProbe {
    float fa[3];  // the start point as given
    double a[3], inv[3];
    bool parallel[3];  // b == a on this axis: the whole segment has that coordinate exactly
    // The exact form: every coordinate times `scale`, a power of two, is an integer below 2^60
    // (fixedPoint); the end points A and the direction D so.
    double scale = 1.0;
    bool exact = false;
    int64_t A[3], D[3];
};

// x * scale (a power of two, so the product is exact) as an integer, when it is a whole number
// below 2^61 in magnitude.
bool fixedPoint(float x, double scale, int64_t& out) {
    const double s = double(x) * scale;
    if (!(std::fabs(s) < 0x1p61) || s != std::floor(s)) return false;
    out = int64_t(s);
    return true;
}

EdgeProbe makeProbe(const Aabb& root, Vec3 a, Vec3 b) {
    EdgeProbe p;
    float most = 0.0f;
    for (int i = 0; i < 3; ++i) {
        p.fa[i] = a[i];
        p.a[i] = a[i];
        p.parallel[i] = a[i] == b[i];
        p.inv[i] = p.parallel[i] ? 0.0 : 1.0 / (double(b[i]) - double(a[i]));
        most = std::max(
            {most, std::fabs(root.lo[i]), std::fabs(root.hi[i]), std::fabs(a[i]), std::fabs(b[i])});
    }
    // Every box of the tree lies within the root, so |coordinate| < 2^e for all of them and
    // 2^(60 - e) scales each below 2^60; differences stay below 2^61, products below 2^122.
    int e = 0;
    std::frexp(most, &e);
    p.scale = std::ldexp(1.0, 60 - e);
    p.exact = true;
    for (int i = 0; i < 3; ++i) {
        int64_t B = 0;
        p.exact = p.exact && fixedPoint(a[i], p.scale, p.A[i]) && fixedPoint(b[i], p.scale, B);
        p.D[i] = B - p.A[i];
    }
    return p;
}

// A fraction num / den with den > 0, compared exactly.
struct Fraction {
    __int128 num, den;
};
bool lessThan(const Fraction& x, const Fraction& y) { return x.num * y.den < y.num * x.den; }

// Exact: some t in [0, 1] has a + t d in [lo, hi] on every axis. Unsure when a box coordinate
// is not a whole multiple of the scale (it then cannot be counted).
Meets meetsExactly(const EdgeProbe& p, const Aabb& box) {
    if (!p.exact) return Meets::Unsure;
    Fraction enter{0, 1}, exit{1, 1};
    for (int i = 0; i < 3; ++i) {
        int64_t L = 0, H = 0;
        if (!fixedPoint(box.lo[i], p.scale, L) || !fixedPoint(box.hi[i], p.scale, H))
            return Meets::Unsure;
        if (p.D[i] == 0) {
            if (p.A[i] < L || p.A[i] > H) return Meets::No;
            continue;
        }
        const bool up = p.D[i] > 0;
        const __int128 den = up ? p.D[i] : -__int128(p.D[i]);
        const Fraction in{up ? __int128(L) - p.A[i] : __int128(p.A[i]) - H, den};
        const Fraction out{up ? __int128(H) - p.A[i] : __int128(p.A[i]) - L, den};
        if (lessThan(enter, in)) enter = in;
        if (lessThan(out, exit)) exit = out;
    }
    return lessThan(exit, enter) ? Meets::No : Meets::Yes;
}

// The segment's parameters where it crosses a cell's planes, kept per cell so that a child's
// come from its parent's and the one plane between them (the parent's centre).
struct CellPlanes {
    double t[3][2];  // t at the box's lo and hi plane on each axis (unused where parallel)
};

CellPlanes planesOf(const EdgeProbe& p, const Aabb& box) {
    CellPlanes c{};
    for (int i = 0; i < 3; ++i) {
        c.t[i][0] = (double(box.lo[i]) - p.a[i]) * p.inv[i];
        c.t[i][1] = (double(box.hi[i]) - p.a[i]) * p.inv[i];
    }
    return c;
}

// Doubles first. Each plane's t is the exact quotient within a few ulps (the float difference
// is exact in double, then one rounding for 1/d and one for the product): below 1e-15 where it
// matters, in [0, 1]. So a common interval longer than 1e-9 is one the exact segment has (Yes:
// it passes through the box), one shorter than -1e-9 misses (No), and the rest, touching or
// nearly, are decided exactly.
Meets meetsByPlanes(const EdgeProbe& p, const Aabb& box, const CellPlanes& c) {
    double tin = 0.0, tout = 1.0;
    for (int i = 0; i < 3; ++i) {
        if (p.parallel[i]) {  // float comparisons of the one coordinate: exact
            if (p.fa[i] < box.lo[i] || p.fa[i] > box.hi[i]) return Meets::No;
            continue;
        }
        tin = std::max(tin, std::min(c.t[i][0], c.t[i][1]));
        tout = std::min(tout, std::max(c.t[i][0], c.t[i][1]));
    }
    if (tout - tin > 1e-9) return Meets::Yes;
    if (tout < tin - 1e-9) return Meets::No;
    return meetsExactly(p, box);
}

// ---- Which edges are worth counting ------------------------------------------------------------

// A generous estimate of the nodes along a segment crossing `cross` root widths (the sum over
// the axes of its extent): at depth d it meets at most some cross * 2^d + 1 cells' interiors,
// each of whose points touches at most 8 cells, and never more than the 8^d cells there are.
// Edges whose estimate stays within the limit are not counted: the exact count could not pass.
double mostNodesAlong(double cross, int splitDepth) {
    double nodes = 1.0, level = 1.0;
    for (int d = 0; d < splitDepth; ++d, level *= 8.0)
        nodes += 8.0 * std::min(level, 8.0 * (cross * std::ldexp(1.0, d) + 3.0));
    return nodes;
}

// The shortest crossing (in root widths) whose estimate passes the limit; +inf when none does
// (a segment crosses at most 3 root widths).
double shortestCrossingThatCanPass(int splitDepth, uint64_t limit) {
    if (mostNodesAlong(3.0, splitDepth) <= double(limit)) return INFINITY;
    double lo = 0.0, hi = 3.0;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (mostNodesAlong(mid, splitDepth) > double(limit) ? hi : lo) = mid;
    }
    return lo;
}

using Corners = std::array<float, 6>;  // an edge's end points, the lesser first

Corners edgeKey(Vec3 p, Vec3 q) {
    std::array<float, 3> u = {p.x, p.y, p.z}, v = {q.x, q.y, q.z};
    if (v < u) std::swap(u, v);
    return {u[0], u[1], u[2], v[0], v[1], v[2]};
}

// The segment's crossing in scene units: the sum over the axes of its extent.
double crossing(Vec3 a, Vec3 b) {
    return std::fabs(double(b.x) - a.x) + std::fabs(double(b.y) - a.y) +
           std::fabs(double(b.z) - a.z);
}

// Edges long enough to pass, each with the distinct triangles that have it, most first.
std::vector<SharedEdge> longSharedEdges(const Scene& scene, double shortest, uint32_t maxPrims) {
    struct Entry {
        Corners edge;
        uint32_t tri;
    };
    std::vector<Entry> entries;
    for (uint32_t t = 0; t < uint32_t(scene.triangles.size()); ++t) {
        const Triangle& tri = scene.triangles[t];
        for (const auto& [p, q] : {std::pair{tri.v0, tri.v1}, {tri.v1, tri.v2}, {tri.v2, tri.v0}}) {
            if (crossing(p, q) > shortest) entries.push_back({edgeKey(p, q), t});
        }
    }
    std::sort(entries.begin(), entries.end(),
              [](const Entry& x, const Entry& y) { return x.edge < y.edge; });
    std::vector<SharedEdge> out;
    for (size_t i = 0; i < entries.size();) {
        size_t j = i;
        // Distinct as the builder tells copies of a face apart (sameTriangle).
        std::vector<std::array<std::array<float, 3>, 3>> distinct;
        for (; j < entries.size() && entries[j].edge == entries[i].edge; ++j)
            distinct.push_back(sortedVertices(scene.triangles[entries[j].tri]));
        std::sort(distinct.begin(), distinct.end());
        const size_t n = size_t(std::unique(distinct.begin(), distinct.end()) - distinct.begin());
        if (n > maxPrims) {
            const Corners& k = entries[i].edge;
            out.push_back({{k[0], k[1], k[2]}, {k[3], k[4], k[5]}, uint32_t(n)});
        }
        i = j;
    }
    std::sort(out.begin(), out.end(), [](const SharedEdge& x, const SharedEdge& y) {
        return crossing(x.a, x.b) > crossing(y.a, y.b);
    });
    return out;
}

// At most this many edges are counted: each count costs up to the limit's nodes, and the
// longest edges are the likeliest to pass it.
constexpr size_t kEdgesCounted = 8;

}  // namespace

EdgeNodeCount nodesAlongEdge(const Aabb& root, Vec3 a, Vec3 b, int splitDepth, uint64_t limit) {
    const EdgeProbe probe = makeProbe(root, a, b);
    struct Cell {
        Aabb box;
        CellPlanes planes;
        int depth;
    };
    const CellPlanes rootPlanes = planesOf(probe, root);
    if (meetsByPlanes(probe, root, rootPlanes) != Meets::Yes) return {};
    // Depth first: at most 7 cells wait per level, so the stack stays small.
    std::vector<Cell> stack = {{root, rootPlanes, 0}};
    stack.reserve(8 * (size_t(std::max(splitDepth, 0)) + 1));
    EdgeNodeCount count{1, false};
    while (!stack.empty()) {
        const Cell cell = stack.back();
        stack.pop_back();
        if (cell.depth >= splitDepth) continue;
        count.nodes += 8;
        if (count.nodes > limit) {
            count.passed = true;
            return count;
        }
        // The centre planes childBox splits at, and where the segment crosses them.
        const Vec3 centre = cell.box.center();
        double mid[3];
        for (int k = 0; k < 3; ++k) mid[k] = (double(centre[k]) - probe.a[k]) * probe.inv[k];
        for (int i = 0; i < 8; ++i) {
            Cell child{childBox(cell.box, i), cell.planes, cell.depth + 1};
            for (int k = 0; k < 3; ++k) child.planes.t[k][((i >> k) & 1) ? 0 : 1] = mid[k];
            if (meetsByPlanes(probe, child.box, child.planes) == Meets::Yes) stack.push_back(child);
        }
    }
    return count;
}

std::optional<SharedEdgeBound> sharedEdgePastLimit(const Scene& scene, const Aabb& root,
                                                   uint32_t maxPrims, int splitDepth,
                                                   uint64_t limit) {
    if (scene.kind != PrimKind::Triangles || splitDepth <= 0) return std::nullopt;
    const double width = std::max({double(root.hi.x) - root.lo.x, double(root.hi.y) - root.lo.y,
                                   double(root.hi.z) - root.lo.z});
    const double shortest = shortestCrossingThatCanPass(splitDepth, limit);
    if (!(width > 0.0) || std::isinf(shortest)) return std::nullopt;
    std::vector<SharedEdge> edges = longSharedEdges(scene, shortest * width, maxPrims);
    if (edges.size() > kEdgesCounted) edges.resize(kEdgesCounted);
    for (const SharedEdge& e : edges) {
        const EdgeNodeCount n = nodesAlongEdge(root, e.a, e.b, splitDepth, limit);
        if (n.passed) return SharedEdgeBound{e, n.nodes};
    }
    return std::nullopt;
}

}  // namespace oct
