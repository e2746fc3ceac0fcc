#include "validation/exact/exact_overlap.h"

#include <algorithm>
#include <cmath>

#include "core/geometry/tri_box.h"
#include "core/octree/octree.h"

namespace oct {
namespace {

V3<double> d3(Vec3 v) { return {double(v.x), double(v.y), double(v.z)}; }

struct BoxD {
    V3<double> c, h;
};

// Centre and half size in double: (lo + hi) / 2 and (hi - lo) / 2 of floats are exact.
BoxD boxD(const Aabb& b) {
    V3<double> lo = d3(b.lo), hi = d3(b.hi);
    return {{(lo.x + hi.x) * 0.5, (lo.y + hi.y) * 0.5, (lo.z + hi.z) * 0.5},
            {(hi.x - lo.x) * 0.5, (hi.y - lo.y) * 0.5, (hi.z - lo.z) * 0.5}};
}

double sphereBoxDistance(const Sphere& s, const Aabb& box) {
    return std::sqrt(sphereCentreBoxDistanceSq(s, box));
}

}  // namespace

bool doubleTriangleBoxOverlap(const Triangle& tri, const Aabb& box) {
    BoxD b = boxD(box);
    return triBoxOverlap(b.c, b.h, d3(tri.v0), d3(tri.v1), d3(tri.v2));
}

bool doubleSphereBoxOverlap(const Sphere& s, const Aabb& box) {
    double d2 = sphereCentreBoxDistanceSq(s, box);
    double r = double(s.radius);
    return d2 <= r * r;
}

double triangleBoxGap(const Triangle& tri, const Aabb& box) {
    using namespace tribox_detail;
    BoxD b = boxD(box);
    V3<double> v0 = sub(d3(tri.v0), b.c), v1 = sub(d3(tri.v1), b.c), v2 = sub(d3(tri.v2), b.c);
    double gap = 0.0;
    // Gap on axis a, in units of box growth: a separates the box grown by delta exactly when
    // (min p - rad) > delta * |a|_1 (or the mirrored condition).
    auto axis = [&](V3<double> a) {
        double l1 = ab(a.x) + ab(a.y) + ab(a.z);
        if (l1 == 0.0) return;  // degenerate axis: never separates
        double p0 = dt(a, v0), p1 = dt(a, v1), p2 = dt(a, v2);
        double rad = ab(a.x) * b.h.x + ab(a.y) * b.h.y + ab(a.z) * b.h.z;
        double g = std::max(mn3(p0, p1, p2) - rad, -rad - mx3(p0, p1, p2));
        gap = std::max(gap, g / l1);
    };
    const V3<double> units[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    V3<double> e[3] = {sub(v1, v0), sub(v2, v1), sub(v0, v2)};
    for (const auto& u : units) axis(u);
    for (const auto& u : units)
        for (const auto& ej : e) axis(crs(u, ej));
    axis(crs(e[0], e[1]));
    return gap;
}

double sphereBoxGap(const Sphere& s, const Aabb& box) {
    return std::max(0.0, sphereBoxDistance(s, box) - double(s.radius));
}

}  // namespace oct
