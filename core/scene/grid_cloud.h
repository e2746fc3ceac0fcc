// The paper's synthetic point cloud (Barboza & Clua 2011): N spheres on a regular grid, one per
// cell, where a cell is exactly one leaf of the deepest octree level, so that no sphere lies in
// two leaves and every leaf holds at most one primitive.
//
// Rule, reproducible from (N, seed) on every platform:
//  - depth D = smallest D >= 1 with 8^D >= N; D > kGridCloudMaxDepth is refused;
//  - root box [0,1]^3, cell edge 2^-D; cell c in [0, 8^D) has integer coordinates
//    x = c mod 2^D, y = (c / 2^D) mod 2^D, z = c / 4^D;
//  - the N cells are the first N of a partial Fisher-Yates shuffle of 0 .. 8^D-1 driven by
//    std::mt19937_64(seed): step i swaps slot i with slot i + (engine() mod (8^D - i)). The raw
//    engine output is used (std::uniform_int_distribution is implementation-defined), and the
//    engine's output sequence is fixed by the C++ standard;
//  - sphere i sits at the centre of the i-th chosen cell with radius 0.4 * 2^-D, which leaves a
//    gap of 0.1 cell to every face of its cell.
#pragma once

#include <cstdint>
#include <vector>

#include "core/scene/scene.h"

namespace oct {

constexpr int kGridCloudMaxDepth = 10;         // 8^10 cells = 2^30, cell indices fit in uint32_t
constexpr uint64_t kGridCloudDefaultSeed = 1;  // used for the spec "grid:N" without a seed
constexpr float kGridCloudRadiusInCells = 0.4f;

// D for N points (see above). Throws SceneError for N = 0 or N > 8^kGridCloudMaxDepth.
int gridCloudDepth(uint32_t n);

// The N chosen cell indices in order of selection (the shuffle above), for depth `depth`.
std::vector<uint32_t> chooseGridCells(uint32_t n, int depth, uint64_t seed);

// The memory makeGridCloud holds at once for N points: the slot array of every cell (4 bytes
// each, up to 8 N of them), the chosen cells and the spheres.
uint64_t gridCloudBytes(uint32_t n);

// Scene with kind Spheres, name "grid:N:seed", report.format "grid", domain [0,1]^3 and
// gridDepth D. Throws SceneError for N = 0, too large an N, or one needing more memory than
// the machine has left (gridCloudBytes, core/system/resources.h: refused with the figure).
Scene makeGridCloud(uint32_t n, uint64_t seed);

}  // namespace oct
