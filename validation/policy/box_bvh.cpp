#include "validation/policy/box_bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace oct {
namespace {

constexpr uint32_t kLeafSize = 4;
// gamma_4 of double arithmetic (PBRT: n eps / (1 - n eps), eps = 2^-53).
constexpr double kGamma4 = 4.0 * 0x1p-53 / (1.0 - 4.0 * 0x1p-53);

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
    std::vector<DBox> grown(boxes.size());
    std::vector<double> centres(3 * boxes.size());
    for (size_t i = 0; i < boxes.size(); ++i) {
        grown[i] = padded(boxes[i], pad);
        for (int a = 0; a < 3; ++a) centres[3 * i + a] = 0.5 * (boxes[i].lo[a] + boxes[i].hi[a]);
    }
    if (boxes.empty()) return;
    std::vector<uint32_t> ids(boxes.size());
    std::iota(ids.begin(), ids.end(), 0u);
    nodes_.reserve(2 * boxes.size() / kLeafSize + 1);
    nodes_.push_back({});
    build(0, ids, 0, uint32_t(ids.size()), grown, centres, 0);
    prims_ = std::move(ids);
}

// Builds node `self` over ids[begin, end): a leaf of at most kLeafSize, or a split at the median
// of the centres along the axis of their largest spread, into two adjacent children (depth at
// most log2(n) + 1, so the traversal stacks of kStack entries never overflow).
void BoxBvh::build(uint32_t self, std::vector<uint32_t>& ids, uint32_t begin, uint32_t end,
                   const std::vector<DBox>& boxes, const std::vector<double>& centres, int depth) {
    DBox box = emptyBox(), spread = emptyBox();
    for (uint32_t k = begin; k < end; ++k) {
        grow(box, boxes[ids[k]]);
        const double* c = &centres[3 * ids[k]];
        grow(spread, {{c[0], c[1], c[2]}, {c[0], c[1], c[2]}});
    }
    nodes_[self].box = box;
    int axis = 0;
    double widest = -1.0;
    for (int a = 0; a < 3; ++a)
        if (spread.hi[a] - spread.lo[a] > widest) {
            widest = spread.hi[a] - spread.lo[a];
            axis = a;
        }
    if (end - begin <= kLeafSize || !(widest > 0.0) || depth + 2 >= kStack) {
        nodes_[self].first = begin;
        nodes_[self].count = end - begin;
        return;
    }
    const uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(ids.begin() + begin, ids.begin() + mid, ids.begin() + end,
                     [&](uint32_t x, uint32_t y) {
                         const double cx = centres[3 * x + axis], cy = centres[3 * y + axis];
                         return cx < cy || (cx == cy && x < y);
                     });
    const uint32_t left = uint32_t(nodes_.size());
    nodes_.push_back({});
    nodes_.push_back({});
    nodes_[self].first = left;
    nodes_[self].count = 0;
    build(left, ids, begin, mid, boxes, centres, depth + 1);
    build(left + 1, ids, mid, end, boxes, centres, depth + 1);
}

bool BoxBvh::slabs(const Node& n, const double org[3], const double inv[3], double t0, double t1,
                   double more, double& tEnter) const {
    for (int a = 0; a < 3; ++a) {
        const double lo = n.box.lo[a] - more, hi = n.box.hi[a] + more;
        if (std::isinf(inv[a])) {  // parallel to the slab: inside it for all t, or never
            if (org[a] < lo || org[a] > hi) return false;
            continue;
        }
        double tn = (lo - org[a]) * inv[a];
        double tf = (hi - org[a]) * inv[a];
        if (tn > tf) std::swap(tn, tf);
        // Conservative for the exact box: each distance is within gamma_4 |t| of the exact one
        // (two differences, a reciprocal, a product), so the interval grows by that much.
        tf += 2.0 * kGamma4 * std::fabs(tf);
        tn -= 2.0 * kGamma4 * std::fabs(tn);
        if (tn > t0) t0 = tn;
        if (tf < t1) t1 = tf;
        if (t0 > t1) return false;
    }
    tEnter = t0;
    return true;
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
