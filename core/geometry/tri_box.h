// Triangle/box overlap by the separating axis theorem, after Tomas Akenine-Möller, "Fast 3D
// Triangle-Box Overlap Testing", journal of graphics tools 6(1), 2001. Our own implementation:
// the 13 candidate axes are the 3 box normals, the triangle normal and the 9 cross products of
// box edges and triangle edges. Templated on the scalar so the validation module can run the
// same algorithm in double precision next to the float one the builder uses.
//
// Boundary convention: touching counts as overlap (every comparison is strict "> rad" for a
// separation), so a triangle lying in a face shared by two boxes belongs to both.
#pragma once

#include "core/geometry/vec3t.h"
#include "core/platform.h"

namespace oct {

namespace tribox_detail {

template <class T>
OCT_HD inline T mn3(T a, T b, T c) {
    T m = a < b ? a : b;
    return m < c ? m : c;
}
template <class T>
OCT_HD inline T mx3(T a, T b, T c) {
    T m = a > b ? a : b;
    return m > c ? m : c;
}
template <class T>
OCT_HD inline T ab(T a) {
    return a < T(0) ? -a : a;
}

// Does axis a separate the triangle (vertices relative to the box centre) from the box with
// half-size h? The box's projection radius on a is sum |a_i| h_i.
template <class T>
OCT_HD inline bool separates(Vec3T<T> a, Vec3T<T> v0, Vec3T<T> v1, Vec3T<T> v2, Vec3T<T> h) {
    T p0 = dot(a, v0), p1 = dot(a, v1), p2 = dot(a, v2);
    T rad = ab(a.x) * h.x + ab(a.y) * h.y + ab(a.z) * h.z;
    return mn3(p0, p1, p2) > rad || mx3(p0, p1, p2) < -rad;
}

}  // namespace tribox_detail

// Returns true when the closed triangle (a, b, c) and the closed box centre +- halfSize share a
// point. Works for degenerate triangles (a segment or a point): their zero normal and zero
// edge crosses give axes that never separate, and the remaining axes decide.
template <class T>
OCT_HD inline bool triBoxOverlap(Vec3T<T> centre, Vec3T<T> halfSize, Vec3T<T> a, Vec3T<T> b,
                                 Vec3T<T> c) {
    using namespace tribox_detail;
    Vec3T<T> v0 = a - centre, v1 = b - centre, v2 = c - centre;
    const Vec3T<T>& h = halfSize;
    // Axes 1-3: the box normals, i.e. the triangle's bounding box against the box.
    if (mn3(v0.x, v1.x, v2.x) > h.x || mx3(v0.x, v1.x, v2.x) < -h.x) return false;
    if (mn3(v0.y, v1.y, v2.y) > h.y || mx3(v0.y, v1.y, v2.y) < -h.y) return false;
    if (mn3(v0.z, v1.z, v2.z) > h.z || mx3(v0.z, v1.z, v2.z) < -h.z) return false;
    // Axes 4-12: box edge directions (unit axes) crossed with the triangle's edges.
    Vec3T<T> e[3] = {v1 - v0, v2 - v1, v0 - v2};
    const Vec3T<T> units[3] = {{T(1), T(0), T(0)}, {T(0), T(1), T(0)}, {T(0), T(0), T(1)}};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (separates(cross(units[i], e[j]), v0, v1, v2, h)) return false;
    // Axis 13: the triangle's normal (plane against box).
    return !separates(cross(e[0], e[1]), v0, v1, v2, h);
}

}  // namespace oct
