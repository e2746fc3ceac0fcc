#include "core/scene/grid_cloud.h"

#include <new>
#include <numeric>
#include <random>
#include <string>
#include <utility>

#include "core/system/resources.h"

namespace oct {

int gridCloudDepth(uint32_t n) {
    if (n == 0)
        throw SceneError("grid:0: a grid cloud needs at least one point; use grid:N with N >= 1");
    int depth = 1;
    while ((uint64_t{1} << (3 * depth)) < n) ++depth;
    if (depth > kGridCloudMaxDepth)
        throw SceneError("grid:" + std::to_string(n) + ": needs grid depth " +
                         std::to_string(depth) + ", more than the maximum " +
                         std::to_string(kGridCloudMaxDepth) + "; use at most " +
                         std::to_string(uint64_t{1} << (3 * kGridCloudMaxDepth)) + " points");
    return depth;
}

std::vector<uint32_t> chooseGridCells(uint32_t n, int depth, uint64_t seed) {
    // A dense slot array is at most 8x the number of points (D is minimal, so 8^(D-1) < N),
    // i.e. 32 bytes a point next to the 16-byte spheres: simpler than a sparse shuffle.
    const uint64_t cellCount = uint64_t{1} << (3 * depth);
    std::vector<uint32_t> slots(cellCount);
    std::iota(slots.begin(), slots.end(), 0u);
    std::mt19937_64 engine(seed);
    std::vector<uint32_t> chosen(n);
    for (uint64_t i = 0; i < n; ++i) {
        uint64_t j = i + engine() % (cellCount - i);
        std::swap(slots[i], slots[j]);
        chosen[i] = slots[i];
    }
    return chosen;
}

namespace {

Sphere cellSphere(uint32_t cell, int depth) {
    const uint32_t mask = (1u << depth) - 1u;
    const double edge = 1.0 / double(1u << depth);
    auto centre = [&](uint32_t i) { return float((double(i) + 0.5) * edge); };
    Sphere s;
    s.center = {centre(cell & mask), centre((cell >> depth) & mask), centre(cell >> (2 * depth))};
    s.radius = float(double(kGridCloudRadiusInCells) * edge);
    return s;
}

}  // namespace

uint64_t gridCloudBytes(uint32_t n) {
    const uint64_t cells = uint64_t{1} << (3 * gridCloudDepth(n));
    return cells * sizeof(uint32_t) + uint64_t(n) * (sizeof(uint32_t) + sizeof(Sphere));
}

Scene makeGridCloud(uint32_t n, uint64_t seed) {
    const std::string spec = "grid:" + std::to_string(n) + ":" + std::to_string(seed);
    const int depth = gridCloudDepth(n);
    checkMemory<SceneError>(gridCloudBytes(n), spec, "use fewer points");
    Scene scene;
    scene.name = spec;
    scene.kind = PrimKind::Spheres;
    scene.report.format = "grid";
    scene.report.verticesRead = n;
    scene.domain = Aabb{{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}};
    scene.gridDepth = depth;
    try {
        std::vector<uint32_t> cells = chooseGridCells(n, depth, seed);
        scene.spheres.reserve(n);
        for (uint32_t c : cells) scene.spheres.push_back(cellSphere(c, depth));
    } catch (const std::bad_alloc&) {
        throw SceneError(spec + ": out of memory for " + std::to_string(n) + " spheres at depth " +
                         std::to_string(depth) + "; use fewer points");
    }
    return scene;
}

}  // namespace oct
