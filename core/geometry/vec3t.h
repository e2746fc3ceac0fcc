// A three-component vector of any scalar: the double-precision geometry of the checks (the double
// truth, the exact overlap references, the ray sets' acceptance tests, the teaching overlays)
// and the scalar-templated triangle-box test. The kernel's float vector stays Vec3 (vec3.h).
// Every operation is written out component by component in a fixed order, so a result does not
// depend on which of them a caller uses (-ffp-contract=off keeps each product and sum rounded).
#pragma once

#include <cmath>

#include "core/geometry/vec3.h"
#include "core/platform.h"

namespace oct {

template <class T>
struct Vec3T {
    T x, y, z;
};

using DVec3 = Vec3T<double>;

template <class T>
OCT_HD inline Vec3T<T> operator+(Vec3T<T> a, Vec3T<T> b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T>
OCT_HD inline Vec3T<T> operator-(Vec3T<T> a, Vec3T<T> b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class T>
OCT_HD inline Vec3T<T> operator-(Vec3T<T> a) {
    return {-a.x, -a.y, -a.z};
}
template <class T>
OCT_HD inline Vec3T<T> operator*(Vec3T<T> a, T s) {
    return {a.x * s, a.y * s, a.z * s};
}
template <class T>
OCT_HD inline T dot(Vec3T<T> a, Vec3T<T> b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
OCT_HD inline Vec3T<T> cross(Vec3T<T> a, Vec3T<T> b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T>
OCT_HD inline T length(Vec3T<T> a) {
    using std::sqrt;
    return sqrt(dot(a, a));
}
template <class T>
OCT_HD inline Vec3T<T> normalize(Vec3T<T> a) {
    return a * (T(1) / length(a));
}

// Exact: every float is a double.
OCT_HD inline DVec3 toDouble(Vec3 v) { return {double(v.x), double(v.y), double(v.z)}; }

}  // namespace oct
