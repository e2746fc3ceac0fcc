// The independent references of the replication check: does a primitive overlap a box?
//  - exact: CGAL's do_intersect under the exact-predicates kernel (Epick). Our inputs are
//    floats, so every point and box coordinate is exact in double and the answer is the exact
//    answer for the closed triangle (segment, point) or sphere against the closed box. Only
//    exact_overlap_cgal.cpp includes CGAL (it is the slow translation unit to compile).
//  - double: the Akenine-Möller test of core/geometry/tri_box.h in double precision, without
//    the builder's padding, and Arvo's sphere test in double.
// Boxes are the canonical octree's float node boxes, taken as they are.
#pragma once

#include "core/geometry/aabb.h"
#include "core/geometry/primitives.h"

namespace oct {

// Exact: true when the closed triangle and the closed box share a point. A triangle whose
// vertices are collinear is tested as the segment between its two farthest vertices (or as
// a point when all three coincide), since CGAL's Triangle_3 test needs a proper plane.
bool exactTriangleBoxOverlap(const Triangle& tri, const Aabb& box);
// Exact: true when the closed ball (centre, radius) and the closed box share a point. The
// squared float radius is exact in double.
bool exactSphereBoxOverlap(const Sphere& s, const Aabb& box);

// Double precision, unpadded (the builder adds a relative 1e-9 pad; see builder.cpp).
bool doubleTriangleBoxOverlap(const Triangle& tri, const Aabb& box);
bool doubleSphereBoxOverlap(const Sphere& s, const Aabb& box);

// How far apart a primitive and a box are: the smallest delta >= 0 such that the box grown by
// delta on every side overlaps the primitive, computed in double. For a triangle this is the
// largest, over the 13 separating axes a of Akenine-Möller's test, of gap(a) / |a|_1 (growing
// the half sizes by delta widens the box's projection on a by delta * |a|_1); for a sphere,
// the distance from its centre to the box minus its radius. 0 when they overlap.
double triangleBoxGap(const Triangle& tri, const Aabb& box);
double sphereBoxGap(const Sphere& s, const Aabb& box);

}  // namespace oct
