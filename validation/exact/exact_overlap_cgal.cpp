// The one translation unit that includes CGAL (slow to compile; keep it small).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>

#include <algorithm>

#include "validation/exact/exact_overlap.h"

namespace oct {
namespace {

// Exact predicates, inexact constructions: do_intersect is a predicate, evaluated with static
// and interval filters and an exact fallback, so its answer is exact for our double inputs.
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;

Point point(Vec3 v) { return Point(double(v.x), double(v.y), double(v.z)); }

CGAL::Bbox_3 bbox(const Aabb& b) {
    return CGAL::Bbox_3(double(b.lo.x), double(b.lo.y), double(b.lo.z), double(b.hi.x),
                        double(b.hi.y), double(b.hi.z));
}

}  // namespace

bool exactTriangleBoxOverlap(const Triangle& tri, const Aabb& box) {
    const Point p[3] = {point(tri.v0), point(tri.v1), point(tri.v2)};
    const CGAL::Bbox_3 b = bbox(box);
    if (!CGAL::collinear(p[0], p[1], p[2]))
        return CGAL::do_intersect(Kernel::Triangle_3(p[0], p[1], p[2]), b);
    // Collinear: the triangle is the segment between its extreme vertices, which are the
    // lexicographically smallest and largest (the order along a line is the xyz order).
    auto less = [](const Point& a, const Point& b) {
        return CGAL::compare_xyz(a, b) == CGAL::SMALLER;
    };
    const Point lo = std::min({p[0], p[1], p[2]}, less);
    const Point hi = std::max({p[0], p[1], p[2]}, less);
    if (lo == hi)
        return lo.x() >= b.xmin() && lo.x() <= b.xmax() && lo.y() >= b.ymin() &&
               lo.y() <= b.ymax() && lo.z() >= b.zmin() && lo.z() <= b.zmax();
    return CGAL::do_intersect(Kernel::Segment_3(lo, hi), b);
}

bool exactSphereBoxOverlap(const Sphere& s, const Aabb& box) {
    double r = double(s.radius);
    return CGAL::do_intersect(Kernel::Sphere_3(point(s.center), r * r), bbox(box));
}

}  // namespace oct
