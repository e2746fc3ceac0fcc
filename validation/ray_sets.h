// Seeded ray sets for `octrace validate --rays N`: the cases image rays rarely meet.
//  - around: origins uniform on a sphere of 1.5 x the scene's bounding radius, aimed at points
//    uniform in the scene's box;
//  - inside: origins uniform in the octree's root cube, directions uniform on the sphere; one
//    in four has a finite tmax, uniform in [0, bounding radius];
//  - axis: origins uniform in the root cube, directions +-x, +-y or +-z; every other one has
//    one of its other two coordinates moved onto a node boundary plane of depth 1 to 3
//    (computed by the same float midpoints as childBox), so the ray runs inside a face shared
//    by two nodes.
// N is split as evenly as possible in that order. Random numbers are raw std::mt19937_64
// output (the standard fixes its sequence), so a seed gives the same rays everywhere.
#pragma once

#include <cstdint>
#include <vector>

#include "core/scene/scene.h"

namespace oct {

enum class RayKind : uint8_t { Around = 0, Inside = 1, Axis = 2 };
constexpr int kRayKindCount = 3;
const char* rayKindName(RayKind k);  // "around", "inside", "axis"

struct ValidationRays {
    std::vector<float> rays;    // N x 8: ox oy oz dx dy dz tmin tmax (RayBatchView, TRACE_FORMAT)
    std::vector<RayKind> kind;  // N
    uint64_t count() const { return kind.size(); }
};

ValidationRays makeValidationRays(const Scene& scene, uint64_t n, uint64_t seed);

}  // namespace oct
