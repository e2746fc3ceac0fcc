// Three-float vector for kernel code. GLM is used on the host side (tests, reference checks);
// kernels use this 12-byte POD so the same struct is valid in CUDA and in host arrays without
// depending on GLM's CUDA configuration macros.
#pragma once

#include <cmath>
#include <cstring>

#include "core/platform.h"

namespace oct {

struct Vec3 {
    float x, y, z;  // 12 bytes, no padding

    // Component i (0, 1, 2) on a run-time index, e.g. the triangle test's permutation. Not
    // (&x)[i]: indexing past a member is undefined behaviour, and one compiler (clang for
    // WebAssembly) misread it on a temporary. On CUDA by selects, which keep the vector in
    // registers (an indexed array would live in local memory, the stack ptxas counts); on the
    // host by a copy of the three packed floats (standard layout, no padding), which compiles
    // to the one indexed load it was.
    OCT_HD float operator[](int i) const {
#if defined(__CUDA_ARCH__)
        return i == 0 ? x : (i == 1 ? y : z);
#else
        float f[3];
        memcpy(f, this, sizeof f);
        return f[i];
#endif
    }
    OCT_HD float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
};
static_assert(sizeof(Vec3) == 12, "Vec3 must be three packed floats");

// Compare-and-select min/max for the traversal's hot loops. Unlike fminf/fmaxf, which GCC calls
// in libm rather than inline (their NaN rules differ from minss/maxss), these compile to one
// instruction on both host and device. Callers guarantee non-NaN operands (the slab test never
// forms 0 * inf). fminf/fmaxf remain where their NaN rule is wanted and speed is not: clamping a
// colour to a byte (kernel.h toByte maps NaN to 0) and growing host-side boxes (vmin/vmax).
OCT_HD inline float minf(float a, float b) { return b < a ? b : a; }
OCT_HD inline float maxf(float a, float b) { return a < b ? b : a; }

OCT_HD inline Vec3 makeVec3(float s) { return {s, s, s}; }
OCT_HD inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
OCT_HD inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
OCT_HD inline Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
OCT_HD inline Vec3 operator*(Vec3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
OCT_HD inline Vec3 operator*(float s, Vec3 a) { return a * s; }
OCT_HD inline Vec3 operator*(Vec3 a, Vec3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
OCT_HD inline float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
OCT_HD inline Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
OCT_HD inline float length(Vec3 a) { return sqrtf(dot(a, a)); }
OCT_HD inline Vec3 normalize(Vec3 a) { return a * (1.0f / length(a)); }
OCT_HD inline Vec3 vmin(Vec3 a, Vec3 b) {
    return {fminf(a.x, b.x), fminf(a.y, b.y), fminf(a.z, b.z)};
}
OCT_HD inline Vec3 vmax(Vec3 a, Vec3 b) {
    return {fmaxf(a.x, b.x), fmaxf(a.y, b.y), fmaxf(a.z, b.z)};
}
OCT_HD inline bool isFinite(Vec3 a) {
    return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

}  // namespace oct
