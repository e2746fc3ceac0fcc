// A bounding volume hierarchy over boxes, in double precision, for the double truth's queries
// (double_tracer.h): which primitives a segment may meet, which lie nearest a point. It only
// filters: the caller tests every primitive it is handed exactly as the brute force would, so
// answers are the brute force's as long as the filter is conservative. It is: boxes are grown
// outwards on construction, and the slab test widens its interval by 2 gamma_4 |t| (Ize 2013;
// Pharr, Jakob & Humphreys, PBRT 3rd ed., sec. 3.9.2), so a segment that meets a box in exact
// arithmetic is never culled.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace oct {

struct DBox {
    double lo[3], hi[3];
};

class BoxBvh {
public:
    // Builds over `boxes` (primitive i's box at index i), each grown by `pad` on every side.
    BoxBvh(const std::vector<DBox>& boxes, double pad);

    // Calls f(prim) for every primitive whose grown box, grown by `more` again, the segment
    // org + t dir, t in [t0, t1], meets (t1 may be +inf), nearest box first; f returns the t
    // beyond which nothing more is wanted (return t1 to see every box on the segment).
    template <class F>
    void segment(const double org[3], const double dir[3], double t0, double t1, F&& f,
                 double more = 0.0) const;

    // Every hit on the segment in ascending t (equal t: ascending id), in one best-first
    // traversal: hitAt(prim, t) says whether the primitive is hit and where; emit(t, prim) gets
    // each hit once no box left unopened can hold an earlier one, and returns false to stop.
    template <class H, class E>
    void ordered(const double org[3], const double dir[3], double t0, double t1, H&& hitAt,
                 E&& emit) const;

    // Calls dist(prim) for the primitives whose grown box lies within `best` of p, nearest box
    // first, where dist returns the primitive's exact distance (and the caller keeps the best
    // one); boxes farther than the best distance so far are skipped.
    template <class F>
    void nearest(const double p[3], double& best, F&& dist) const;

    uint32_t nodeCount() const { return uint32_t(nodes_.size()); }

private:
    // 32 bytes: the box in float, rounded outwards from the double one (24: half the bytes a
    // traversal reads, and still conservative), then for an internal node the index of its
    // first child (the second follows it) with count 0, for a leaf its first entry in prims_
    // and the count.
    struct FBox {
        float lo[3], hi[3];
    };
    struct Node {
        FBox box;
        uint32_t first;
        uint32_t count;
    };
    static constexpr int kStack = 64;  // depth bound: the build splits at the median at worst

    // A segment query's per-ray constants: the slab test reads the near and far plane of each
    // axis without a swap, and an axis the ray runs parallel to by containment.
    struct Query {
        double org[3], inv[3];
        int nearHi[3];     // 1: the near plane is the box's hi (the ray runs towards -axis)
        bool parallel[3];  // a zero direction component
        double more;
    };
    static Query query(const double org[3], const double dir[3], double more);
    bool slabs(const Node& n, const Query& q, double t0, double t1, double& tEnter) const;
    double boxDistance2(const Node& n, const double p[3]) const;
    struct Inputs {
        std::vector<uint32_t>& ids;
        const std::vector<DBox>& boxes;
        const std::vector<double>& centres;
    };
    struct Bounds {
        DBox box, centres;
    };
    static Bounds boundsOf(const Inputs& in, uint32_t begin, uint32_t end);
    static bool split(Node& node, const Inputs& in, uint32_t begin, uint32_t end, int depth,
                      const Bounds& mine, uint32_t& mid, Bounds& left, Bounds& right);
    static std::vector<Node> subtree(const Inputs& in, uint32_t begin, uint32_t end, int depth,
                                     const Bounds& mine);
    static void build(std::vector<Node>& nodes, uint32_t self, const Inputs& in, uint32_t begin,
                      uint32_t end, int depth, const Bounds& mine);

    std::vector<Node> nodes_;
    std::vector<uint32_t> prims_;
};

// --- implementation --------------------------------------------------------------------------

template <class F>
void BoxBvh::segment(const double org[3], const double dir[3], double t0, double t1, F&& f,
                     double more) const {
    if (nodes_.empty()) return;
    const Query q = query(org, dir, more);
    struct Entry {
        uint32_t node;
        double tEnter;
    };
    Entry stack[kStack];
    int top = 0;
    double tEnter;
    if (!slabs(nodes_[0], q, t0, t1, tEnter)) return;
    stack[top++] = {0, tEnter};
    while (top > 0) {
        const Entry e = stack[--top];
        if (e.tEnter > t1) continue;
        const Node& n = nodes_[e.node];
        if (n.count > 0) {
            for (uint32_t k = 0; k < n.count; ++k) {
                const double limit = f(prims_[n.first + k]);
                if (limit < t1) t1 = limit;
            }
            continue;
        }
        double ta = 0.0, tb = 0.0;  // set by slabs() when it returns true
        const bool ha = slabs(nodes_[n.first], q, t0, t1, ta);
        const bool hb = slabs(nodes_[n.first + 1], q, t0, t1, tb);
        // Nearest popped first: push the farther one first.
        if (ha && hb) {
            const bool aFirst = ta <= tb;
            stack[top++] = {aFirst ? n.first + 1 : n.first, aFirst ? tb : ta};
            stack[top++] = {aFirst ? n.first : n.first + 1, aFirst ? ta : tb};
        } else if (ha) {
            stack[top++] = {n.first, ta};
        } else if (hb) {
            stack[top++] = {n.first + 1, tb};
        }
    }
}

inline BoxBvh::Query BoxBvh::query(const double org[3], const double dir[3], double more) {
    Query q;
    for (int a = 0; a < 3; ++a) {
        q.org[a] = org[a];
        q.parallel[a] = dir[a] == 0.0 || std::isinf(1.0 / dir[a]);
        q.inv[a] = q.parallel[a] ? 0.0 : 1.0 / dir[a];
        q.nearHi[a] = dir[a] < 0.0;
    }
    q.more = more;
    return q;
}

// Conservative for the exact box: each plane distance is within gamma_4 |t| of the exact one
// (two differences, a reciprocal, a product), and widening is monotone, so the interval of the
// planes' distances is widened once, after the per-axis minimum and maximum.
inline bool BoxBvh::slabs(const Node& n, const Query& q, double t0, double t1,
                          double& tEnter) const {
    constexpr double kWiden = 2.0 * 4.0 * 0x1p-53 / (1.0 - 4.0 * 0x1p-53);  // 2 gamma_4
    double lo = -INFINITY, hi = INFINITY;
    for (int a = 0; a < 3; ++a) {
        const double boxLo = n.box.lo[a] - q.more, boxHi = n.box.hi[a] + q.more;
        if (q.parallel[a]) {  // inside the slab for all t, or never
            if (q.org[a] < boxLo || q.org[a] > boxHi) return false;
            continue;
        }
        const double tn = ((q.nearHi[a] ? boxHi : boxLo) - q.org[a]) * q.inv[a];
        const double tf = ((q.nearHi[a] ? boxLo : boxHi) - q.org[a]) * q.inv[a];
        lo = tn > lo ? tn : lo;
        hi = tf < hi ? tf : hi;
    }
    lo -= kWiden * std::fabs(lo);
    hi += kWiden * std::fabs(hi);
    tEnter = lo > t0 ? lo : t0;
    return tEnter <= (hi < t1 ? hi : t1);
}

template <class H, class E>
void BoxBvh::ordered(const double org[3], const double dir[3], double t0, double t1, H&& hitAt,
                     E&& emit) const {
    if (nodes_.empty()) return;
    const Query q = query(org, dir, 0.0);
    struct Box {
        double tEnter;
        uint32_t node;
        bool operator<(const Box& o) const { return tEnter > o.tEnter; }  // min-heap
    };
    struct Found {
        double t;
        uint32_t prim;
        bool operator<(const Found& o) const {  // min-heap by (t, id)
            return t > o.t || (t == o.t && prim > o.prim);
        }
    };
    std::vector<Box> boxes;
    std::vector<Found> found;
    double tEnter;
    if (!slabs(nodes_[0], q, t0, t1, tEnter)) return;
    boxes.push_back({tEnter, 0});
    while (!boxes.empty() || !found.empty()) {
        // Emit what no unopened box can precede (a box entered at the same t may hold the same
        // t with a lower id: it is opened first).
        while (!found.empty() && (boxes.empty() || found.front().t < boxes.front().tEnter)) {
            std::pop_heap(found.begin(), found.end());
            const Found f = found.back();
            found.pop_back();
            if (!emit(f.t, f.prim)) return;
        }
        if (boxes.empty()) break;
        std::pop_heap(boxes.begin(), boxes.end());
        const Box b = boxes.back();
        boxes.pop_back();
        const Node& n = nodes_[b.node];
        if (n.count > 0) {
            for (uint32_t k = 0; k < n.count; ++k) {
                double t;
                if (hitAt(prims_[n.first + k], t)) {
                    found.push_back({t, prims_[n.first + k]});
                    std::push_heap(found.begin(), found.end());
                }
            }
            continue;
        }
        for (uint32_t c = n.first; c < n.first + 2; ++c)
            if (slabs(nodes_[c], q, t0, t1, tEnter)) {
                boxes.push_back({tEnter, c});
                std::push_heap(boxes.begin(), boxes.end());
            }
    }
}

template <class F>
void BoxBvh::nearest(const double p[3], double& best, F&& dist) const {
    if (nodes_.empty()) return;
    struct Entry {
        uint32_t node;
        double d2;
    };
    Entry stack[kStack];
    int top = 0;
    stack[top++] = {0, boxDistance2(nodes_[0], p)};
    while (top > 0) {
        const Entry e = stack[--top];
        // A box at the best distance is still visited (ties are the caller's to break), and a
        // relative margin keeps the rounding of d2 and best^2 from culling one.
        if (!(e.d2 <= best * best * (1.0 + 1e-9))) continue;
        const Node& n = nodes_[e.node];
        if (n.count > 0) {
            for (uint32_t k = 0; k < n.count; ++k) {
                const double d = dist(prims_[n.first + k]);
                if (d < best) best = d;
            }
            continue;
        }
        const double da = boxDistance2(nodes_[n.first], p);
        const double db = boxDistance2(nodes_[n.first + 1], p);
        const bool aFirst = da <= db;
        stack[top++] = {aFirst ? n.first + 1 : n.first, aFirst ? db : da};
        stack[top++] = {aFirst ? n.first : n.first + 1, aFirst ? da : db};
    }
}

}  // namespace oct
