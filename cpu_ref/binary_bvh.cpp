// The binary BVH's builder: top-down binned SAH after Wald, "On fast construction of SAH-based
// bounding volume hierarchies" (IEEE Symposium on Interactive Ray Tracing, 2007). Each node's
// triangles are binned by centroid into kBvhBins equal slices of the centroids' bounds along
// each axis; the plane between two bins with the least surface area heuristic cost splits them,
// unless a leaf costs no more (or the node is small enough to be a leaf anyway).
#include "cpu_ref/binary_bvh.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <string>

namespace oct {
namespace {

// The SAH's two costs (MacDonald & Booth 1990, as Wald 2007 uses them): a node's cost is one
// traversal step plus the triangles its children's boxes make the ray test, weighted by the
// chance (surface area ratio) that a ray meeting the node meets each child.
constexpr float kTraversalCost = 1.0f;
constexpr float kIntersectionCost = 1.0f;

// Half the surface area (the factor 2 cancels in every ratio the SAH takes).
float halfArea(const Aabb& b) {
    const Vec3 e = b.extent();
    return e.x * e.y + e.y * e.z + e.z * e.x;
}

// The union of two boxes; an empty box (emptyAabb: lo +inf, hi -inf) changes nothing, as an
// empty bin must not (growing by its corners would make the union infinite).
// By compare and select (minf, maxf), which inline, where vmin's fminf is a libm call.
Aabb merged(const Aabb& a, const Aabb& b) {
    return {{minf(a.lo.x, b.lo.x), minf(a.lo.y, b.lo.y), minf(a.lo.z, b.lo.z)},
            {maxf(a.hi.x, b.hi.x), maxf(a.hi.y, b.hi.y), maxf(a.hi.z, b.hi.z)}};
}

// A node's box as stored: grown by kBoxPad of its largest coordinate's magnitude on every side.
// The triangle test's hit point is off the exact triangle by roundings of the coordinates
// (relative to their magnitude), which no relative widening of t covers where t is near 0: a
// ray starting on a face (an origin on the unit cube's face x = 0 hits it at t = 1e-17, just
// outside the flat box [0, 0] in x). A child's pad is at most its parent's, so padded children
// stay inside their padded parent.
constexpr float kBoxPad = 0x1p-20f;

Aabb padded(const Aabb& b) {
    const float m =
        maxf(maxf(maxf(fabsf(b.lo.x), fabsf(b.lo.y)), maxf(fabsf(b.lo.z), fabsf(b.hi.x))),
             maxf(fabsf(b.hi.y), fabsf(b.hi.z)));
    const float pad = m * kBoxPad;
    return {b.lo - makeVec3(pad), b.hi + makeVec3(pad)};
}

// The bin of a centroid along `axis`: the same float operations for the binning and for the
// partition that follows, so a triangle goes to the side its bin was counted on.
struct Binning {
    int axis = 0;
    float origin = 0.0f, scale = 0.0f;  // bin = (c - origin) * scale, clamped

    int binOf(Vec3 centroid) const {
        const int b = int((centroid[axis] - origin) * scale);
        return std::min(std::max(b, 0), kBvhBins - 1);
    }
};

// A split plane found by the binning: triangles of bins below `plane` go left.
struct Split {
    Binning binning;
    int plane = 0;  // 1 .. kBvhBins - 1
    float cost = INFINITY;
};

struct Bin {
    Aabb box = emptyAabb();
    uint32_t count = 0;
};

class BvhBuilder {
public:
    explicit BvhBuilder(const std::vector<Triangle>& tris) : tris_(tris) {
        boxes_.reserve(tris.size());
        centroids_.reserve(tris.size());
        order_.reserve(tris.size());
        for (uint32_t i = 0; i < tris.size(); ++i) {
            boxes_.push_back(boundsOf(tris[i]));
            centroids_.push_back(boxes_.back().center());
            order_.push_back(i);
        }
    }

    // Builds the tree; afterwards order() lists the scene ids in leaf order.
    std::vector<BvhNode> build() {
        nodes_.reserve(2 * tris_.size() + 1);
        nodes_.push_back({emptyAabb(), 0, 0});
        if (!tris_.empty()) buildNode(0, 0, uint32_t(tris_.size()), 0);
        return std::move(nodes_);
    }
    const std::vector<uint32_t>& order() const { return order_; }

private:
    // Fills node `at` for order_[begin, end), then its subtree, depth first: its two children
    // are appended side by side, the first child's subtree before the second's.
    void buildNode(uint32_t at, uint32_t begin, uint32_t end, int depth) {
        Aabb box = emptyAabb(), centroidBox = emptyAabb();
        for (uint32_t k = begin; k < end; ++k) {
            box = merged(box, boxes_[order_[k]]);
            grow(centroidBox, centroids_[order_[k]]);
        }
        nodes_[at].box = padded(box);
        const uint32_t count = end - begin;
        if (count <= kBvhLeafTriangles || depth == kBvhMaxDepth - 1)
            return makeLeaf(at, begin, count);
        const Split split = bestSplit(begin, end, box, centroidBox);
        const float leafCost = kIntersectionCost * float(count);
        const bool sahSaysLeaf = split.cost >= leafCost && count <= kBvhMaxLeafTriangles;
        // No split at all: every centroid in one bin on every axis (coincident centroids).
        if (split.cost == INFINITY || sahSaysLeaf) return makeLeaf(at, begin, count);

        const uint32_t mid =
            uint32_t(std::partition(order_.begin() + begin, order_.begin() + end,
                                    [&](uint32_t i) {
                                        return split.binning.binOf(centroids_[i]) < split.plane;
                                    }) -
                     order_.begin());
        const uint32_t child = uint32_t(nodes_.size());
        nodes_.push_back({emptyAabb(), 0, 0});
        nodes_.push_back({emptyAabb(), 0, 0});
        nodes_[at].index = child;  // nodes_ may have moved: index, never a reference
        nodes_[at].count = 0;
        buildNode(child, begin, mid, depth + 1);
        buildNode(child + 1, mid, end, depth + 1);
    }

    // A leaf lists its triangles by ascending id, as the octree's leaves do: two triangles hit
    // at the same float t (the two sides of an edge) are then met lower id first in a leaf,
    // which intersectTriangle's range test against the closest t so far does not always
    // accept the other way round (leaf order otherwise changes which one is kept).
    void makeLeaf(uint32_t at, uint32_t begin, uint32_t count) {
        std::sort(order_.begin() + begin, order_.begin() + begin + count);
        nodes_[at].index = begin;
        nodes_[at].count = count;
    }

    // The cheapest of the kBvhBins - 1 planes between bins on each axis whose centroids
    // spread, by SAH cost relative to the node's box: kTraversalCost + (A_left N_left +
    // A_right N_right) / A_node x kIntersectionCost. Infinite cost: no plane separates them,
    // or the box's area underflows float (triangles below 1e-19 across), where no ratio is
    // defined.
    Split bestSplit(uint32_t begin, uint32_t end, const Aabb& box, const Aabb& centroidBox) const {
        const float nodeArea = halfArea(box);
        Split best;
        if (!(nodeArea > 0.0f)) return best;
        for (int axis = 0; axis < 3; ++axis) {
            const float lo = centroidBox.lo[axis], extent = centroidBox.hi[axis] - lo;
            if (!(extent > 0.0f)) continue;
            Binning binning;
            binning.axis = axis;
            binning.origin = lo;
            // Wald's k1 = K (1 - epsilon) / extent: the largest centroid lands in the last bin.
            binning.scale = float(kBvhBins) * (1.0f - 1e-6f) / extent;
            const std::array<Bin, kBvhBins> bins = binCentroids(begin, end, binning);
            considerPlanes(bins, binning, nodeArea, best);
        }
        return best;
    }

    std::array<Bin, kBvhBins> binCentroids(uint32_t begin, uint32_t end,
                                           const Binning& binning) const {
        std::array<Bin, kBvhBins> bins;
        for (uint32_t k = begin; k < end; ++k) {
            const uint32_t i = order_[k];
            Bin& b = bins[binning.binOf(centroids_[i])];
            b.box = merged(b.box, boxes_[i]);
            ++b.count;
        }
        return bins;
    }

    // One sweep from the left accumulates each plane's left box and count, one from the right
    // its right ones (Wald 2007, sec. 3.2); a plane with an empty side is no split.
    static void considerPlanes(const std::array<Bin, kBvhBins>& bins, const Binning& binning,
                               float nodeArea, Split& best) {
        std::array<float, kBvhBins> leftCost{};  // A_left N_left for the plane before bin p
        Aabb acc = emptyAabb();
        uint32_t n = 0;
        for (int p = 1; p < kBvhBins; ++p) {
            acc = merged(acc, bins[p - 1].box);
            n += bins[p - 1].count;
            leftCost[p] = n > 0 ? halfArea(acc) * float(n) : -1.0f;
        }
        acc = emptyAabb();
        n = 0;
        for (int p = kBvhBins - 1; p >= 1; --p) {
            acc = merged(acc, bins[p].box);
            n += bins[p].count;
            if (n == 0 || leftCost[p] < 0.0f) continue;
            const float cost = kTraversalCost + kIntersectionCost *
                                                    (leftCost[p] + halfArea(acc) * float(n)) /
                                                    nodeArea;
            if (cost < best.cost) {
                best.cost = cost;
                best.binning = binning;
                best.plane = p;
            }
        }
    }

    const std::vector<Triangle>& tris_;
    std::vector<Aabb> boxes_;
    std::vector<Vec3> centroids_;
    std::vector<uint32_t> order_;
    std::vector<BvhNode> nodes_;
};

}  // namespace

BinaryBvh::BinaryBvh(const Scene& scene) {
    if (scene.kind != PrimKind::Triangles)
        throw BvhError("backend bvh: '" + scene.name + "' is a point cloud (" +
                       std::to_string(scene.primitiveCount()) +
                       " spheres) and the scalar binary BVH holds triangle meshes only; trace it "
                       "with backend cpu (the octree layouts) or embree");
    const auto start = std::chrono::steady_clock::now();
    BvhBuilder builder(scene.triangles);
    nodes_ = builder.build();
    ids_ = builder.order();
    tris_.reserve(ids_.size());
    for (uint32_t id : ids_) tris_.push_back(scene.triangles[id]);
    buildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

BvhStats BinaryBvh::stats() const {
    BvhStats s;
    s.nodes = nodes_.size();
    s.bytes = nodes_.size() * sizeof(BvhNode) + tris_.size() * sizeof(Triangle) +
              ids_.size() * sizeof(uint32_t);
    // Depth first with an explicit stack of (node, depth).
    std::vector<std::pair<uint32_t, int>> todo = {{0u, 0}};
    while (!todo.empty()) {
        const auto [at, depth] = todo.back();
        todo.pop_back();
        const BvhNode& n = nodes_[at];
        if (n.leaf()) {
            ++s.leaves;
            s.depth = std::max(s.depth, depth);
            s.largestLeaf = std::max(s.largestLeaf, n.count);
            continue;
        }
        todo.push_back({n.index, depth + 1});
        todo.push_back({n.index + 1, depth + 1});
    }
    return s;
}

}  // namespace oct
