// The numeric range in which octrace's float32 geometry is correct: the kernel's watertight
// triangle test and sphere test (primitives.h), and Embree's robust-mode tests, which the
// ground truth uses. Inputs outside it are refused with a message, never traced: loading checks
// the scene (load_scene.cpp), the ray file reader the rays (core/io/ray_file.h), makeFrame the
// camera and light (core/render/frame.cpp). docs/ROBUSTNESS.md ("Numeric range") states it as
// a promise; tests/validation/numeric_range_test.cpp traces at its edges against the
// double-precision truth and tests/apps/robustness_cli_test.cpp checks the refusals.
//
// Why these numbers. Let B bound |vertex - ray origin| per component and let the direction's
// largest component be D (traceRayAt scales every ray's direction by an exact power of two so
// that D lies in [0.5, 1); camera and shadow rays are unit vectors, D >= 1/sqrt(3)).
//  - Too large: the kernel's scaled distance t * det = sum(u_i * a_kz / d_kz) reaches 24 B^3 / D
//    (edge functions u_i <= 8 B^2 after the shear), Embree's T = 2 dot(v0, Ng) reaches 48 B^3;
//    beyond FLT_MAX (3.4e38) both report t = +inf with a valid primitive (scenes of 1e13 did).
//    With coordinates within kMaxCoordinate and origins within kMaxRayOrigin, B <= 9e11 < 2^40,
//    so 48 B^3 <= 6.4e37: a factor 5 below FLT_MAX.
//  - Too small: products of coordinate differences leave float's normal range (1.2e-38): at a
//    scene extent of 1e-20 the scaled distance underflows and the CPU reported t = 0, and a
//    triangle of area 1e-60 has a zero determinant for every ray (it can never be hit). A
//    denormal scaled distance is off by up to 2^-149 / det in t; with the scene's extent E
//    >= kMinSceneExtent and twice every triangle's area >= kMinTriangleArea2 that stays below
//    2^-149 / (1e-28 * 1e-6 * cos) ~ 1.4e-11 / cos of E, far inside validation's 1e-5 (grazing
//    rays, cos <= 1e-3, are excused there anyway). Sphere radii >= kMinSphereRadius keep r^2
//    normal.
#pragma once

namespace oct {

// Every scene coordinate (a sphere's centre plus and minus its radius): |x| <= this.
constexpr double kMaxCoordinate = 1e11;
// Ray origins (octrace trace), the camera's eye and target and the light: |x| <= this. Eight
// times the scene bound leaves room for the default camera (within 5.75 x the bound).
constexpr double kMaxRayOrigin = 8e11;
// The scene's extent (the largest side of its bounding box) must be at least this.
constexpr double kMinSceneExtent = 1e-6;
// Twice each triangle's area (the length of the cross product of two edges, in double).
constexpr double kMinTriangleArea2 = 1e-28;
// Each sphere's radius.
constexpr double kMinSphereRadius = 1e-15;
// The largest |component| of a ray's direction (octrace trace): within [min, max]. Inside
// [2^-64, 2^64], so scaling the direction by a power of two (traceRayAt) and t back by its
// inverse stays exact and t stays a normal float for any hit within the coordinate range.
constexpr double kMinRayDirection = 1e-19;
constexpr double kMaxRayDirection = 1e19;

}  // namespace oct
