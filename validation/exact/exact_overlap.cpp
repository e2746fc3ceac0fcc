#include "validation/exact/exact_overlap.h"

#include <algorithm>
#include <cmath>

#include "core/geometry/tri_box.h"
#include "core/octree/octree.h"

namespace oct {
namespace {

struct BoxD {
    DVec3 c, h;
};

// Centre and half size in double: (lo + hi) / 2 and (hi - lo) / 2 of floats are exact.
BoxD boxD(const Aabb& b) {
    DVec3 lo = toDouble(b.lo), hi = toDouble(b.hi);
    return {{(lo.x + hi.x) * 0.5, (lo.y + hi.y) * 0.5, (lo.z + hi.z) * 0.5},
            {(hi.x - lo.x) * 0.5, (hi.y - lo.y) * 0.5, (hi.z - lo.z) * 0.5}};
}

double sphereBoxDistance(const Sphere& s, const Aabb& box) {
    return std::sqrt(sphereCentreBoxDistanceSq(s, box));
}

}  // namespace

bool doubleTriangleBoxOverlap(const Triangle& tri, const Aabb& box) {
    BoxD b = boxD(box);
    return triBoxOverlap(b.c, b.h, toDouble(tri.v0), toDouble(tri.v1), toDouble(tri.v2));
}

bool doubleSphereBoxOverlap(const Sphere& s, const Aabb& box) {
    double d2 = sphereCentreBoxDistanceSq(s, box);
    double r = double(s.radius);
    return d2 <= r * r;
}

double triangleBoxGap(const Triangle& tri, const Aabb& box) {
    using namespace tribox_detail;
    BoxD b = boxD(box);
    DVec3 v0 = toDouble(tri.v0) - b.c, v1 = toDouble(tri.v1) - b.c, v2 = toDouble(tri.v2) - b.c;
    double gap = 0.0;
    // Gap on axis a, in units of box growth: a separates the box grown by delta exactly when
    // (min p - rad) > delta * |a|_1 (or the mirrored condition).
    auto axis = [&](DVec3 a) {
        double l1 = ab(a.x) + ab(a.y) + ab(a.z);
        if (l1 == 0.0) return;  // degenerate axis: never separates
        double p0 = dot(a, v0), p1 = dot(a, v1), p2 = dot(a, v2);
        double rad = ab(a.x) * b.h.x + ab(a.y) * b.h.y + ab(a.z) * b.h.z;
        double g = std::max(mn3(p0, p1, p2) - rad, -rad - mx3(p0, p1, p2));
        gap = std::max(gap, g / l1);
    };
    const DVec3 units[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    DVec3 e[3] = {v1 - v0, v2 - v1, v0 - v2};
    for (const auto& u : units) axis(u);
    for (const auto& u : units)
        for (const auto& ej : e) axis(cross(u, ej));
    axis(cross(e[0], e[1]));
    return gap;
}

double sphereBoxGap(const Sphere& s, const Aabb& box) {
    return std::max(0.0, sphereBoxDistance(s, box) - double(s.radius));
}

}  // namespace oct
