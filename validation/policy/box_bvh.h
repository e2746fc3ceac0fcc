// A bounding volume hierarchy over boxes, in double precision, for the double truth's queries
// (double_tracer.h): which primitives a segment may meet, which lie nearest a point. It only
// filters: the caller tests every primitive it is handed exactly as the brute force would, so
// answers are the brute force's as long as the filter is conservative. It is: boxes are grown
// outwards on construction, and the slab test widens its interval by 2 gamma_4 |t| (Ize 2013;
// Pharr, Jakob & Humphreys, PBRT 3rd ed., sec. 3.9.2), so a segment that meets a box in exact
// arithmetic is never culled.
#pragma once

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

    // Calls dist(prim) for the primitives whose grown box lies within `best` of p, nearest box
    // first, where dist returns the primitive's exact distance (and the caller keeps the best
    // one); boxes farther than the best distance so far are skipped.
    template <class F>
    void nearest(const double p[3], double& best, F&& dist) const;

    uint32_t nodeCount() const { return uint32_t(nodes_.size()); }

private:
    // 56 bytes: the box (48), then for an internal node the index of its first child (the
    // second follows it) with count 0, for a leaf its first entry in prims_ and the count.
    struct Node {
        DBox box;
        uint32_t first;
        uint32_t count;
    };
    static constexpr int kStack = 64;  // depth bound: the build splits at the median at worst

    bool slabs(const Node& n, const double org[3], const double inv[3], double t0, double t1,
               double more, double& tEnter) const;
    double boxDistance2(const Node& n, const double p[3]) const;
    void build(uint32_t self, std::vector<uint32_t>& ids, uint32_t begin, uint32_t end,
               const std::vector<DBox>& boxes, const std::vector<double>& centres, int depth);

    std::vector<Node> nodes_;
    std::vector<uint32_t> prims_;
};

// --- implementation --------------------------------------------------------------------------

template <class F>
void BoxBvh::segment(const double org[3], const double dir[3], double t0, double t1, F&& f,
                     double more) const {
    if (nodes_.empty()) return;
    double inv[3];
    for (int a = 0; a < 3; ++a) inv[a] = 1.0 / dir[a];  // +-inf for a zero component
    struct Entry {
        uint32_t node;
        double tEnter;
    };
    Entry stack[kStack];
    int top = 0;
    double tEnter;
    if (!slabs(nodes_[0], org, inv, t0, t1, more, tEnter)) return;
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
        double ta, tb;
        const bool ha = slabs(nodes_[n.first], org, inv, t0, t1, more, ta);
        const bool hb = slabs(nodes_[n.first + 1], org, inv, t0, t1, more, tb);
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
