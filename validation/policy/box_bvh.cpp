#include "validation/policy/box_bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace oct {
namespace {

constexpr uint32_t kLeafSize = 4;
constexpr int kBins = 16;  // SAH bins per split
// The parallel build: subtrees of at least this many boxes, in the top levels, are tasks.
constexpr uint32_t kParallelGrain = 50000;
constexpr int kParallelDepth = 4;

DBox emptyBox() {
    const double inf = std::numeric_limits<double>::infinity();
    return {{inf, inf, inf}, {-inf, -inf, -inf}};
}

void grow(DBox& b, const DBox& o) {
    for (int a = 0; a < 3; ++a) {
        b.lo[a] = std::min(b.lo[a], o.lo[a]);
        b.hi[a] = std::max(b.hi[a], o.hi[a]);
    }
}

// The nearest float at or below x, at or above x (infinities stay: an empty box stays empty).
float floatBelow(double x) {
    const float f = float(x);
    return double(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
float floatAbove(double x) {
    const float f = float(x);
    return double(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

// The box grown by pad, rounded outwards (the sum rounds to nearest; one step further out
// makes the grown box contain the exact one).
DBox padded(const DBox& b, double pad) {
    DBox out;
    for (int a = 0; a < 3; ++a) {
        out.lo[a] = std::nextafter(b.lo[a] - pad, -std::numeric_limits<double>::infinity());
        out.hi[a] = std::nextafter(b.hi[a] + pad, std::numeric_limits<double>::infinity());
    }
    return out;
}

}  // namespace

BoxBvh::BoxBvh(const std::vector<DBox>& boxes, double pad) {
    if (boxes.size() >= std::numeric_limits<uint32_t>::max())
        throw std::length_error("BoxBvh: more than 2^32 - 1 boxes");
    const int64_t n = int64_t(boxes.size());
    std::vector<DBox> grown(boxes.size());
    std::vector<double> centres(3 * boxes.size());
#pragma omp parallel for schedule(static)
    for (int64_t i = 0; i < n; ++i) {
        grown[size_t(i)] = padded(boxes[size_t(i)], pad);
        for (int a = 0; a < 3; ++a)
            centres[3 * size_t(i) + a] = 0.5 * (boxes[size_t(i)].lo[a] + boxes[size_t(i)].hi[a]);
    }
    if (boxes.empty()) return;
    std::vector<uint32_t> ids(boxes.size());
    std::iota(ids.begin(), ids.end(), 0u);
    const Inputs in{ids, grown, centres};
    const Bounds all = boundsOf(in, 0, uint32_t(ids.size()));
#pragma omp parallel
#pragma omp single
    nodes_ = subtree(in, 0, uint32_t(ids.size()), 0, all);
    prims_ = std::move(ids);
}

double halfArea(const DBox& b) {
    const double x = b.hi[0] - b.lo[0], y = b.hi[1] - b.lo[1], z = b.hi[2] - b.lo[2];
    return x * y + y * z + z * x;
}

// The boxes and the centres' bounds of ids[begin, end).
BoxBvh::Bounds BoxBvh::boundsOf(const Inputs& in, uint32_t begin, uint32_t end) {
    Bounds b{emptyBox(), emptyBox()};
    for (uint32_t k = begin; k < end; ++k) {
        grow(b.box, in.boxes[in.ids[k]]);
        const double* c = &in.centres[3 * in.ids[k]];
        grow(b.centres, {{c[0], c[1], c[2]}, {c[0], c[1], c[2]}});
    }
    return b;
}

// Gives `node` the box of ids[begin, end) (`mine`, made by the parent) and decides: a leaf of at
// most kLeafSize, or a split (returned in `mid`, with each side's bounds; ids reordered around
// it) by the surface area heuristic over kBins bins of the centres along the axis of their
// largest spread (MacDonald & Booth 1990; binned after Wald, "On fast construction of SAH-based
// bounding volume hierarchies", 2007), or at the median when the bins cannot split. One pass
// bins the boxes and centres, a second partitions. A forced leaf past kStack - 2 levels keeps
// the traversal stacks from overflowing (it only costs time).
bool BoxBvh::split(Node& node, const Inputs& in, uint32_t begin, uint32_t end, int depth,
                   const Bounds& mine, uint32_t& mid, Bounds& left, Bounds& right) {
    for (int a = 0; a < 3; ++a) {
        node.box.lo[a] = floatBelow(mine.box.lo[a]);
        node.box.hi[a] = floatAbove(mine.box.hi[a]);
    }
    int axis = 0;
    double widest = -1.0;
    for (int a = 0; a < 3; ++a)
        if (mine.centres.hi[a] - mine.centres.lo[a] > widest) {
            widest = mine.centres.hi[a] - mine.centres.lo[a];
            axis = a;
        }
    if (end - begin <= kLeafSize || !(widest > 0.0) || depth + 2 >= kStack) {
        node.first = begin;
        node.count = end - begin;
        return false;
    }
    node.count = 0;
    const std::vector<double>& centres = in.centres;
    const double lo = mine.centres.lo[axis], scale = kBins / widest;
    auto binOf = [&](uint32_t id) {
        const int b = int((centres[3 * id + axis] - lo) * scale);
        return b < 0 ? 0 : (b >= kBins ? kBins - 1 : b);
    };
    Bounds bins[kBins];
    uint32_t counts[kBins] = {};
    for (Bounds& b : bins) b = {emptyBox(), emptyBox()};
    for (uint32_t k = begin; k < end; ++k) {
        const uint32_t id = in.ids[k];
        const int b = binOf(id);
        ++counts[b];
        grow(bins[b].box, in.boxes[id]);
        const double* c = &centres[3 * id];
        grow(bins[b].centres, {{c[0], c[1], c[2]}, {c[0], c[1], c[2]}});
    }
    // Cost of splitting after bin i: area x count of each side (the sweep from the right first).
    double rightCost[kBins];
    Bounds acc{emptyBox(), emptyBox()};
    uint32_t n = 0;
    for (int i = kBins - 1; i > 0; --i) {
        grow(acc.box, bins[i].box);
        n += counts[i];
        rightCost[i] = n ? halfArea(acc.box) * n : 0.0;
    }
    int best = -1;
    double bestCost = INFINITY;
    acc = {emptyBox(), emptyBox()};
    n = 0;
    for (int i = 0; i < kBins - 1; ++i) {
        grow(acc.box, bins[i].box);
        n += counts[i];
        if (n == 0 || n == end - begin) continue;
        const double cost = halfArea(acc.box) * n + rightCost[i + 1];
        if (cost < bestCost) {
            bestCost = cost;
            best = i;
        }
    }
    if (best >= 0) {
        auto it = std::partition(in.ids.begin() + begin, in.ids.begin() + end,
                                 [&](uint32_t id) { return binOf(id) <= best; });
        mid = uint32_t(it - in.ids.begin());
        if (mid > begin && mid < end) {
            left = right = {emptyBox(), emptyBox()};
            for (int i = 0; i < kBins; ++i) {
                Bounds& side = i <= best ? left : right;
                grow(side.box, bins[i].box);
                grow(side.centres, bins[i].centres);
            }
            return true;
        }
    }
    mid = begin + (end - begin) / 2;
    std::nth_element(in.ids.begin() + begin, in.ids.begin() + mid, in.ids.begin() + end,
                     [&](uint32_t x, uint32_t y) {
                         const double cx = centres[3 * x + axis], cy = centres[3 * y + axis];
                         return cx < cy || (cx == cy && x < y);
                     });
    left = boundsOf(in, begin, mid);
    right = boundsOf(in, mid, end);
    return true;
}

// The subtree over ids[begin, end) as its own node array, root at 0, children adjacent. The top
// levels of a large tree build their two halves as parallel tasks and splice them: the root, the
// two roots, then each half's other nodes; a half's indices move by where it landed. The tree is
// the one a serial build makes.
std::vector<BoxBvh::Node> BoxBvh::subtree(const Inputs& in, uint32_t begin, uint32_t end, int depth,
                                          const Bounds& mine) {
    std::vector<Node> nodes(1);
    if (end - begin < kParallelGrain || depth >= kParallelDepth) {
        nodes.reserve(2 * (end - begin) / kLeafSize + 1);
        build(nodes, 0, in, begin, end, depth, mine);
        return nodes;
    }
    uint32_t mid = 0;
    Bounds sides[2];
    if (!split(nodes[0], in, begin, end, depth, mine, mid, sides[0], sides[1])) return nodes;
    std::vector<Node> halves[2];
#pragma omp task shared(halves, in, sides)
    halves[0] = subtree(in, begin, mid, depth + 1, sides[0]);
#pragma omp task shared(halves, in, sides)
    halves[1] = subtree(in, mid, end, depth + 1, sides[1]);
#pragma omp taskwait
    nodes.resize(3);
    nodes[0].first = 1;
    // Index i > 0 of half h lands at rest[h] + i - 1; its root at 1 + h.
    const uint32_t rest[2] = {3u, 3u + uint32_t(halves[0].size()) - 1u};
    for (int h = 0; h < 2; ++h) {
        auto place = [&](uint32_t i) { return i == 0 ? uint32_t(1 + h) : rest[h] + i - 1; };
        for (uint32_t i = 0; i < halves[h].size(); ++i) {
            Node n = halves[h][i];
            if (n.count == 0) n.first = place(n.first);
            if (i == 0)
                nodes[1 + h] = n;
            else
                nodes.push_back(n);
        }
    }
    return nodes;
}

// Builds node `self` of `nodes` (and its subtree, appended) over ids[begin, end).
void BoxBvh::build(std::vector<Node>& nodes, uint32_t self, const Inputs& in, uint32_t begin,
                   uint32_t end, int depth, const Bounds& mine) {
    uint32_t mid = 0;
    Node node;
    Bounds left, right;
    const bool inner = split(node, in, begin, end, depth, mine, mid, left, right);
    nodes[self] = node;
    if (!inner) return;
    const uint32_t first = uint32_t(nodes.size());
    nodes.push_back({});
    nodes.push_back({});
    nodes[self].first = first;
    build(nodes, first, in, begin, mid, depth + 1, left);
    build(nodes, first + 1, in, mid, end, depth + 1, right);
}

double BoxBvh::boxDistance2(const Node& n, const double p[3]) const {
    double d2 = 0.0;
    for (int a = 0; a < 3; ++a) {
        const double d = p[a] < n.box.lo[a]   ? n.box.lo[a] - p[a]
                         : p[a] > n.box.hi[a] ? p[a] - n.box.hi[a]
                                              : 0.0;
        d2 += d * d;
    }
    return d2;
}

}  // namespace oct
