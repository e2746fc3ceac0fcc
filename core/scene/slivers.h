// The watertightness scene of Vulkan's conformance tests (VK-GL-CTS, ray tracing
// watertightness): the unit square [0,1]^2 in the plane z = 0, cut by repeated interior splits
// into N triangles, many of them slivers, that meet at shared edges and vertices. Every ray
// aimed inside the square must hit it, so a tracer's cracks show without a reference (the
// slivers ray set, validation/rays/ray_sets.h; docs/CERTIFY.md).
//
// Rule, reproducible from (N, seed) on every platform (integer arithmetic only):
//  - vertices lie on the grid of step 2^-24 (integer coordinates 0 .. 2^24, exact as floats), so
//    neighbours share bit-identical endpoints and every orientation test is exact;
//  - start: corners 0 (0,0), 1 (1,0), 2 (1,1), 3 (0,1); triangles (0,1,2) and (0,2,3), all
//    triangles counter-clockwise seen from +z;
//  - a split draws from std::mt19937_64(seed), raw output only: triangle k = engine() mod count,
//    then a = kSliversMixLo + engine() mod (kSliversMixHi - kSliversMixLo + 1) and b the same
//    (fractions of 2^16, 0.01 .. 0.99); with (p, q, r) the triangle's corners, the point
//    s = (1 - b)((1 - a) p + a q) + b r, in fixed point, rounded to the grid (half up). When s
//    is not strictly inside (p, q, r) (a child of zero area, exactly), the whole draw is
//    repeated; else triangle k becomes (p, q, s) and (q, r, s), (r, p, s) are appended;
//  - N, the number of triangles, is 2 + 2 x splits: even, 2 .. kSliversMaxTriangles.
#pragma once

#include <cstdint>

#include "core/scene/scene.h"

namespace oct {

constexpr uint64_t kSliversMaxTriangles = uint64_t{1} << 22;  // 4,194,304: 144 MiB of triangles
constexpr uint64_t kSliversDefaultSeed = 1;  // used for the spec "slivers:N" without a seed
constexpr int kSliversGridBits = 24;         // vertices on the grid of step 2^-24
constexpr uint32_t kSliversMixLo = 655, kSliversMixHi = 65536 - 655;  // 0.01 .. 0.99 of 2^16

// Scene with name "slivers:N:SEED", report.format "slivers", sourceFace[i] = i. Throws
// SceneError for an odd N, N < 2 or N > kSliversMaxTriangles, or when memory runs out.
Scene makeSlivers(uint64_t n, uint64_t seed);

// A scene makeSlivers made (report.format "slivers"): the square's rays must all hit.
bool isSliversScene(const Scene& scene);

}  // namespace oct
