// Triangle/box overlap by the separating axis theorem, after Tomas Akenine-Möller, "Fast 3D
// Triangle-Box Overlap Testing", journal of graphics tools 6(1), 2001. Our own implementation:
// the 13 candidate axes are the 3 box normals, the triangle normal and the 9 cross products of
// box edges and triangle edges. Templated on the scalar so the validation module can run the
// same algorithm in double precision next to the float one the builder uses.
//
// Boundary convention: touching counts as overlap (every comparison is strict "> rad" for a
// separation), so a triangle lying in a face shared by two boxes belongs to both.
#pragma once

#include <cmath>

#include "core/platform.h"

namespace oct {

template <class T>
struct V3 {
    T x, y, z;
};

namespace tribox_detail {

template <class T>
OCT_HD inline V3<T> sub(V3<T> a, V3<T> b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class T>
OCT_HD inline V3<T> crs(V3<T> a, V3<T> b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T>
OCT_HD inline T dt(V3<T> a, V3<T> b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
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
OCT_HD inline bool separates(V3<T> a, V3<T> v0, V3<T> v1, V3<T> v2, V3<T> h) {
    T p0 = dt(a, v0), p1 = dt(a, v1), p2 = dt(a, v2);
    T rad = ab(a.x) * h.x + ab(a.y) * h.y + ab(a.z) * h.z;
    return mn3(p0, p1, p2) > rad || mx3(p0, p1, p2) < -rad;
}

}  // namespace tribox_detail

// Returns true when the closed triangle (a, b, c) and the closed box centre +- halfSize share a
// point. Works for degenerate triangles (a segment or a point): their zero normal and zero
// edge crosses give axes that never separate, and the remaining axes decide.
template <class T>
OCT_HD inline bool triBoxOverlap(V3<T> centre, V3<T> halfSize, V3<T> a, V3<T> b, V3<T> c) {
    using namespace tribox_detail;
    V3<T> v0 = sub(a, centre), v1 = sub(b, centre), v2 = sub(c, centre);
    const V3<T>& h = halfSize;
    // Axes 1-3: the box normals, i.e. the triangle's bounding box against the box.
    if (mn3(v0.x, v1.x, v2.x) > h.x || mx3(v0.x, v1.x, v2.x) < -h.x) return false;
    if (mn3(v0.y, v1.y, v2.y) > h.y || mx3(v0.y, v1.y, v2.y) < -h.y) return false;
    if (mn3(v0.z, v1.z, v2.z) > h.z || mx3(v0.z, v1.z, v2.z) < -h.z) return false;
    // Axes 4-12: box edge directions (unit axes) crossed with the triangle's edges.
    V3<T> e[3] = {sub(v1, v0), sub(v2, v1), sub(v0, v2)};
    const V3<T> units[3] = {{T(1), T(0), T(0)}, {T(0), T(1), T(0)}, {T(0), T(0), T(1)}};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (separates(crs(units[i], e[j]), v0, v1, v2, h)) return false;
    // Axis 13: the triangle's normal (plane against box).
    return !separates(crs(e[0], e[1]), v0, v1, v2, h);
}

}  // namespace oct
