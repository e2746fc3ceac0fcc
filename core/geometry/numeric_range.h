// The numeric range in which octrace's float32 geometry (the kernel's triangle and sphere
// tests, and Embree's robust ones, the ground truth) is correct. Inputs outside it are refused,
// never traced: by loading (the scene), the ray file reader (the rays) and makeFrame (camera
// and light). The derivation of each bound and its measurements: docs/ROBUSTNESS.md, "Numeric
// range".
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
